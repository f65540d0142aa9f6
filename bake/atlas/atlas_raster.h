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
// triangle that contains it (the others are listed with
// AtlasRasterOptions::overlap_candidates); a sample inside no triangle (a texel on a chart's
// border) takes the nearest point of the nearest candidate triangle (those
// whose dilated footprint covers the texel; ties: lowest index), so border
// texels continue the surface instead of staying black.
//
// Output is structure-of-arrays, texels in ascending index order (row-major,
// top row first, like the image), and does not depend on the thread count.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "mapping/error.h"
#include "mapping/vec.h"
#include "mesh_io/image_io.h"  // kMaxAtlasSize
#include "mesh_io/mesh_data.h"

namespace texbake {

inline constexpr int kMaxAtlasSamples = 256;

struct AtlasRasterOptions {
  int size = 2048;  // atlas width and height in texels, 1 .. kMaxAtlasSize
  int samples = 4;  // supersamples per covered texel, 1 .. kMaxAtlasSamples
  // Also list, for each sample inside two or more triangles (an overlapping
  // layout: --uv proxy on a non-star-shaped mesh, --uv mesh with shared UVs),
  // the further triangles that contain it (AtlasRaster::alt_*), so that the
  // bake can choose the visible one. Off: the scan stops at the first.
  bool overlap_candidates = false;
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
  // With AtlasRasterOptions::overlap_candidates: entry a says that sample
  // alt_sample[a] (an index into the per-sample arrays; ascending, and for
  // one sample its triangles ascending) lies also inside triangle
  // alt_triangle[a] (index > sample_triangle's), at barycentrics alt_b1[a],
  // alt_b2[a]. Empty otherwise.
  std::vector<uint32_t> alt_sample;
  std::vector<uint32_t> alt_triangle;
  std::vector<float> alt_b1, alt_b2;

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

// Banded rasterisation, for bakes that stream over the atlas instead of
// holding every sample at once (bake_atlas): the validated pixel-space
// triangles binned into bands of kAtlasBandRows rows. Band b covers rows
// [b * kAtlasBandRows, min(size, (b + 1) * kAtlasBandRows)); rasterising it
// gives exactly the texels (ascending) and samples that rasterize_atlas gives
// for those rows, so the concatenation of all bands in order is
// rasterize_atlas's result (rasterize_atlas is implemented that way).
inline constexpr int kAtlasBandRows = 16;

// Per-thread working memory of AtlasBands::rasterize (reused across bands, so
// a stream of bands allocates only while the buffers grow).
struct AtlasBandScratch {
  std::vector<uint32_t> pair_texel, pair_tri, count, cand, fill;
};

class AtlasBands {
 public:
  // Errors: those of rasterize_atlas.
  static Expected<AtlasBands> prepare(const MeshData& mesh, const AtlasRasterOptions& options);
  // The errors prepare would give, without its tables (one pass over the
  // corners): a bake can check its input before the long stages that come
  // before the bands. With `covers`: whether the bands will hold any
  // triangle (!empty()), i.e. whether some triangle reaches the atlas' rows.
  static Status check(const MeshData& mesh, const AtlasRasterOptions& options,
                      bool* covers = nullptr);

  int size() const { return size_; }
  int samples_per_texel() const { return samples_; }
  std::size_t band_count() const { return band_start_.size() - 1; }
  // Rows of band `band` (kAtlasBandRows, fewer for the last).
  int band_rows(std::size_t band) const {
    const int y0 = static_cast<int>(band) * kAtlasBandRows;
    return std::min(kAtlasBandRows, size_ - y0);
  }
  // True if no triangle reaches a row of the atlas (nothing to bake).
  bool empty() const { return band_tris_.empty(); }

  // Rasterises band `band` into `out` (cleared first; size and
  // samples_per_texel set; texel indices are whole-atlas indices y * size + x).
  // Thread-safe for distinct out / scratch.
  void rasterize(std::size_t band, AtlasRaster& out, AtlasBandScratch& scratch) const;

 private:
  int size_ = 0;
  int samples_ = 0;
  bool overlaps_ = false;                    // AtlasRasterOptions::overlap_candidates
  std::vector<std::array<PixelPos, 3>> px_;  // corners in continuous pixel coordinates
  std::vector<int> row_lo_, row_hi_;         // dilated row range per triangle (lo > hi: none)
  std::vector<uint32_t> band_start_;         // CSR over band_tris_
  std::vector<uint32_t> band_tris_;          // triangles per band, ascending
  std::vector<SampleOffset> offsets_;
};

// One byte per texel (size * size, row-major): 1 where raster covers a texel.
std::vector<uint8_t> coverage_mask(const AtlasRaster& raster);

}  // namespace texbake
