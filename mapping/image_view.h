// A non-owning view of an RGBA float image and the one place where texture
// coordinates become pixel positions (SPEC section 1).
#pragma once

#include <array>
#include <cstddef>

#include "mapping/vec.h"

namespace texbake {

using Rgba = std::array<float, 4>;

// width x height pixels, 4 floats (R, G, B, A) each, top row first, rows
// contiguous. Values are the image's stored values scaled to [0, 1] for
// integer formats (float images are unscaled).
struct ImageView {
  int width = 0;
  int height = 0;
  const float* data = nullptr;  // width * height * 4 floats

  const float* pixel(int x, int y) const {
    return data + (static_cast<std::size_t>(y) * width + x) * 4;
  }
};

// SPEC section 1: x = u*W - 0.5, y = (1 - v)*H - 0.5. The only v-flip in texbake.
constexpr PixelPos pixel_from_uv(UV uv, int width, int height) {
  return {uv.u * width - 0.5, (1.0 - uv.v) * height - 0.5};
}

}  // namespace texbake
