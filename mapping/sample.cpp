// Bilinear sampling (SPEC section 1) and the sRGB curves.
#include "mapping/sample.h"

#include <algorithm>
#include <cmath>

namespace texbake {

namespace {

// Texel index i (any integer-valued double) folded into [0, n) by `mode`.
// Works in double so huge coordinates cannot overflow an int.
int fold(double i, int n, WrapMode mode) {
  if (mode == WrapMode::kRepeat) i -= n * std::floor(i / n);
  return std::clamp(static_cast<int>(std::clamp(i, 0.0, n - 1.0)), 0, n - 1);
}

}  // namespace

Rgba sample_bilinear(const ImageView& image, UV uv, WrapMode wrap_u, WrapMode wrap_v) {
  PixelPos p = pixel_from_uv(uv, image.width, image.height);
  // A NaN coordinate is a caller bug; sample a defined texel rather than
  // cast NaN to int (undefined behaviour).
  if (!std::isfinite(p.x)) p.x = 0;
  if (!std::isfinite(p.y)) p.y = 0;
  const double x0 = std::floor(p.x), y0 = std::floor(p.y);
  const double fx = p.x - x0, fy = p.y - y0;
  const int xa = fold(x0, image.width, wrap_u), xb = fold(x0 + 1, image.width, wrap_u);
  const int ya = fold(y0, image.height, wrap_v), yb = fold(y0 + 1, image.height, wrap_v);
  const Rgba t00 = image.texel(xa, ya);
  const Rgba t10 = image.texel(xb, ya);
  const Rgba t01 = image.texel(xa, yb);
  const Rgba t11 = image.texel(xb, yb);
  Rgba out;
  for (int c = 0; c < 4; ++c) {
    const double top = t00[c] + (t10[c] - t00[c]) * fx;
    const double bottom = t01[c] + (t11[c] - t01[c]) * fx;
    out[c] = static_cast<float>(top + (bottom - top) * fy);
  }
  return out;
}

// IEC 61966-2-1:1999, section 5.2 (decoding) and 5.3 (encoding).
float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

float linear_to_srgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
}

}  // namespace texbake
