// The `--report FILE.json` of `texbake bake` (SPEC section 5): what was done.
//
// JSON layout (keys stable; numbers in the units stated):
//   {"command": "bake", "target": "vertex" | "atlas",
//    "inputs":  {"mesh": path, "texture": path, "output": path,
//                "image": {"width": px, "height": px},
//                "options": {"filter", "samples", "visibility", "occluded",
//                            "outside", "wrap", "linear", "threads"}},
//    "proxy":   {"kind": "sphere", ...the proxy's parameters, vectors unit...},
//    "proxy_fitted": ["--center", "--radius"],   // flags filled by a fit ([] if none)
//    "counts":  vertex: {"vertices", "triangles", "degenerate_skipped",
//                "unreferenced_vertices", "samples", "occluded", "undefined",
//                "outside", "filled", "unfilled"}
//               atlas: {"vertices", "triangles", "degenerate_skipped",
//                "unreferenced_vertices", "texels", "samples", "occluded",
//                "undefined", "outside", "padded"},
//    "atlas":   atlas target only: the AtlasJobReport of bake/cli/atlas_target.h
//               (uv source, size, samples per texel, padding, counts, UV
//               checks or chart statistics, its own stage timings),
//    "timings": vertex: {"load", "fit", "scene_build", "bake", "fill", "write", "total"}
//               atlas:  {"load", "fit", "uv_layout", "rasterize", "scene_build",
//                        "sample", "fill", "pad", "write", "total"}}  // seconds
// Vertex target: "samples" counts sample points mapped, "outside" those
// outside the proxy's (u, v) domain, "occluded" vertices whose visibility ray
// is blocked, "unfilled" fill-bound vertices in components with no visible
// vertex. Atlas target: "texels" covered texels, "samples" supersamples
// taken, "occluded"/"undefined"/"outside" samples, "padded" texels filled by
// the padding; options.filter does not apply and "samples" is per texel.
#pragma once

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bake/atlas/bake_atlas.h"
#include "bake/shade/options.h"
#include "bake/vertex/bake_vertex.h"
#include "mapping/error.h"
#include "mapping/proxy.h"

namespace texbake {

struct StageTimings {      // seconds
  double load = 0;         // mesh and image reading
  double fit = 0;          // fitting the proxy to the mesh (0 if nothing was fitted)
  double uv_layout = 0;    // atlas: UV layout (mesh check, proxy cut or generate)
  double rasterize = 0;    // atlas: covered texels and their samples
  double sample = 0;       // atlas: mapping, visibility and image samples
  double pad = 0;          // atlas: padding
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
  std::vector<std::string> fitted_flags;  // geometry flags filled by a fit
  VertexBakeCounts counts;                // vertex target (vertices and triangles for both)
  // Atlas target: its counts, and the "atlas" object as JSON text (from
  // bake/cli/atlas_target.h's atlas_report_json, which lives in the CLI).
  std::optional<AtlasBakeCounts> atlas_counts;
  int atlas_samples = 0;  // samples per texel
  std::string atlas_json;
  std::size_t degenerate_skipped = 0;
  std::size_t unreferenced_vertices = 0;
  StageTimings timings;
};

// The JSON text of the layout above (pretty-printed, 2 spaces, ends with a newline).
std::string report_json(const BakeReport& report);

// Writes report_json(report) to path through write_atomically. Errors: kIo naming path.
Status write_report(const std::filesystem::path& path, const BakeReport& report);

}  // namespace texbake
