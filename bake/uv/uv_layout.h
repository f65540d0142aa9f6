// The UV layout of an atlas bake (SPEC section 4, `--uv`): which layout a
// bake uses, with its checks, warnings and the gutter rule.
//
//  - kAuto resolves to kMesh when the mesh has UVs, else kGenerate.
//  - kMesh bakes against the mesh's own per-corner UVs after check_mesh_uvs
//    (bake/uv/uv_proxy.h): corners outside [0, 1] and texels covered by
//    overlapping UV triangles are counted and each gives a warning.
//  - kProxy cuts the mesh at the proxy's seam (proxy_uv_layout); triangles
//    still spanning more than half the u range give a warning, and so do
//    texels covered by overlapping UV triangles (counted as for kMesh, by
//    check_mesh_uvs on the cut mesh): a mesh that is not star-shaped as seen
//    from the proxy (its centre, axis or plane) has surfaces behind one
//    another at the same (u, v); the bake gives such texels the visible
//    surface's colour (AtlasBakeOptions::resolve_overlaps). The layout is
//    periodic in u when the proxy's u wraps.
//  - kGenerate packs new charts (generate_uv_atlas) with a gutter of at
//    least kMinGutter texels whatever the padding: each chart's conservative
//    coverage reaches one texel beyond the packer's texel squares, and two
//    charts must never share a texel.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bake/uv/uv_generate.h"
#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

enum class UvLayout {
  kAuto,      // the mesh's own UVs if it has any, else kGenerate
  kMesh,      // the mesh's own per-corner UVs (checked: outside [0,1], overlaps)
  kGenerate,  // new non-overlapping charts (bake/uv/uv_generate.h)
  kProxy,     // the proxy's (u, v), cut at its seam (bake/uv/uv_proxy.h)
};
const char* to_string(UvLayout layout);  // "auto", "mesh", "generate", "proxy"

// The smallest gutter between generated charts, in texels (see above).
inline constexpr int kMinGutter = 2;

// What the UV layout stage found (the report's "uv_check" / chart figures).
struct UvLayoutStats {
  UvLayout used = UvLayout::kMesh;  // kAuto resolved
  std::size_t corners_outside = 0;  // kMesh
  std::size_t overlap_texels = 0;   // kMesh, kProxy
  std::size_t cut_triangles = 0;    // kProxy
  std::size_t charts = 0;           // kGenerate
  double utilisation = 0;           // kGenerate: covered / all texels
  double stretch_l2 = 0;            // kGenerate
};

struct UvLayoutOptions {
  UvLayout uv = UvLayout::kAuto;
  int atlas_size = 2048;  // texels per side
  int padding = 8;        // texels of dilation the bake adds (>= 0); the gutter is
                          // max(padding, kMinGutter)
};

struct UvLayoutResult {
  UvLayoutStats stats;
  std::vector<std::string> warnings;  // e.g. "12 UV corners lie outside [0, 1] ..."
  bool repeat_u = false;              // the layout is periodic in u
  // The mesh to bake against. kMesh: empty (the input itself); kProxy: the
  // cut mesh; kGenerate: empty, the charts are in `generated` (per triangle
  // of the input; mesh_with_triangle_uvs of bake/atlas/atlas_common.h makes
  // the mesh).
  MeshData mesh;
  UvAtlas generated;
};

// kInvalidArgument for kMesh on a mesh without UVs ("--uv mesh: the mesh has
// no UV coordinates (use --uv generate or --uv proxy)"), else ok.
Status check_uv_layout(const MeshData& mesh, UvLayout layout);

// Lays out `mesh`'s UVs as options.uv says (see the file comment).
// Errors: check_uv_layout's, the errors of proxy_uv_layout and
// generate_uv_atlas (as they give them).
Expected<UvLayoutResult> lay_out_uvs(const MeshData& mesh, const Proxy& proxy,
                                     const UvLayoutOptions& options);

// The same for a bake without a proxy (photographs: bake/engine/photo_atlas.h):
// kMesh, kGenerate and kAuto as above; kProxy is kInvalidArgument ("--uv
// proxy needs a proxy, and this bake has none ...").
Expected<UvLayoutResult> lay_out_uvs(const MeshData& mesh, const UvLayoutOptions& options);

}  // namespace texbake
