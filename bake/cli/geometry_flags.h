// The geometry flags of SPEC section 5 on a CLI11 command (map, bake, fit,
// render): --proxy KIND | --proxy-file F, the parameters of
// mapping/proxy_schema.h and --up, parsed and checked by the library
// (texbake/geometry_options.h); a bad value is a CLI::ValidationError with
// the library's message (exit 2). Negative values need no '=': --up -z,
// --center -1,0,0.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <string_view>

#include "texbake/geometry_options.h"

namespace texbake::cli {

// The library's geometry options, by the names the commands have always used.
using texbake::check_geometry_flags;
using texbake::flags_of_kind;
using texbake::GeometryFlags;
using texbake::given_geometry_flags;
using texbake::merge_flags;
using texbake::missing_geometry_flags;
using texbake::params_from_flags;
using texbake::projector_from_flags;
using texbake::proxy_from_flags;
using texbake::spec_from_flags;
using texbake::up_direction;

// The parser of the vector flags, for other commands' own flags (e.g. map's
// --point). Throws CLI::ValidationError naming `flag` on bad input: call it
// inside a CLI11 option callback.
Vec3 parse_vec3_flag(std::string_view text, const std::string& flag);

// Registers all the geometry flags on `command`, writing into `flags` (which
// must outlive parsing): --proxy, --proxy-file, the parameters of
// geometry_params() in its order with their help and type, then --up.
void add_geometry_flags(CLI::App& command, GeometryFlags& flags);

}  // namespace texbake::cli
