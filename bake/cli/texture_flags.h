// --texture-colorspace, shared by every command that reads a texture (bake,
// render): how the texture's values are encoded (issue #11, README "Colour
// spaces"; the rules of detection: mesh_io/image_io.h).
#pragma once

#include <CLI/CLI.hpp>
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

}  // namespace texbake::cli
