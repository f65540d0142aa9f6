#include "bake/uv/uv_layout.h"

#include <algorithm>
#include <string>
#include <utility>

#include "bake/uv/uv_proxy.h"

namespace texbake {

const char* to_string(UvLayout layout) {
  switch (layout) {
    case UvLayout::kAuto:
      return "auto";
    case UvLayout::kMesh:
      return "mesh";
    case UvLayout::kGenerate:
      return "generate";
    case UvLayout::kProxy:
      return "proxy";
  }
  return "auto";
}

Status check_uv_layout(const MeshData& mesh, UvLayout layout) {
  if (layout == UvLayout::kMesh && !mesh.has_uvs()) {
    return make_error(
        ErrorCode::kInvalidArgument,
        "--uv mesh: the mesh has no UV coordinates (use --uv generate or --uv proxy)");
  }
  return ok_status();
}

namespace {

// The overlap figure and warning of --uv mesh and --uv proxy (check_mesh_uvs
// on the layout baked against).
void check_overlaps(const MeshUvCheck& check, const char* consequence, UvLayoutResult& result) {
  result.stats.overlap_texels = check.overlap_texels;
  if (check.overlap_texels > 0) {
    result.warnings.push_back(std::to_string(check.overlap_texels) +
                              " atlas texels are covered by overlapping UV triangles; " +
                              consequence);
  }
}

}  // namespace

namespace {

// proxy: null for a bake without one (kProxy is then refused).
Expected<UvLayoutResult> lay_out(const MeshData& mesh, const Proxy* proxy,
                                 const UvLayoutOptions& options) {
  if (Status s = check_uv_layout(mesh, options.uv); !s) return s.error();
  if (options.uv == UvLayout::kProxy && !proxy) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--uv proxy needs a proxy, and this bake has none (use --uv generate or "
                      "--uv mesh)");
  }
  UvLayoutResult result;
  UvLayout used = options.uv;
  if (used == UvLayout::kAuto) used = mesh.has_uvs() ? UvLayout::kMesh : UvLayout::kGenerate;
  result.stats.used = used;
  switch (used) {
    case UvLayout::kMesh: {
      const MeshUvCheck check = check_mesh_uvs(mesh, options.atlas_size);
      result.stats.corners_outside = check.corners_outside;
      if (check.corners_outside > 0) {
        result.warnings.push_back(std::to_string(check.corners_outside) +
                                  " UV corners lie outside [0, 1]; their texels are not baked");
      }
      check_overlaps(check, "overlapping parts share colours", result);
      break;
    }
    case UvLayout::kProxy: {
      Expected<ProxyUvLayout> cut = proxy_uv_layout(mesh, *proxy);
      if (!cut) return cut.error();
      result.stats.cut_triangles = cut->stats.cut_triangles;
      if (cut->stats.wide_triangles > 0) {
        result.warnings.push_back(std::to_string(cut->stats.wide_triangles) +
                                  " triangles contain a pole of the proxy and are stretched "
                                  "across the atlas");
      }
      // Surfaces behind one another as seen from the proxy share (u, v).
      check_overlaps(check_mesh_uvs(cut->mesh, options.atlas_size),
                     "surfaces behind one another share (u, v) (the mesh is not star-shaped "
                     "as seen from the proxy); the visible ones colour the shared texels",
                     result);
      result.mesh = std::move(cut->mesh);
      result.repeat_u = wrap_u(*proxy) == WrapMode::kRepeat;
      break;
    }
    case UvLayout::kGenerate:
    case UvLayout::kAuto: {
      UvGenerateOptions go;
      go.atlas_size = options.atlas_size;
      go.padding = std::max(options.padding, kMinGutter);
      Expected<UvAtlas> atlas = generate_uv_atlas(mesh, go);
      if (!atlas) return atlas.error();
      result.stats.charts = atlas->chart_count;
      result.stats.utilisation = atlas->utilisation;
      result.stats.stretch_l2 = atlas->stretch_l2;
      result.generated = std::move(*atlas);
      break;
    }
  }
  return result;
}

}  // namespace

Expected<UvLayoutResult> lay_out_uvs(const MeshData& mesh, const Proxy& proxy,
                                     const UvLayoutOptions& options) {
  return lay_out(mesh, &proxy, options);
}

Expected<UvLayoutResult> lay_out_uvs(const MeshData& mesh, const UvLayoutOptions& options) {
  return lay_out(mesh, nullptr, options);
}

}  // namespace texbake
