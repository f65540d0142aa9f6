// The `--report FILE.json` of `texbake bake` (SPEC section 5): what was done.
//
// JSON layout (keys stable; numbers in the units stated):
//   {"command": "bake", "target": "vertex",
//    "inputs":  {"mesh": path, "texture": path, "output": path,
//                "image": {"width": px, "height": px},
//                "options": {"filter", "samples", "visibility", "occluded",
//                            "outside", "wrap", "linear", "threads"}},
//    "proxy":   {"kind": "sphere", ...the proxy's parameters, vectors unit...},
//    "counts":  {"vertices", "triangles", "degenerate_skipped",
//                "unreferenced_vertices", "samples", "occluded", "undefined",
//                "outside", "filled", "unfilled"},
//    "timings": {"load", "scene_build", "bake", "fill", "write", "total"}}  // seconds
// "samples" counts sample points mapped, "outside" those outside the proxy's
// (u, v) domain, "occluded" vertices whose visibility ray is blocked,
// "unfilled" fill-bound vertices in components with no visible vertex.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

#include "bake/bake_vertex.h"
#include "bake/options.h"
#include "mapping/error.h"
#include "mapping/proxy.h"

namespace texbake {

struct StageTimings {      // seconds
  double load = 0;         // mesh and image reading
  double scene_build = 0;  // Embree BVH
  double bake = 0;         // mapping, visibility, sampling
  double fill = 0;         // occluded handling
  double write = 0;        // output mesh
  double total = 0;        // wall clock of the whole command
};

struct BakeReport {
  std::string mesh_path, texture_path, output_path;
  int image_width = 0, image_height = 0;
  VertexBakeOptions options;
  int threads = 0;  // 0 = all cores
  ProxyParams proxy;
  VertexBakeCounts counts;
  std::size_t degenerate_skipped = 0;
  std::size_t unreferenced_vertices = 0;
  StageTimings timings;
};

// The JSON text of the layout above (pretty-printed, 2 spaces, ends with a newline).
std::string report_json(const BakeReport& report);

// Writes report_json(report) to path through write_atomically. Errors: kIo naming path.
Status write_report(const std::filesystem::path& path, const BakeReport& report);

}  // namespace texbake
