// `texbake bake MESH --layers LAYERS.json -o OUT` (SPEC section 10): vertex
// colours (bake_vertex_colors_from_layers; the vertex target's writers:
// .ply, .obj, .glb; RGBA when the result is not opaque) or an atlas
// (bake_atlas_texture_from_layers; write_atlas: .obj + .mtl + RGBA .png, or
// a .glb with alphaMode BLEND when a covered texel is not opaque)
// composited from several projections over a base.
#pragma once

#include <functional>
#include <string>

#include "texbake/texbake.h"

namespace texbake::cli {

struct LayersJob {
  std::string mesh, layers, output, report;
  OccludedMode occluded = OccludedMode::kFill;
  Rgba occluded_color{0, 0, 0, 1};
  WriteOptions write;
  bool atlas = false;          // the atlas target (else vertex)
  AtlasOptions atlas_options;  // bake.size 0: the base texture's size, else 2048
  int threads = 0;
  bool quiet = false;
  std::size_t cache_mb = kDefaultCacheMb;             // --cache-mb: the layers' textures and masks
  bool strict_photos = false;                         // --strict-photos: "cameras" layers' photos
  std::function<void(const std::string&)> on_report;  // CliHooks::on_report (batch results)
};

// Reads the layers file and the mesh (usage errors exit 2, input errors 1),
// bakes, writes atomically, prints the summary line; returns the exit code.
int run_layers_bake(const LayersJob& job);

}  // namespace texbake::cli
