// A MIP pyramid of an ImageView and the elliptical weighted average (EWA)
// lookup over it (issue #16 item 2, SPEC section 13): the footprint filter
// behind --filter ewa. Standard C++ only.
//
// Pyramid: level 0 is the image itself (viewed, not copied); level i + 1 is
// level i reduced by 2 in each dimension (floor, at least 1) by an exact box
// (area) filter: each output texel is the area-weighted mean of the input
// texels its rectangle covers (2 x 2 for even sizes, fractional weights for
// odd ones), down to 1 x 1. An image with its own MIP levels (ImageView::
// mip_levels: a MIP-mapped file) is not reduced: its levels are viewed as
// they are (whatever filter made them), so a bake reads only the texels
// of the levels its footprints reach. It filters the stored values of the view it is
// given, so, built from the working image (bake/shade/shade.h working_image),
// it averages in the same encoding as the bilinear lookup interpolates: the
// stored (sRGB-encoded) values, or linear light with --linear or for a
// linear image. A box over a whole period needs no wrap, so the levels are
// the same for every wrap mode.
//
// Lookup (sample_ewa), as pbrt-v4's MIPMap::EWA (Pharr, Jakob, Humphreys,
// Physically Based Rendering, 4th ed., 10.4.4; Heckbert 1989):
//  - The footprint is two vectors in (u, v) (the differentials of a sample:
//    d(u, v) along two surface directions), taken to level-0 pixels
//    (x = u W, y = -v H). The longer is the major axis.
//  - Magnification: when the major axis is at most one texel the result is
//    sample_bilinear() on level 0, bit for bit (the bilinear lookup already
//    covers such a footprint). This departs from pbrt-v4, which runs its
//    Gaussian at level 0 there (blurring a magnified image by a texel).
//  - Otherwise the axes are capped at 2 max(W, H) texels (a footprint wider
//    than the image averages all of it anyway) and the eccentricity is
//    clamped: a minor axis shorter than major / max_anisotropy is lengthened
//    to it. The level is lod = max(0, log2(minor axis in level-0 texels));
//    the result is the linear blend of the EWA at floor(lod) and the next
//    level (only the top one past the pyramid's end).
//  - EWA at one level: the ellipse of the two axes, widened by one texel in
//    each direction (pbrt's "+1", the reconstruction filter, so at least one
//    texel is always inside), each texel centre inside weighted by the
//    Gaussian exp(-2 r^2) - exp(-2) of its elliptical radius r (a 128-entry
//    table, as pbrt's MIPFilterLUT), the weighted mean in double.
//  - Texels outside the level follow wrap_u / wrap_v as in sample_bilinear:
//    kRepeat is periodic (a footprint straddling the u seam averages both
//    sides), kClamp the edge texel.
//  - Whole rows (periodic u only): a footprint whose ellipse is as wide in u
//    as the period (near a sphere's pole, a cone's apex, a disk's centre)
//    covers every column, and the eccentricity clamp would blur it in v by
//    an eighth of its width (a quarter of a 2:1 map's height at the pole).
//    Such a lookup is instead the 1D Gaussian average (the same weights,
//    the same one-texel widening) of the level's row means over the
//    ellipse's v extent, at the level where that extent is one texel:
//    neither smeared in v nor pinched in u. Between a half and a whole
//    period of width the two results are blended linearly, so the filter
//    changes continuously towards the pole.
// A coordinate far outside a clamped axis counts as just past the widest
// footprint's reach (every texel the edge's); a periodic one is taken
// modulo 1 (a whole-period shift, so the same result).
// A constant image gives that constant exactly (the weights are normalised
// in double, and the result rounds back to the same float). No allocation
// or virtual call (except once per row, the first time a whole-rows lookup
// needs that row's mean: MipPyramid::row_mean); a pure function of its
// arguments.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <mutex>
#include <vector>

#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mapping/vec.h"

namespace texbake {

// Runs body(begin, end) over [0, count) in chunks, possibly in parallel
// (the bake passes its thread pool; mapping/ itself stays standard C++).
using RowRunner = std::function<void(std::size_t count,
                                     const std::function<void(std::size_t, std::size_t)>& body)>;

class MipPyramid {
 public:
  MipPyramid() = default;
  // Precondition: base has at least 1 x 1 pixel and stays alive (level 0
  // views it, and its mip_levels when it has them). for_rows (empty:
  // serial) runs the rows of each level it reduces; every row is computed
  // alone, so the pyramid does not depend on how it splits them.
  explicit MipPyramid(const ImageView& base, const RowRunner& for_rows = {});
  MipPyramid(MipPyramid&&) = default;
  MipPyramid& operator=(MipPyramid&&) = default;
  MipPyramid(const MipPyramid&) = delete;
  MipPyramid& operator=(const MipPyramid&) = delete;

  int levels() const { return static_cast<int>(views_.size()); }
  // Level i's pixels (same color_space as the base). 0 <= i < levels().
  const ImageView& level(int i) const { return views_[static_cast<std::size_t>(i)]; }
  // Whether the levels above 0 are the image's own (ImageView::mip_levels).
  bool given_levels() const { return owned_.empty() && views_.size() > 1; }
  // The mean of row y of level i (4 channels, double). Each row's mean is
  // computed when first asked for, by the asking thread (others asking for
  // it wait): only footprints as wide as the period use them, at the rows
  // near a pole, so a bake never reads a whole level for them.
  const double* row_mean(int i, int y) const {
    RowMeans& r = *row_means_[static_cast<std::size_t>(i)];
    std::call_once(r.once[y], [this, i, y] { compute_row_mean(i, y); });
    return &r.means[static_cast<std::size_t>(y) * 4];
  }
  // The bytes the levels above 0 and the row means hold (level 0, and
  // given levels, are the caller's).
  std::size_t owned_bytes() const;

 private:
  struct RowMeans {
    std::unique_ptr<std::once_flag[]> once;  // height
    std::vector<double> means;               // height * 4
  };
  void compute_row_mean(int i, int y) const;

  std::vector<std::vector<float>> owned_;             // levels 1 .. (when reduced here)
  std::vector<ImageView> views_;                      // levels 0 ..
  std::vector<std::unique_ptr<RowMeans>> row_means_;  // levels 0 ..
};

// A lookup's footprint: two vectors in (u, v) units (each (du, dv)).
struct UvFootprint {
  Vec2 a, b;
};

inline constexpr double kDefaultMaxAnisotropy = 8;  // pbrt-v4's default

// The EWA lookup described above. Precondition: mip has at least one level.
// Non-finite footprint components count as the cap (the widest footprint).
Rgba sample_ewa(const MipPyramid& mip, UV uv, UvFootprint footprint, WrapMode wrap_u,
                WrapMode wrap_v, double max_anisotropy = kDefaultMaxAnisotropy);

}  // namespace texbake
