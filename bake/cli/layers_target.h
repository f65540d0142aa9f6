// `texbake bake MESH --layers LAYERS.json -o OUT` (SPEC section 10): vertex
// colours composited from several projections over a base
// (bake_vertex_colors_from_layers; the vertex target's writers: .ply, .obj,
// .glb; RGBA when the result is not opaque).
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
  int threads = 0;
  bool quiet = false;
  std::function<void(const std::string&)> on_report;  // CliHooks::on_report (batch results)
};

// Reads the layers file and the mesh (usage errors exit 2, input errors 1),
// bakes, writes atomically, prints the summary line; returns the exit code.
int run_layers_bake(const LayersJob& job);

}  // namespace texbake::cli
