// The photo flags of `texbake bake MESH --cameras PATH [--images DIR]
// [--blend soft|best|mean] [--exposure gain|none] [--strict-photos] -o OUT`
// (SPEC section 9); the bake itself is the library's job (texbake/job.h,
// run_job with Job::cameras).
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "texbake/texbake.h"

namespace texbake::cli {

struct PhotoFlags {
  std::string cameras;  // empty: not a photo bake
  std::string images;
  PhotoBlend blend = PhotoBlend::kSoft;
  std::optional<ExposureMode> exposure;  // default: gain (a single photo has none)
  bool strict_photos = false;            // --strict-photos: an unreadable photo is an error
};

// Adds --cameras, --images, --blend, --exposure and --strict-photos to `bake`.
void add_photo_flags(CLI::App& cmd, PhotoFlags& flags);

}  // namespace texbake::cli
