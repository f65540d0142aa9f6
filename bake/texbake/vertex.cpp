// bake_vertex_colors: bake/engine/bake_vertex.h behind the API's conventions.
#include <utility>

#include "bake/engine/bake_vertex.h"
#include "bake/texbake/run.h"
#include "bake/util/progress.h"
#include "bake/util/timing.h"

namespace texbake {

namespace {

// `release` is called once nothing reads `image` any more (between the
// sampling and the fill's solve).
template <class Release>
Expected<VertexColors> bake(const MeshData& mesh, const ImageView& image, const Proxy& proxy,
                            const VertexBakeOptions& options, const RunOptions& run,
                            const EmbreeScene* scene, Release&& release) {
  const auto start = Clock::now();
  if (Status s = validate_options(options); !s) return s.error();
  if (Status s = detail::check_image(image); !s) return s.error();
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<VertexColors>(run, [&]() -> Expected<VertexColors> {
    Expected<VertexBakeStage> sampled =
        bake_vertex_sample(mesh, image, proxy, options, &progress, scene);
    if (!sampled) return detail::as_input(sampled.error());
    if (progress.cancelled()) return cancelled_error();
    release();
    progress.start("fill", 1);
    Expected<VertexBakeResult> baked = bake_vertex_finish(mesh, std::move(sampled).value());
    if (!baked) return detail::as_input(baked.error());
    progress.finish();
    if (progress.cancelled()) return cancelled_error();

    VertexColors out;
    out.colors = std::move(baked->colors);
    Counts& c = out.stats.counts;
    c = detail::bake_counts(detail::mesh_counts(mesh), baked->counts);
    c.filled = baked->counts.filled;
    c.unfilled = baked->counts.unfilled;
    if (Status s = detail::check_mapped(c.undefined, c.vertices, "vertices", out.stats.warnings);
        !s) {
      return s.error();
    }
    Timings& t = out.stats.timings;
    t.scene_build = baked->timings.scene_build;
    t.bake = baked->timings.bake;
    t.fill = baked->timings.fill;
    t.total = seconds_since(start);
    return out;
  });
}

}  // namespace

Status validate_options(const VertexBakeOptions& options) {
  if (options.filter == VertexFilter::kArea) {
    if (Status s = check_range("--samples", options.samples, 1, kMaxVertexSamples); !s) return s;
  }
  return detail::check_shading_colors(options);
}

Expected<VertexColors> detail::image_vertex_colors(const MeshData& mesh, const ImageView& image,
                                                   const Proxy& proxy,
                                                   const VertexBakeOptions& options,
                                                   const RunOptions& run) {
  return bake(mesh, image, proxy, options, run, nullptr, [] {});
}

Expected<VertexColors> bake_vertex_colors(const MeshData& mesh, Image&& image, const Proxy& proxy,
                                          const VertexBakeOptions& options, const RunOptions& run) {
  Image owned = std::move(image);
  return bake(mesh, owned.view(), proxy, options, run, nullptr, [&] { owned = Image{}; });
}

Expected<VertexColors> detail::bake_vertex_colors_on(const MeshData& mesh, const ImageView& image,
                                                     Image* owned, const Proxy& proxy,
                                                     const VertexBakeOptions& options,
                                                     const RunOptions& run,
                                                     const EmbreeScene* scene) {
  return bake(mesh, image, proxy, options, run, scene, [&] {
    if (owned) *owned = Image{};
  });
}

}  // namespace texbake
