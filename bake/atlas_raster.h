// Rasterisation of a mesh's UV layout into an atlas: which texels to bake and,
// for each, its supersamples with the triangle under them (SPEC section 4).
//
// Coverage is conservative: a texel is covered when a bilinear lookup
// (SPEC section 1: x = u*N - 0.5, y = (1 - v)*N - 0.5, texels floor(x),
// floor(x)+1 by floor(y), floor(y)+1) from some point inside some triangle
// reads it. In the texel-centre grid this is the triangle dilated by one
// texel in the max norm: texel (i, j) is covered iff the triangle meets the
// square [i-1, i+1] x [j-1, j+1]. Texels outside [0, N)^2 are dropped (UVs
// outside [0, 1] are the layout's problem, see uv_proxy.h and the --uv mesh
// warnings).
//
// Samples: each covered texel gets `samples` points in a fixed stratified
// pattern inside the texel (sample_offset()). A sample takes the lowest-index
// triangle that contains it; a sample inside no triangle (a texel on a chart's
// border) takes the nearest point of the nearest candidate triangle (those
// whose dilated footprint covers the texel; ties: lowest index), so border
// texels continue the surface instead of staying black.
//
// Output is structure-of-arrays, texels in ascending index order (row-major,
// top row first, like the image), and does not depend on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapping/error.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

inline constexpr int kMaxAtlasSize = 16384;  // SPEC section 4 / issue #4
inline constexpr int kMaxAtlasSamples = 256;

struct AtlasRasterOptions {
  int size = 2048;  // atlas width and height in texels, 1 .. kMaxAtlasSize
  int samples = 4;  // supersamples per covered texel, 1 .. kMaxAtlasSamples
};

struct AtlasRaster {
  int size = 0;
  int samples_per_texel = 0;
  // Covered texels, ascending, as y * size + x (y = 0 the top row).
  std::vector<uint32_t> texels;
  // Per sample; sample s of covered texel k is entry k * samples_per_texel + s.
  std::vector<uint32_t> sample_triangle;  // index into MeshData::triangles
  std::vector<float> sample_b1;           // barycentric weight of the triangle's 2nd corner
  std::vector<float> sample_b2;           // ... of its 3rd corner; the 1st gets 1 - b1 - b2
  std::size_t border_samples = 0;         // samples inside no triangle (clamped onto one)

  std::size_t sample_count() const { return sample_triangle.size(); }
};

// Offset of sample s (of n) from its texel's centre, in texels, each
// coordinate in (-0.5, 0.5). n == 1: the centre. n == k*k: the centres of a
// k x k grid of sub-cells. Otherwise a Hammersley set (x = (s + 0.5) / n,
// y = base-2 radical inverse of s, shifted by 0.5 / n), which is stratified in
// x and well spread in y.
struct SampleOffset {
  double dx = 0, dy = 0;
};
SampleOffset sample_offset(int s, int n);

// The per-corner UV of triangle t's corner k (0..2):
// mesh.uvs[mesh.corner_uv[mesh.triangle_corners[t][k]]].
inline Float2 triangle_uv(const MeshData& mesh, std::size_t t, int k) {
  return mesh.uvs[mesh.corner_uv[mesh.triangle_corners[t][k]]];
}

// Rasterises mesh.triangles through their per-corner UVs.
// Errors: kInvalidArgument for a size or sample count out of range or a mesh
// without UVs; kParse for a non-finite UV or a UV index out of range.
Expected<AtlasRaster> rasterize_atlas(const MeshData& mesh, const AtlasRasterOptions& options);

// One byte per texel (size * size, row-major): 1 where raster covers a texel.
std::vector<uint8_t> coverage_mask(const AtlasRaster& raster);

}  // namespace texbake
