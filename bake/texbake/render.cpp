// render_mesh: the Embree scene and bake/render/render_preview.h behind the
// API's conventions.
#include <utility>

#include "bake/render/render_preview.h"
#include "bake/texbake/run.h"
#include "bake/trace/embree_scene.h"
#include "bake/util/progress.h"
#include "bake/util/timing.h"
#include "mapping/tiled_image.h"

namespace texbake {

Expected<Rendered> render_mesh(const MeshData& mesh, const ColorSource& source,
                               const RenderOptions& options, const RunOptions& run) {
  const auto start = Clock::now();
  if (Status s = validate_options(options); !s) return s.error();
  if (Status s = validate_color_source(mesh, source); !s) return s.error();
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<Rendered>(run, [&]() -> Expected<Rendered> {
    Rendered out;
    auto t0 = Clock::now();
    Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kMedium);
    if (!scene) return scene.error();
    out.stats.timings.scene_build = seconds_since(t0);
    t0 = Clock::now();
    // Its errors are the options' (kInvalidArgument: usage) or kCancelled.
    Expected<RenderImage> image =
        render_preview(mesh, *scene, source, options, &out.rays, &progress);
    if (!image) return image.error();
    if (progress.cancelled()) return cancelled_error();  // a false at the very end counts too
    // A projected image read through the cache (--cache-mb): a failed read is the file's error.
    const ImageView* projected = nullptr;
    if (const auto* p = std::get_if<ProjectionSource>(&source)) projected = &p->texture;
    if (const auto* c = std::get_if<CameraProjectionSource>(&source)) projected = &c->texture;
    if (projected) {
      if (Status s = check_texels_read(*projected); !s) return s.error();
    }
    out.image = std::move(*image);
    out.stats.counts = detail::mesh_counts(mesh);
    out.stats.timings.render = seconds_since(t0);
    out.stats.timings.total = seconds_since(start);
    return out;
  });
}

}  // namespace texbake
