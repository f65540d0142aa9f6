// --texture-colorspace and --cache-mb, shared by every command that reads a
// texture (bake, render): how the texture's values are encoded (issue #11,
// README "Colour spaces"; the rules of detection: mesh_io/image_io.h) and
// the memory budget past which it is read in tiles (issue #16, SPEC section 13).
#pragma once

#include <CLI/CLI.hpp>
#include <cstddef>
#include <string>

#include "bake/cli/choice_option.h"
#include "mesh_io/image_io.h"
#include "texbake/texbake.h"

namespace texbake::cli {

// Adds --texture-colorspace auto|srgb|linear (default auto) to `cmd`,
// setting `target`; another value is exit 2 naming the flag. `what` names
// the texture(s) it applies to in --help.
inline CLI::Option* add_texture_colorspace_flag(CLI::App& cmd, TextureColorSpace& target,
                                                const std::string& what) {
  return add_choice_option<TextureColorSpace>(
      cmd, "--texture-colorspace", target,
      "colour space of " + what +
          ": auto (default: as OpenImageIO reports it; untagged float/half "
          "files linear, 8/16-bit sRGB), srgb or linear (overrides the file)");
}

// Adds --cache-mb N (default kDefaultCacheMb; texbake::check_cache_mb's
// range, 1 .. 2^24 MiB, and message) to `cmd`.
inline CLI::Option* add_cache_mb_flag(CLI::App& cmd, std::size_t& target) {
  return cmd
      .add_option_function<long long>(
          "--cache-mb",
          [&target](long long mb) {
            if (Status s = check_cache_mb(mb); !s) throw CLI::ValidationError(s.error().message);
            target = static_cast<std::size_t>(mb);
          },
          "memory budget for the texture (or each layer's texture and mask) in MiB "
          "(default " +
              std::to_string(kDefaultCacheMb) +
              "): a texture whose float RGBA copies would not fit, or larger than "
              "16384 x 16384, is read in tiles on demand through OpenImageIO's "
              "ImageCache (same results, bit for bit)")
      ->type_name("N");
}

}  // namespace texbake::cli
