// Atlas padding (SPEC section 4, issue #11 item 4): grow the baked charts
// into the unbaked gutter so that mipmapping and filtering renderers never
// blend in the background.
//
// Images here are RGBA float, width * height * 4 values, row-major (the
// layout of ImageView). `baked` has one byte per texel: non-zero = holds a
// baked colour. Baked texels are never changed by either function; all four
// channels are treated alike (except by push_pull_fill's kMipSafe).
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

// The two push-pull fills.
enum class PushPullMode {
  // --padding inf (Gortler et al.'s push): each hole blends the plain
  // bilinear upsampling of the filled coarser level; all four channels, so
  // the atlas comes out opaque.
  kOpaque,
  // The default padding's fill: each hole takes its colour from the first
  // coarser level where its ancestor holds data, interpolating bilinearly
  // between that ancestor and those of its neighbours that hold data (or
  // inherits its parent's fill when the parent holds none). Within any
  // 2^k-aligned block holding baked texels, every filled value is then a
  // convex combination of the baked texels of the block and its 8
  // neighbours, so the block's box-filtered mip texel stays within their
  // range (tests/bake/atlas/atlas_mip_test.cpp). Channels 0-2; alpha is set
  // to 0, so it still tells the baked texels (coverage) from the fill.
  kMipSafe,
};

// Fills every unbaked texel by push-pull (Gortler et al., "The Lumigraph",
// SIGGRAPH 1996, section 3.3; what Substance and MeshLab call infinite
// padding): pull averages the baked texels down a pyramid of half-resolution
// levels to 1 x 1 (each level's texel the weighted mean of its 2 x 2
// children, weights summed and clamped to 1); push fills each level's holes
// from the next coarser level as `mode` says. The background becomes a
// continuation of the charts made of their colours (every filled value is a
// convex combination of baked texels), so box-filtered mip levels near a
// chart average chart colours, never black. Baked texels are not changed.
// Returns the number of texels filled (0 and the image untouched if nothing
// or everything is baked). Work and memory linear in the texels (the coarser
// levels: a third of the image); parallel; the result does not depend on
// the thread count.
std::size_t push_pull_fill(std::span<float> rgba, std::span<const uint8_t> baked, int width,
                           int height, PushPullMode mode = PushPullMode::kOpaque);

}  // namespace texbake
