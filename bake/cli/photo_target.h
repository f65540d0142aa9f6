// `texbake bake MESH --cameras PATH [--images DIR] [--blend soft|best|mean]
// [--exposure gain|none] -o OUT` (SPEC section 9): vertex colours
// (bake_vertex_colors_from_photos; the vertex target's writers: .ply, .obj,
// .glb) or a texture atlas (bake_atlas_texture_from_photos, with the atlas
// flags --size, --samples, --uv, --padding, --format; .obj + .mtl + image,
// .glb) from calibrated photographs.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
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

// The report's "photos_skipped": one {"image", "path", "reason"} per photo
// left out because it cannot be read.
nlohmann::ordered_json skipped_photos_json(const std::vector<SkippedPhoto>& skipped);

// Adds --cameras, --images, --blend, --exposure and --strict-photos to `bake`.
void add_photo_flags(CLI::App& cmd, PhotoFlags& flags);

struct PhotoJob {
  std::string mesh, output, report;
  PhotoFlags flags;
  OccludedMode occluded = OccludedMode::kFill;
  Rgba occluded_color{0, 0, 0, 1};
  WriteOptions write;          // with the atlas target: --format as well
  bool atlas = false;          // the atlas target
  AtlasOptions atlas_options;  // validated (atlas_options of atlas_target.h); shading unused
  int threads = 0;
  bool quiet = false;
  std::function<void(const std::string&)> on_report;  // CliHooks::on_report (batch results)
  // A camera --proxy-file with its --texture: this one photo instead of
  // flags.cameras (which then names the camera file, for messages and the
  // report), seen up to 90 degrees (SPEC section 9's camera proxy rule).
  std::optional<Photo> single;
  TextureColorSpace color_space = TextureColorSpace::kAuto;  // --texture-colorspace
};

// Checks (exit 2 for usage), reads the cameras and the mesh, bakes, writes
// atomically (an atlas's OBJ + MTL + image set together), prints the summary
// line; returns the exit code.
int run_photo_bake(const PhotoJob& job);

}  // namespace texbake::cli
