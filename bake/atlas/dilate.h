// Atlas padding (SPEC section 4, issue #11 item 4): grow the baked charts
// into the unbaked gutter so that mipmapping and filtering renderers never
// blend in the background.
//
// Images here are RGBA float, width * height * 4 values, row-major (the
// layout of ImageView). `baked` has one byte per texel: non-zero = holds a
// baked colour. Baked texels are never changed by either function; all four
// channels are treated alike (except push_pull_fill's FillAlpha::kTransparent).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace texbake {

// The default padding of an atlas of `size` texels: 8 texels at 2048, scaled
// in proportion to the size, rounded to nearest, at least 1
// (max(1, round(8 * size / 2048)): 4 at 1024, 16 at 4096, 1 at 256 and below).
// An explicit --padding N is used as given (N texels at any size).
int default_padding(int size);

// Dilates by `texels` rings: each pass gives every unbaked texel with at
// least one baked texel in its 8-neighbourhood the plain average of those
// neighbours (as they were at the start of the pass) and marks it baked in
// `baked`. Returns the number of texels filled. Deterministic: each pass
// reads only texels baked before it.
std::size_t dilate(std::span<float> rgba, std::span<uint8_t> baked, int width, int height,
                   int texels);

// What push_pull_fill writes into a filled texel's alpha.
enum class FillAlpha {
  kPushPull,     // alpha is pushed and pulled like the colour (--padding inf: an opaque image)
  kTransparent,  // alpha 0: the colour continues the charts, alpha stays the coverage (default)
};

// Fills every unbaked texel by push-pull (Gortler et al., "The Lumigraph",
// SIGGRAPH 1996, section 3.3; what Substance and MeshLab call infinite
// padding): pull averages the baked texels down a pyramid of half-resolution
// levels to 1 x 1 (each level's texel the weighted mean of its 2 x 2
// children, weights summed and clamped to 1); push fills each level's holes
// with the bilinear upsampling of the next coarser level, blended by the
// hole's weight. The background becomes a smooth continuation of the
// charts (every filled value is a convex combination of baked texels), so
// box-filtered mip levels near a chart average chart colours, never black.
// Channels 0-2 always, channel 3 as `alpha` says. Baked texels are not
// changed. Returns the number of texels filled (0 and the image untouched if
// nothing or everything is baked). Work and memory linear in the texels
// (the coarser levels: a third of the image); parallel; the result does not
// depend on the thread count.
std::size_t push_pull_fill(std::span<float> rgba, std::span<const uint8_t> baked, int width,
                           int height, FillAlpha alpha = FillAlpha::kPushPull);

}  // namespace texbake
