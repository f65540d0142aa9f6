// texture_read_options and check_ewa_budget: how the bakes read a large texture.
#include <algorithm>
#include <string>

#include "texbake/texbake.h"

namespace texbake {

ImageReadOptions texture_read_options(TextureColorSpace color_space, std::size_t cache_mb,
                                      bool linear, bool ewa) {
  ImageReadOptions o;
  o.color_space = color_space;
  o.cache_mb = cache_mb;
  o.memory_copies = 1 + (linear ? 1.0 : 0.0) + (ewa ? 1.0 / 3 : 0.0);
  o.mip_levels = ewa;
  o.linear_working = linear;
  return o;
}

Status check_ewa_budget(const Image& image, std::size_t cache_mb, bool linear) {
  if (!image.tiles) return ok_status();
  // The file's own levels, read through the same cache (unless --linear
  // makes linear-light levels of an sRGB texture necessary).
  if (image.mip && !(linear && image.color_space == ColorSpace::kSrgb)) return ok_status();
  double bytes = 0;
  for (long long w = image.width, h = image.height; w > 1 || h > 1;) {
    w = std::max(1ll, w / 2);
    h = std::max(1ll, h / 2);
    bytes += static_cast<double>(w) * h * 16;
  }
  const double mib = bytes / (1 << 20);
  if (mib <= static_cast<double>(cache_mb)) return ok_status();
  return make_error(ErrorCode::kInvalidArgument,
                    "--filter ewa keeps the MIP levels of the " + std::to_string(image.width) +
                        " x " + std::to_string(image.height) + " texture in memory (" +
                        std::to_string(static_cast<long long>(mib + 1)) +
                        " MiB), more than --cache-mb " + std::to_string(cache_mb) +
                        ": raise --cache-mb or use --filter bilinear or area");
}

}  // namespace texbake
