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

}  // namespace texbake
