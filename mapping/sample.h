// Bilinear sampling of an ImageView (SPEC section 1) and sRGB transfer curves.
#pragma once

#include "mapping/image_view.h"
#include "mapping/proxy.h"

namespace texbake {

// Interpolates the four texels around pixel_from_uv(uv). Texels outside the
// image follow wrap_u horizontally and wrap_v vertically (kRepeat: periodic,
// kClamp: the edge texel). Precondition: image has at least 1x1 pixel.
Rgba sample_bilinear(const ImageView& image, UV uv, WrapMode wrap_u, WrapMode wrap_v);

// IEC 61966-2-1 sRGB transfer functions on one channel value in [0, 1].
float srgb_to_linear(float c);
float linear_to_srgb(float c);

// The same on R, G and B of a colour; alpha is never converted (SPEC section
// 1 --linear). The one per-colour form of the curves: images, constants and
// results all go through these.
inline Rgba srgb_to_linear(Rgba c) {
  for (int k = 0; k < 3; ++k) c[k] = srgb_to_linear(c[k]);
  return c;
}
inline Rgba linear_to_srgb(Rgba c) {
  for (int k = 0; k < 3; ++k) c[k] = linear_to_srgb(c[k]);
  return c;
}

}  // namespace texbake
