// --texture-colorspace and --cache-mb, shared by every command that reads a
// texture (bake, render): how the texture's values are encoded (issue #11,
// README "Colour spaces"; the rules of detection: mesh_io/image_io.h) and
// the memory budget past which it is read in tiles (issue #16, SPEC section 13).
#pragma once

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstddef>
#include <string>

#include "bake/cli/choice_option.h"
#include "mesh_io/image_io.h"

namespace texbake::cli {

// Adds --texture-colorspace auto|srgb|linear (default auto) to `cmd`,
// setting `target`; another value is exit 2 naming the flag. `what` names
// the texture(s) it applies to in --help.
inline CLI::Option* add_texture_colorspace_flag(CLI::App& cmd, TextureColorSpace& target,
                                                const std::string& what) {
  return add_choice_option(cmd, "--texture-colorspace", target,
                           {{"auto", TextureColorSpace::kAuto},
                            {"srgb", TextureColorSpace::kSrgb},
                            {"linear", TextureColorSpace::kLinear}},
                           "colour space of " + what +
                               ": auto (default: as OpenImageIO reports it; untagged float/half "
                               "files linear, 8/16-bit sRGB), srgb or linear (overrides the file)");
}

// Adds --cache-mb N (1 .. 2^24 MiB, default kDefaultCacheMb) to `cmd`.
inline CLI::Option* add_cache_mb_flag(CLI::App& cmd, std::size_t& target) {
  return cmd
      .add_option("--cache-mb", target,
                  "memory budget for the texture in MiB (default " +
                      std::to_string(kDefaultCacheMb) +
                      "): a texture whose float RGBA copies would not fit, or larger than "
                      "16384 x 16384, is read in tiles on demand through OpenImageIO's "
                      "ImageCache (same results, bit for bit)")
      ->check(CLI::Range(std::size_t{1}, std::size_t{1} << 24));
}

// How bake and render read their texture: the colour space flag and the
// budget, counting the float RGBA copies the job holds besides the image
// (a linear working copy with --linear, a MIP pyramid's third with --filter ewa).
inline ImageReadOptions texture_read_options(TextureColorSpace color_space, std::size_t cache_mb,
                                             bool linear, bool ewa) {
  ImageReadOptions o;
  o.color_space = color_space;
  o.cache_mb = cache_mb;
  o.memory_copies = 1 + (linear ? 1.0 : 0.0) + (ewa ? 1.0 / 3 : 0.0);
  return o;
}

// --filter ewa on a texture read through the cache: its MIP levels above
// the full size are built in memory (mapping/mipmap.h), a third of the
// image's float RGBA size. Over the budget that is a usage error naming
// what to change (exit 2) rather than a bake that exceeds it.
inline Status check_ewa_budget(const Image& image, std::size_t cache_mb) {
  if (!image.tiles) return ok_status();
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

}  // namespace texbake::cli
