// `--uv generate` (SPEC section 4, issue #4): a new non-overlapping UV atlas
// for a triangle mesh.
//
// Pipeline (each stage deterministic: the output does not depend on the
// thread count of bake/util/parallel.h; one source file per stage, see
// uv_generate_internal.h):
//  1. Charts are grown over MeshData::triangles by normal-cone region growing:
//     a chart only crosses edges shared by exactly two consistently oriented
//     triangles, so non-manifold edges, non-manifold vertices and orientation
//     flips are chart borders. Saw-toothed borders are smoothed and charts
//     below 1/2000 of the surface are merged into a neighbour.
//  2. Every chart is cut into topological disks: holes are cut open along
//     shortest paths joining its border loops; other non-disks, and pieces
//     above 49152 triangles (to bound the solve), are halved.
//  3. Every disk is flattened by least-squares conformal maps (LSCM, Levy et
//     al. 2002; a direct Eigen sparse solve). A disk whose map flips a
//     triangle, whose border crosses itself, whose stretch exceeds
//     max_chart_stretch or whose solve fails is halved and goes back to 2 (a
//     single triangle always succeeds). Charts are then scaled so that UV
//     area equals 3D area (uniform texel density) and rotated to their
//     minimum-area bounding rectangle.
//  4. Charts are packed as rasterised shapes (conservative coverage at the
//     atlas size) by bottom-left fill over column spans, trying four quarter
//     turns, with at least `padding` empty texels between texels covered by
//     different charts (none at the atlas edge). The global scale is searched
//     from the height each pack needs in a strip of the atlas' width; the
//     largest scale whose pack fits the square is kept.
//
// Conventions: UVs are SPEC section 1 coordinates in [0, 1]; the atlas is
// atlas_size x atlas_size texels, texel (i, j) covering u in [i, i+1]/size and
// v in [j, j+1]/size (v = 0 the bottom row). A texel is "covered" by a chart
// when its closed square meets one of the chart's UV triangles.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mapping/error.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct UvGenerateOptions {
  int atlas_size = 2048;  // texels per side of the square atlas, 1 .. 16384
  int padding = 8;        // minimum empty texels between two charts (the gutter), >= 0
  // Normal-cone half angle of a chart, in degrees (0, 90): a triangle joins a
  // chart when its normal is within this angle of the chart's mean normal.
  double max_chart_angle_deg = 70.0;
  // A chart whose own area-weighted L2 stretch (Sander et al. 2001, normalised
  // so that an isometry gives 1) exceeds this after flattening is split; >= 1.
  double max_chart_stretch = 1.1;
};

struct UvAtlas {
  int atlas_size = 0;
  int padding = 0;
  // UV table and 3 UV indices per MeshData::triangles entry (same order).
  // Triangles of one chart share UVs along the chart's interior edges.
  std::vector<Float2> uvs;
  std::vector<std::array<uint32_t, 3>> triangle_uvs;
  std::vector<uint32_t> triangle_chart;  // chart id per triangle, 0 .. chart_count-1
  uint32_t chart_count = 0;
  // Texels covered by charts / all texels (conservative coverage, see above).
  double utilisation = 0.0;
  // Area-weighted L2 stretch of the whole atlas (Sander, Snyder, Gortler,
  // Hoppe 2001, "Texture mapping progressive meshes", section 3), normalised by
  // sqrt(total UV area / total 3D area) so that an isometry up to scale gives 1.
  double stretch_l2 = 0.0;
  double texels_per_unit = 0.0;  // atlas texels per unit of 3D length
};

// Builds the atlas for mesh.triangles (positions and triangles only are used).
// Errors (kInvalidArgument): atlas_size outside 1..16384, negative padding, an
// option out of range, no triangles, a vertex index out of range, a
// non-finite position; the packer cannot fit the charts (only for absurd
// padding versus size): kUnsupported.
Expected<UvAtlas> generate_uv_atlas(const MeshData& mesh, const UvGenerateOptions& options = {});

}  // namespace texbake
