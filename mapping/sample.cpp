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
namespace {

float srgb_curve(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

// The curve at the 256 values an 8-bit image decodes to, b / 255 (the
// quotient, or b * (1 / 255) as some readers compute it: one ulp apart for
// some b): most photos' and textures' texels, looked up instead of a pow
// each (a quarter of a photo bake's time was that pow). The table holds the
// curve's own results for those exact inputs, so every value is the same
// bits as without it. Hand-written rather than a library's conversion: the
// values must be exactly those of SPEC's formula above.
struct Srgb8 {
  float in_div[256], in_mul[256], out_div[256], out_mul[256];
  Srgb8() {
    for (int b = 0; b < 256; ++b) {
      in_div[b] = static_cast<float>(b) / 255.0f;
      in_mul[b] = static_cast<float>(b) * (1.0f / 255.0f);
      out_div[b] = srgb_curve(in_div[b]);
      out_mul[b] = srgb_curve(in_mul[b]);
    }
  }
};

}  // namespace

float srgb_to_linear(float c) {
  const float k = c * 255.0f;
  if (k > 0.0f && k <= 255.0f) {  // (not NaN; 0 and -0 keep their sign below)
    static const Srgb8 table;
    const int b = static_cast<int>(k + 0.5f);
    // OpenImageIO decodes a byte as b * (1 / 255): that first, so the
    // branch is always taken the same way for its images.
    if (c == table.in_mul[b]) return table.out_mul[b];
    if (c == table.in_div[b]) return table.out_div[b];
  }
  return srgb_curve(c);
}

float linear_to_srgb(float c) {
  return c <= 0.0031308f ? c * 12.92f : 1.055f * std::pow(c, 1 / 2.4f) - 0.055f;
}

}  // namespace texbake
