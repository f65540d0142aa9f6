// texbake bake MESH --texture IMG --proxy KIND [geometry] [--target vertex]
//   -o OUT.ply|OUT.obj [options]   (SPEC sections 3, 4, 5)
//
// Parse -> options -> load -> bake_vertex -> write, nothing more: the work is
// in bake/bake_vertex.h. Bad flag values are rejected by CLI11 validators
// (exit 2), never clamped. Every geometry flag of the kind is required until
// fitting lands (issue #5); the atlas target and .glb output until issue #4.
// The output's folder is checked before the long work, and outputs are
// written atomically, so a failure never leaves a file behind.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "bake/bake_vertex.h"
#include "bake/cli/commands.h"
#include "bake/cli/geometry_flags.h"
#include "bake/options.h"
#include "bake/parallel.h"
#include "bake/progress.h"
#include "bake/report.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "mesh_io/write_mesh.h"

namespace texbake::cli {

namespace {

namespace fs = std::filesystem;

enum class Target { kVertex, kAtlas };

// A flag that is a keyword or a colour "R,G,B[,A]" (components in [0, 1]).
struct KeywordOrColor {
  std::string keyword;  // empty when a colour was given
  Rgba color{0, 0, 0, 1};
};

struct BakeCliOptions {
  std::string mesh;
  std::string texture;
  std::string output;
  GeometryFlags geometry;
  std::optional<Target> target;
  bool ascii = false;
  VertexFilter filter = VertexFilter::kArea;
  int samples = 16;
  Visibility visibility = Visibility::kFirst;
  KeywordOrColor occluded{"fill"};
  KeywordOrColor outside{"clamp"};
  std::optional<WrapMode> wrap;
  bool linear = false;
  std::string report;
  int threads = 0;
  bool quiet = false;
};

// Parses "R,G,B" or "R,G,B,A", each a number in [0, 1]. Throws
// CLI::ValidationError naming the flag (exit 2).
Rgba parse_color(const std::string& text, const std::string& flag) {
  Rgba c{0, 0, 0, 1};
  std::stringstream in(text);
  std::string part;
  int n = 0;
  while (std::getline(in, part, ',')) {
    if (n == 4) break;
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(part, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != part.size() || !(value >= 0 && value <= 1)) {
      throw CLI::ValidationError(flag, "'" + text +
                                           "' is not a colour R,G,B[,A] with components in [0, 1] "
                                           "(e.g. 1,0,0 for red)");
    }
    c[n++] = static_cast<float>(value);
  }
  if ((n != 3 && n != 4) || (!text.empty() && text.back() == ',') ||
      std::count(text.begin(), text.end(), ',') != n - 1) {
    throw CLI::ValidationError(flag, "'" + text +
                                         "' is not a colour R,G,B[,A] with components in [0, 1] "
                                         "(e.g. 1,0,0 for red)");
  }
  return c;
}

// Adds --flag accepting one of `keywords` or a colour.
void add_keyword_or_color(CLI::App& cmd, const std::string& flag, KeywordOrColor& target,
                          std::vector<std::string> keywords, const std::string& help) {
  cmd.add_option_function<std::string>(
         flag,
         [&target, flag, keywords](const std::string& value) {
           for (const std::string& k : keywords) {
             if (value == k) {
               target = KeywordOrColor{k};
               return;
             }
           }
           target = KeywordOrColor{"", parse_color(value, flag)};
         },
         help)
      ->type_name(keywords.size() == 1 ? keywords[0] + "|R,G,B[,A]"
                                       : keywords[0] + "|" + keywords[1] + "|R,G,B[,A]");
}

// Adds --flag mapping exactly one of the names in `names` to its enum value.
// (Not CLI::CheckedTransformer: CLI11 2.1's also accepts the enum's integer
// values, e.g. "--filter 1", and its message lists the integers.)
template <class T>
void add_enum_option(CLI::App& cmd, const std::string& flag, T& target,
                     const std::vector<std::pair<std::string, T>>& names, const std::string& help) {
  std::string expected, type_name;
  for (std::size_t i = 0; i < names.size(); ++i) {
    expected += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + names[i].first;
    type_name += (i == 0 ? "" : "|") + names[i].first;
  }
  cmd.add_option_function<std::string>(
         flag,
         [&target, flag, names, expected](const std::string& value) {
           for (const auto& [name, v] : names) {
             if (value == name) {
               target = v;
               return;
             }
           }
           throw CLI::ValidationError(flag,
                                      "unknown value '" + value + "' (expected " + expected + ")");
         },
         help)
      ->type_name(type_name);
}

std::string lower_extension(const fs::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

int run_bake(const BakeCliOptions& o) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();

  // ---- Usage checks (exit 2), before touching any file. ----
  if (Status s = check_geometry_flags(o.geometry, /*require_proxy=*/true); !s) {
    return report_error(s.error());
  }
  if (o.geometry.kind) {
    const std::vector<std::string> missing = missing_geometry_flags(o.geometry, *o.geometry.kind);
    if (!missing.empty()) {
      return report_error(ErrorCode::kInvalidArgument,
                          "missing " + missing.front() + " for --proxy " +
                              to_string(*o.geometry.kind) +
                              " (fitting the proxy to the mesh is not available yet: give every "
                              "geometry flag of the kind, or --proxy-file)");
    }
  }
  const fs::path output = o.output;
  const std::string ext = lower_extension(output);
  if (ext == ".glb") {
    return report_error(ErrorCode::kUnsupported,
                        "cannot write " + o.output + ": .glb output is not supported yet");
  }
  if (ext != ".ply" && ext != ".obj") {
    return report_error(ErrorCode::kInvalidArgument,
                        "cannot write " + o.output + ": the output must be .ply or .obj");
  }
  // SPEC section 5: the default target is vertex for .ply, atlas for .obj.
  const Target target = o.target.value_or(ext == ".ply" ? Target::kVertex : Target::kAtlas);
  if (target == Target::kAtlas) {
    return report_error(ErrorCode::kUnsupported,
                        "--target atlas is not supported yet; use --target vertex" +
                            std::string(ext == ".obj" ? " for OBJ vertex colours" : ""));
  }
  if (o.ascii && ext != ".ply") {
    return report_error(ErrorCode::kInvalidArgument, "--ascii applies to .ply output only");
  }
  Expected<Proxy> proxy = proxy_from_flags(o.geometry);
  if (!proxy) return report_error(proxy.error());
  if (o.wrap && !std::holds_alternative<Plane>(*proxy)) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--wrap applies to the plane proxy only (the others' wrap is fixed)");
  }

  // ---- Outputs must be writable before the long work (exit 1). ----
  if (Status s = check_writable(output); !s) return report_error(s.error());
  if (!o.report.empty()) {
    if (Status s = check_writable(o.report); !s) return report_error(s.error());
  }

  ThreadLimit thread_limit(o.threads);
  BakeReport report;
  report.mesh_path = o.mesh;
  report.texture_path = o.texture;
  report.output_path = o.output;
  report.threads = o.threads;
  report.proxy = params_of(*proxy);

  // ---- Load. ----
  const auto load_start = Clock::now();
  Expected<LoadedMesh> mesh = read_mesh(o.mesh);
  if (!mesh) return report_error(mesh.error());
  Expected<Image> image = read_image(o.texture);
  if (!image) return report_error(image.error());
  report.timings.load = seconds_since(load_start);
  report.image_width = image->width;
  report.image_height = image->height;
  report.degenerate_skipped = mesh->issues.degenerate_triangles;
  report.unreferenced_vertices = mesh->issues.unreferenced_vertices;

  // ---- Bake. ----
  VertexBakeOptions& options = report.options;
  options.filter = o.filter;
  options.samples = o.samples;
  options.visibility = o.visibility;
  if (o.occluded.keyword == "fill") {
    options.occluded = OccludedMode::kFill;
  } else if (o.occluded.keyword == "project") {
    options.occluded = OccludedMode::kProject;
  } else {
    options.occluded = OccludedMode::kColor;
    options.occluded_color = o.occluded.color;
  }
  if (o.outside.keyword == "clamp") {
    options.outside = OutsideMode::kClamp;
  } else {
    options.outside = OutsideMode::kColor;
    options.outside_color = o.outside.color;
  }
  options.linear = o.linear;
  options.plane_wrap = o.wrap.value_or(WrapMode::kClamp);

  Progress progress(!o.quiet && Progress::stderr_is_terminal());
  Expected<VertexBakeStage> sampled =
      bake_vertex_sample(mesh->mesh, image->view(), *proxy, options, &progress);
  if (!sampled) return report_error(sampled.error());
  image = Image{};  // nothing reads the image any more: free it before the fill's peak
  Expected<VertexBakeResult> baked = bake_vertex_finish(mesh->mesh, std::move(sampled).value());
  if (!baked) return report_error(baked.error());
  report.counts = baked->counts;
  report.timings.scene_build = baked->timings.scene_build;
  report.timings.bake = baked->timings.bake;
  report.timings.fill = baked->timings.fill;

  // ---- Write. ----
  const auto write_start = Clock::now();
  MeshWriteOptions write_options;
  write_options.ascii = o.ascii;
  write_options.vertex_colors = baked->colors;
  if (Status s = write_mesh(output, mesh->mesh, write_options); !s) return report_error(s.error());
  report.timings.write = seconds_since(write_start);
  report.timings.total = seconds_since(start);
  if (!o.report.empty()) {
    if (Status s = write_report(o.report, report); !s) return report_error(s.error());
  }

  if (!o.quiet) {
    const VertexBakeCounts& c = baked->counts;
    std::printf(
        "baked %zu vertices (%zu occluded, %zu filled, %zu unfilled, %zu outside samples) "
        "in %.2f s -> %s\n",
        c.vertices, c.occluded, c.filled, c.unfilled, c.outside, report.timings.total,
        o.output.c_str());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

RunFunction add_bake_command(CLI::App& app) {
  auto o = std::make_shared<BakeCliOptions>();
  CLI::App* cmd = app.add_subcommand(
      "bake", "Bake an image onto a mesh through a proxy shape (per-vertex colours)");
  cmd->add_option("mesh", o->mesh, "input mesh (.obj, .ply, .off, .stl)")->required();
  cmd->add_option("--texture", o->texture, "image to bake (anything OpenImageIO reads)")
      ->required();
  cmd->add_option("-o,--output", o->output, "output mesh (.ply, or .obj with --target vertex)")
      ->required();
  add_geometry_flags(*cmd, o->geometry);

  add_enum_option<std::optional<Target>>(
      *cmd, "--target", o->target, {{"vertex", Target::kVertex}, {"atlas", Target::kAtlas}},
      "vertex | atlas (default: vertex for .ply, atlas for .obj; atlas arrives later)");
  cmd->add_flag("--ascii", o->ascii, "write ASCII PLY instead of binary little-endian");

  add_enum_option(*cmd, "--filter", o->filter,
                  {{"bilinear", VertexFilter::kBilinear}, {"area", VertexFilter::kArea}},
                  "bilinear: sample at the vertex; area: average over the vertex's share of its "
                  "triangles (default)");
  cmd->add_option("--samples", o->samples, "samples per vertex for --filter area (default 16)")
      ->check(CLI::Range(1, 65536));

  add_enum_option(*cmd, "--visibility", o->visibility,
                  {{"first", Visibility::kFirst}, {"all", Visibility::kAll}},
                  "first: only what the projector sees is coloured (default); all: no test");
  add_keyword_or_color(*cmd, "--occluded", o->occluded, {"fill", "project"},
                       "occluded vertices: fill (smooth from visible neighbours, default), "
                       "project (projected colour anyway) or a colour R,G,B[,A] in [0,1]");
  add_keyword_or_color(*cmd, "--outside", o->outside, {"clamp"},
                       "points outside the proxy's (u,v) domain: clamp (edge texel, default) "
                       "or a colour R,G,B[,A] in [0,1]");
  add_enum_option<std::optional<WrapMode>>(
      *cmd, "--wrap", o->wrap, {{"clamp", WrapMode::kClamp}, {"repeat", WrapMode::kRepeat}},
      "plane proxy only: clamp (default) or repeat (tile)");
  cmd->add_flag("--linear", o->linear, "interpolate and average in linear light (sRGB image)");
  cmd->add_option("--report", o->report, "write what was done as JSON to this file");
  cmd->add_option("--threads", o->threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  cmd->add_flag("-q,--quiet", o->quiet, "no progress bar, no summary");
  return [o] { return run_bake(*o); };
}

}  // namespace texbake::cli
