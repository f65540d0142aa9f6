// The atlas flags of `texbake bake` (SPEC section 4/5, issue #4): their
// registration and their validation before any long work, into the
// AtlasOptions of texbake/texbake.h (whose bake_atlas_texture and
// write_atlas do the work).
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "texbake/texbake.h"

namespace texbake::cli {

enum class BakeTarget { kVertex, kAtlas };

// The atlas flags as parsed (strings are turned into enums by CLI11
// transformers, see add_atlas_flags).
struct AtlasFlags {
  std::string target;   // "", "vertex" or "atlas"
  int size = 2048;      // --size
  std::string padding;  // --padding: "" (default), a count >= 0, or "inf"
  UvLayout uv = UvLayout::kAuto;
  AtlasFormat format = AtlasFormat::kPng8;  // --format png8|png16|exr
};

// Registers --target, --size, --padding, --uv and --format on `bake`.
// (--samples is shared with the vertex target and registered by cmd_bake;
// pass its value, if given, to atlas_options.)
void add_atlas_flags(CLI::App& bake, AtlasFlags& flags);

// --target given or the default for the output's extension: vertex for .ply,
// atlas for .obj and .glb. Errors (kInvalidArgument / kUnsupported, exit 2):
// --target atlas with a .ply output, an unknown extension.
Expected<BakeTarget> resolve_target(const AtlasFlags& flags, const std::filesystem::path& output);

// Validated atlas options (call before loading anything). Errors
// (kInvalidArgument / kUnsupported, naming the flag): validate_options's
// (--size outside 1..16384, --samples outside 1..256), --padding not a count
// or "inf", then validate_write's (--format exr with .glb).
Expected<AtlasOptions> atlas_options(const AtlasFlags& flags, std::optional<int> samples,
                                     const VertexBakeOptions& shading,
                                     const std::filesystem::path& output);

// The writer options of the atlas flags (--format).
WriteOptions atlas_write_options(const AtlasFlags& flags);

}  // namespace texbake::cli
