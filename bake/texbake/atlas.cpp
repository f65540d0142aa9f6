// bake_atlas_texture: the UV layout (bake/uv/uv_layout.h), the atlas bake and
// its padding (bake/engine/bake_atlas.h) behind the API's conventions.
#include <string>
#include <utility>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/atlas_samples.h"
#include "bake/atlas/dilate.h"
#include "bake/engine/bake_atlas.h"
#include "bake/texbake/run.h"
#include "bake/util/progress.h"
#include "bake/util/timing.h"
#include "bake/uv/uv_layout.h"

namespace texbake {

Status validate_options(const AtlasOptions& options) {
  const AtlasBakeOptions& o = options.bake;
  if (o.size < 1 || o.size > kMaxAtlasSize) {
    return make_error(ErrorCode::kInvalidArgument, "--size " + std::to_string(o.size) +
                                                       " is out of range (1 .. " +
                                                       std::to_string(kMaxAtlasSize) + ")");
  }
  if (o.samples < 1 || o.samples > kMaxAtlasSamples) {
    return make_error(ErrorCode::kInvalidArgument, "--samples " + std::to_string(o.samples) +
                                                       " is out of range for an atlas (1 .. " +
                                                       std::to_string(kMaxAtlasSamples) + ")");
  }
  if (Status s = check_padding(o.padding); !s) return s.error();
  return detail::check_shading_colors(o.shading);
}

namespace detail {

Status lay_out_atlas(const MeshData& mesh, const Proxy* proxy, const AtlasOptions& options,
                     Progress& progress, Atlas& atlas, MeshData* consumed) {
  const AtlasBakeOptions& bo = options.bake;
  auto t0 = Clock::now();
  progress.start("uv_layout", 1);
  if (progress.cancelled()) return cancelled_error();
  UvLayoutOptions lo;
  lo.uv = options.uv;
  lo.atlas_size = bo.size;
  // The padding the bake will dilate by (push-pull has no ring count: the
  // default's) sets the gutter.
  lo.padding = bo.padding >= 0 ? bo.padding : default_padding(bo.size);
  Expected<UvLayoutResult> layout = proxy ? lay_out_uvs(mesh, *proxy, lo) : lay_out_uvs(mesh, lo);
  if (!layout) return as_input(layout.error());
  atlas.uv = layout->stats;
  atlas.repeat_u = layout->repeat_u;
  atlas.stats.warnings = std::move(layout->warnings);
  switch (atlas.uv.used) {
    case UvLayout::kProxy:
      atlas.mesh = std::move(layout->mesh);
      break;
    case UvLayout::kGenerate:
      atlas.mesh =
          mesh_with_triangle_uvs(mesh, layout->generated.uvs, layout->generated.triangle_uvs);
      break;
    case UvLayout::kMesh:
    case UvLayout::kAuto:
      if (consumed) {
        atlas.mesh = std::move(*consumed);
      } else {
        atlas.mesh = mesh;
      }
      break;
  }
  if (consumed) *consumed = MeshData{};  // the input's memory, before the bake
  layout->generated = UvAtlas{};         // free the layout's tables before the bake
  progress.finish();
  if (progress.cancelled()) return cancelled_error();
  atlas.stats.timings.uv_layout = seconds_since(t0);
  return ok_status();
}

}  // namespace detail

namespace {

// bake_atlas_texture, consuming `mesh` when `consumed` is it (lay_out_atlas).
Expected<Atlas> atlas_texture(const MeshData& mesh, MeshData* consumed, const ImageView& image,
                              const Proxy& proxy, const AtlasOptions& options,
                              const RunOptions& run) {
  const auto start = Clock::now();
  if (Status s = validate_options(options); !s) return s.error();
  if (Status s = detail::check_image(image); !s) return s.error();
  if (Status s = check_uv_layout(mesh, options.uv); !s) return s.error();
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<Atlas>(run, [&]() -> Expected<Atlas> {
    const AtlasBakeOptions& bo = options.bake;
    Atlas atlas;
    const Counts input = detail::mesh_counts(mesh);  // `mesh` may be consumed below
    if (Status s = detail::lay_out_atlas(mesh, &proxy, options, progress, atlas, consumed); !s) {
      return s.error();
    }
    Timings& t = atlas.stats.timings;

    AtlasBakeOptions with_overlaps = bo;
    with_overlaps.resolve_overlaps = atlas.uv.overlap_texels > 0;
    Expected<AtlasBakeResult> baked =
        bake_atlas(atlas.mesh, image, proxy, with_overlaps, &progress);
    if (!baked) return detail::as_input(baked.error());
    if (progress.cancelled()) return cancelled_error();  // a false at the very end counts too
    atlas.image = std::move(baked->atlas);
    Counts& c = atlas.stats.counts;
    c = detail::bake_counts(input, baked->counts);
    c.texels = baked->counts.texels;
    c.border_samples = baked->counts.border_samples;
    c.padded = baked->counts.padded;
    if (Status s =
            detail::check_mapped(c.undefined, c.samples, "atlas samples", atlas.stats.warnings);
        !s) {
      return s.error();
    }
    t.rasterize = baked->timings.rasterize;
    t.scene_build = baked->timings.scene_build;
    t.bake = baked->timings.sample;
    t.fill = baked->timings.fill;
    t.pad = baked->timings.pad;
    t.total = seconds_since(start);
    return atlas;
  });
}

}  // namespace

Expected<Atlas> detail::image_atlas_texture(const MeshData& mesh, const ImageView& image,
                                            const Proxy& proxy, const AtlasOptions& options,
                                            const RunOptions& run) {
  return atlas_texture(mesh, nullptr, image, proxy, options, run);
}

Expected<Atlas> bake_atlas_texture(MeshData&& mesh, const ImageView& image, const Proxy& proxy,
                                   const AtlasOptions& options, const RunOptions& run) {
  Expected<Atlas> atlas = atlas_texture(mesh, &mesh, image, proxy, options, run);
  mesh = MeshData{};  // also when the call failed before the layout took it
  return atlas;
}

}  // namespace texbake
