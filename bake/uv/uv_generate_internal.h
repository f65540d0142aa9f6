// Internals of `--uv generate` (bake/uv/uv_generate.h): the types its stages
// share and each stage's entry points. Not a public API. One file per stage:
//   uv_charts.cpp    mesh geometry and adjacency; charts by normal cones
//   uv_cut.cpp       charts cut into topological disks, split until they flatten
//   uv_flatten.cpp   one disk flattened (LSCM on Eigen), checked, oriented
//   uv_pack.cpp      charts rasterised and packed into the atlas
//   uv_generate.cpp  validation, the stages in order, the scale search, output
// Every stage is deterministic: its result does not depend on the thread
// count of bake/util/parallel.h.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake::uv_detail {

inline constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

using texbake::Vec2;  // the one 2-D vector type (mapping/vec.h)

// Twice the signed area of triangle (a, b, c), positive when counter-clockwise.
inline double cross2(Vec2 a, Vec2 b, Vec2 c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// The mesh in double precision with per-triangle data and edge adjacency.
struct Geometry {
  const std::vector<std::array<uint32_t, 3>>* tris = nullptr;  // MeshData::triangles
  std::vector<Vec3> pos;
  std::vector<Vec3> normal;  // unit face normal (zero for a triangle degenerate in double)
  std::vector<double> area;
  std::vector<Vec3> centroid;
  // adj[3t+k]: corner-edge 3t'+k' across edge k of t (vertices v[k] -> v[k+1]),
  // or kNone when that edge is a border, non-manifold (not exactly two
  // triangles) or shared by two triangles of opposite winding.
  std::vector<uint32_t> adj;
};

// Border edges (i, j) of a welded piece in face winding order, as local
// vertex indices: every edge of a face that no other face of the piece shares
// across a welded (interior) edge.
using Border = std::vector<std::pair<uint32_t, uint32_t>>;

// One flattened chart: its triangles with a local vertex per welded corner.
struct FlatChart {
  std::vector<uint32_t> tris;                   // global triangle ids, ascending
  std::vector<std::array<uint32_t, 3>> corner;  // local vertex per corner (same order as tris)
  std::vector<Vec2> uv;                         // per local vertex, in 3D length units
  double area3d = 0;                            // summed 3D area of tris
};

// ---------------------------------------------------------------------------
// 1. Charts (uv_charts.cpp).

// Positions, normals, areas, centroids and adjacency of mesh (whose indices
// the caller has checked). g.tris points into mesh, which must outlive g.
Geometry build_geometry(const MeshData& mesh);

// Chart id per triangle (0 .. chart_count-1, set on return), numbered in
// order of each chart's smallest triangle. Charts are grown by normal-cone
// region growing (seeds in triangle order, a triangle joins when its normal
// is within max_angle_deg, in (0, 90), of the chart's area-weighted mean
// normal) only across g.adj edges; saw-toothed borders are then smoothed
// (within max_angle_deg + 15, at most 89 degrees) and charts below min_area
// are merged into the neighbour sharing the longest border with them.
std::vector<uint32_t> make_charts(const Geometry& g, double max_angle_deg, double min_area,
                                  uint32_t& chart_count);

// ---------------------------------------------------------------------------
// 2. Cutting (uv_cut.cpp).

// Flat charts covering every triangle exactly once, each a topological disk
// flattened by the stage below (UV area = 3D area, stretch at most
// max_stretch unless it is a single triangle) and oriented by orient_chart.
// Each chart c of `chart` is split into connected pieces over g.adj; a piece
// with holes is cut open along shortest paths joining its border loops, and
// a piece that is not a disk, does not flatten or exceeds 49152 triangles is
// halved by area and retried (a single triangle always succeeds). Order:
// chart by chart (ids ascending), the pieces of one chart in split order.
std::vector<FlatChart> cut_charts(const Geometry& g, const std::vector<uint32_t>& chart,
                                  uint32_t chart_count, double max_stretch);

// ---------------------------------------------------------------------------
// 3. Flattening (uv_flatten.cpp).

// Lays out a one-triangle chart isometrically (corner 0 at the origin,
// corner 1 on +x, corner 2 above).
void flatten_triangle(const Geometry& g, FlatChart& fc);

// Flattens a chart that the caller has checked to be a topological disk
// (connected, Euler characteristic 1, one border loop `border`) by
// least-squares conformal maps (Levy et al. 2002; a direct Eigen sparse
// solve), the two vertices farthest apart along the longer axis of the
// projection onto the chart's mean plane pinned. Returns true, with fc.uv
// scaled so that UV area = 3D area, when the solve succeeded, no triangle is
// flipped or squeezed below 1e-6 of its 3D area, the border does not cross
// itself and the chart's L2 stretch is at most max_stretch; false otherwise
// (fc.uv is then unspecified: the caller splits the chart).
bool flatten_chart(const Geometry& g, FlatChart& fc, const Border& border, double max_stretch);

// Sander et al. 2001: squared L2 stretch of triangle t (3D points g.pos[t[k]])
// mapped to UVs p1, p2, p3 (counter-clockwise, non-degenerate).
double triangle_l2_squared(const Geometry& g, const std::array<uint32_t, 3>& t, Vec2 p1, Vec2 p2,
                           Vec2 p3);

// Rotates a chart so that its minimum-area bounding rectangle (one side along
// a convex-hull edge, Freeman & Shapira 1975) is axis aligned, with its
// lower-left corner at the origin.
void orient_chart(FlatChart& fc);

// ---------------------------------------------------------------------------
// 4. Packing (uv_pack.cpp).

// Covered texels of a chart at one scale. The chart's UVs (in length units,
// lower-left at the origin) map to texel space as uv * scale + 0.5, so that
// the bitmap is [0, w) x [0, h). A texel is covered when its closed square,
// grown by 1e-2 texel (so that the float32 rounding of the final UVs never
// covers a texel the packer did not see), meets one of the chart's triangles.
struct ChartRaster {
  int w = 0, h = 0;
  std::vector<uint8_t> bits;  // row-major, row 0 at the bottom
  std::size_t covered = 0;    // set bits
};

ChartRaster rasterize_chart(const FlatChart& fc, double scale);

// A packed chart's lower-left texel and counter-clockwise quarter turns.
struct Placement {
  int x = 0, y = 0, rot = 0;
};

// Bottom-left-fill packing of rasterised charts, in `order` (largest first),
// into a strip `size` texels wide and at most `max_height` high: each chart
// takes, over four quarter turns and every column, the lowest position where
// each of its columns' covered span (from its lowest to its highest covered
// texel) fits between the occupied spans of the atlas column below it, so
// holes left under earlier charts are filled by later ones. Covered texels of two charts are more
// than `padding` texels apart (Chebyshev metric); the strip's edges need no gutter. Ties: lower top
// edge, then further left, then fewer turns. Fills placed (one per raster)
// and returns the height used (the highest top edge), or -1 when a chart
// does not fit below max_height.
int pack(const std::vector<ChartRaster>& rasters, const std::vector<uint32_t>& order, int size,
         int padding, int max_height, std::vector<Placement>& placed);

// Atlas texel coordinates of chart UV p (length units) at `scale`, for a
// chart rasterised as r and placed at pl: the continuous version of the
// raster's turn and offset, so that p lands on the texels r covered.
Vec2 placed_texel(const ChartRaster& r, const Placement& pl, double scale, Vec2 p);

}  // namespace texbake::uv_detail
