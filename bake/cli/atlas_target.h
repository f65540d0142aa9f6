// The atlas target of `texbake bake` (SPEC section 4/5, issue #4), packaged
// for cmd_bake.cpp: flag registration, validation before any long work, and
// one call that lays out UVs, bakes and writes. Lives in bake/cli because
// `--uv generate` (texbake_uv) and the bakers (texbake_atlas) meet only in
// the executable.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "bake/atlas/bake_atlas.h"
#include "bake/shade/options.h"
#include "bake/util/progress.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mesh_io/mesh_data.h"

namespace texbake::cli {

enum class BakeTarget { kVertex, kAtlas };
enum class UvSource { kAuto, kMesh, kProxy, kGenerate };

// The atlas flags as parsed (strings are turned into enums by CLI11
// transformers, see add_atlas_flags).
struct AtlasFlags {
  std::string target;   // "", "vertex" or "atlas"
  int size = 2048;      // --size
  std::string padding;  // --padding: "" (default), a count >= 0, or "inf"
  UvSource uv = UvSource::kAuto;
  ImageBitDepth format = ImageBitDepth::k8;  // --format png8|png16|exr
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
// (kInvalidArgument, naming the flag): --size outside 1..16384, --samples
// outside 1..256, --padding not a count or "inf", --format exr with .glb.
Expected<AtlasBakeOptions> atlas_options(const AtlasFlags& flags, std::optional<int> samples,
                                         const VertexBakeOptions& shading,
                                         const std::filesystem::path& output);

struct AtlasJobTimings {  // seconds
  double uv_layout = 0;
  double rasterize = 0;
  double scene_build = 0;
  double sample = 0;
  double fill = 0;
  double pad = 0;
  double write = 0;
};

struct AtlasJobReport {
  std::string uv_source;  // "mesh", "proxy" or "generate" (auto resolved)
  AtlasBakeCounts counts;
  AtlasJobTimings timings;
  std::size_t uv_corners_outside = 0;  // --uv mesh checks
  std::size_t uv_overlap_texels = 0;
  std::size_t cut_triangles = 0;  // --uv proxy
  std::size_t chart_count = 0;    // --uv generate
  double utilisation = 0;         // --uv generate: covered texels / all texels
  double stretch_l2 = 0;          // --uv generate
  std::vector<std::string> warnings;
};

// Lays out UVs (flags.uv; kAuto: the mesh's own if it has any, else
// generate), bakes (bake_atlas) and writes `output` (.obj + .mtl + atlas, or
// .glb) through write_textured_mesh. Warnings (UVs outside [0, 1], overlaps)
// are returned, not printed. Errors: --uv mesh on a mesh without UVs
// (kInvalidArgument), the stages' own errors.
Expected<AtlasJobReport> run_atlas_job(const MeshData& mesh, const ImageView& image,
                                       const Proxy& proxy, const AtlasFlags& flags,
                                       const AtlasBakeOptions& options,
                                       const std::filesystem::path& output, Progress* progress);

// The report's "atlas" object (JSON text): uv source, counts, timings.
std::string atlas_report_json(const AtlasJobReport& report, const AtlasBakeOptions& options);

}  // namespace texbake::cli
