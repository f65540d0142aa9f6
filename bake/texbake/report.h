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
//    "atlas":   atlas target only: {"uv": "mesh" | "proxy" | "generate",
//                "size", "samples_per_texel", "padding": texels | "inf" (the
//                default's rings; it push-pulls the rest, bake/atlas/atlas_common.h),
//                "counts": {"texels", "samples", "border_samples", "occluded",
//                           "undefined", "outside", "padded"},
//                uv mesh: "uv_check": {"corners_outside", "overlap_texels"},
//                uv proxy: "uv_check": {"overlap_texels"}, "cut_triangles",
//                uv generate: "charts",
//                "utilisation", "stretch_l2",
//                "timings": {"uv_layout", "rasterize", "scene_build", "sample",
//                            "fill", "pad", "write"}},
//    "timings": vertex: {"load", "fit", "scene_build", "bake", "fill", "write", "total"}
//               atlas:  {"load", "fit", "uv_layout", "rasterize", "scene_build",
//                        "sample", "fill", "pad", "write", "total"}}  // seconds
// Vertex target: "samples" counts sample points mapped, "outside" those
// outside the proxy's (u, v) domain, "occluded" vertices whose visibility ray
// is blocked, "unfilled" fill-bound vertices in components with no visible
// vertex. Atlas target: "texels" covered texels, "samples" supersamples
// taken, "occluded"/"undefined"/"outside" samples, "padded" texels filled by
// the padding; options.filter is "bilinear" or "ewa" and "samples" is per texel.
// Everything but "inputs" and the CLI's own timings comes from the Stats of
// texbake/texbake.h: the proxy's (timings.fit) and the bake's (counts and
// the other timings; atlas "sample" is Timings::bake).
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "texbake/job.h"
#include "texbake/texbake.h"

namespace texbake {

struct AtlasReport {
  AtlasBakeOptions options;  // size, samples per texel, padding
  UvLayoutStats uv;
};

struct BakeReport {
  std::string mesh_path, texture_path, output_path;
  int image_width = 0, image_height = 0;
  bool image_cached = false;  // read in tiles through the ImageCache (--cache-mb)
  // The texture file's own MIP levels above the full size that --filter ewa
  // uses (a MIP-mapped file); 0 when the bake reduces the image itself.
  int image_mip_levels = 0;
  VertexBakeOptions options;  // shading (filter and samples: vertex target)
  int threads = 0;            // 0 = all cores
  ProxyParams proxy;
  std::vector<std::string> fitted_flags;  // geometry flags filled by a fit
  std::optional<AtlasReport> atlas;       // atlas target
  Stats stats;                            // the bake's (bake_vertex_colors, bake_atlas_texture)
  double fit = 0;                         // seconds: the proxy's Stats timings.fit
  double load = 0;                        // seconds: mesh and image reading
  double write = 0;                       // seconds: the output files
  double total = 0;                       // seconds: the whole command
};

// The report's "atlas" object: the atlas options, the bake's counts, the UV
// layout's figures and the atlas stages' timings (also the photo atlas's,
// bake/cli/photo_target.cpp).
nlohmann::ordered_json atlas_json(const AtlasReport& atlas, const Stats& stats, double write);

// The JSON text of the layout above (pretty-printed, 2 spaces, ends with a newline).
std::string report_json(const BakeReport& report);

// Writes report_json(report) to path through write_atomically. Errors: kIo naming path.
Status write_report(const std::filesystem::path& path, const BakeReport& report);
// The same for a report's text made elsewhere (the photo and layers bakes).
Status write_report_text(const std::filesystem::path& path, const std::string& text);

// The report's "counts" of a bake of `source` (a camera proxy file's bake
// is a photos bake) for either target, by the names the report gives them
// (Python's stats["counts"] use the same): a proxy bake's vertices,
// triangles, degenerate_skipped, unreferenced_vertices, (texels,) samples,
// occluded, undefined, outside, then filled and unfilled or padded; a
// photos bake's unseen, camera_samples (vertex) or samples (atlas), ...; a
// layers bake's uncovered, ...
enum class ReportSource { kProxy, kPhotos, kLayers };
nlohmann::ordered_json counts_json(ReportSource source, bool atlas, const Counts& counts);

// The report's "timings" of the bake's own stages (seconds), by the names
// the report gives them, without the job's load, fit, write and total
// (Python's stats["timings"] use the same): scene_build, bake (a proxy
// vertex bake), sample (a proxy atlas), photos, layers and per_layer (one
// per layer, `layers`), fill, and for an atlas uv_layout, rasterize,
// vertex_photos (a photo atlas's fill), pad.
nlohmann::ordered_json stage_timings_json(ReportSource source, bool atlas, const Timings& timings,
                                          const std::vector<LayerStats>& layers);

// The photo bakes' reports (vertex, atlas: inputs, counts, the atlas
// object, one entry per camera, the photos left out, timings) and the
// layers bakes' (one entry per layer), as JSON text; times in seconds.
// Their "photos_skipped": one {"image", "path", "reason"} per photo left
// out because it cannot be read (skipped_photos_json).
nlohmann::ordered_json skipped_photos_json(const std::vector<SkippedPhoto>& skipped);
std::string photo_report(const Job& job, const PhotoColors& baked, double load, double write,
                         double total);
std::string photo_atlas_report(const Job& job, const PhotoAtlas& baked, double load, double write,
                               double total);
std::string layers_report(const Job& job, const LayerColors& baked, double load, double write,
                          double total);
std::string layers_atlas_report(const Job& job, const LayerAtlas& baked, double load, double write,
                                double total);

}  // namespace texbake
