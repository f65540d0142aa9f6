// A non-owning view of an RGBA float image and the one place where texture
// coordinates become pixel positions (SPEC section 1).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "mapping/vec.h"

namespace texbake {

using Rgba = std::array<float, 4>;

// The encoding of an image's R, G, B values (issue #11; alpha is never
// encoded). kSrgb: sRGB-encoded (the IEC 61966-2-1 transfer curve applied),
// as 8/16-bit files store colour and as texbake's bakes give it. kLinear:
// linear light, as float and half files (EXR, HDR) store it; may exceed 1.
enum class ColorSpace : uint8_t { kSrgb, kLinear };

class TileSource;  // mapping/tiled_image.h
struct ImageView;
namespace detail {
std::array<float, 4> tiled_texel(const ImageView& image, int x, int y);
}

// width x height pixels, 4 floats (R, G, B, A) each, top row first, rows
// contiguous. Values are the image's stored values scaled to [0, 1] for
// integer formats (float images are unscaled), in the encoding
// `color_space` names.
// The texels are either in memory (`data`) or, for an image larger than
// the memory budget, read a tile at a time from `tiles`
// (mapping/tiled_image.h; `data` is then null). texel() reads either.
struct ImageView {
  int width = 0;
  int height = 0;
  const float* data = nullptr;  // width * height * 4 floats, or null when `tiles`
  ColorSpace color_space = ColorSpace::kSrgb;
  const TileSource* tiles = nullptr;  // not owned; used only when data is null
  // tiles only, what happens to a texel as its tile is loaded (instead of
  // to a whole copy; mapping/tiled_image.h transform_texel): R, G, B go
  // through srgb_to_linear (the linear working image of --linear;
  // color_space kLinear), then are multiplied by alpha (a layer's
  // premultiplied texture).
  bool decode_srgb = false;
  bool premultiply = false;
  // The image's own MIP levels 1 .. mip_level_count (a MIP-mapped file, as
  // maketx writes for OpenImageIO's TextureSystem; not owned): level i + 1
  // is mip_levels[i], each max(1, floor(previous / 2)) a side down to 1 x 1,
  // in the same encoding as this view. MipPyramid (mapping/mipmap.h) takes
  // them instead of reducing the image. Views that change the texels
  // (a linear working copy, decode_srgb, premultiply) have none.
  const ImageView* mip_levels = nullptr;
  int mip_level_count = 0;

  // Precondition: data (an in-memory view).
  const float* pixel(int x, int y) const {
    return data + (static_cast<std::size_t>(y) * width + x) * 4;
  }
  // Texel (x, y), 0 <= x < width, 0 <= y < height, from memory or tiles.
  std::array<float, 4> texel(int x, int y) const {
    if (data) {
      const float* p = pixel(x, y);
      return {p[0], p[1], p[2], p[3]};
    }
    return detail::tiled_texel(*this, x, y);
  }
  // Whether the texels exist (in memory or tiled).
  bool has_texels() const { return data != nullptr || tiles != nullptr; }
};

// SPEC section 1: x = u*W - 0.5, y = (1 - v)*H - 0.5. The only v-flip in texbake.
constexpr PixelPos pixel_from_uv(UV uv, int width, int height) {
  return {uv.u * width - 0.5, (1.0 - uv.v) * height - 0.5};
}

}  // namespace texbake
