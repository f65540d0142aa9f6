// texbake bake MESH --texture IMG --proxy KIND [geometry] [--target vertex|atlas]
//   -o OUT.ply|OUT.obj|OUT.glb [options]   (SPEC sections 3 to 7)
//
// Parse -> validate every flag (exit 2) -> a texbake::Job (texbake/job.h:
// an image through a proxy, --cameras, a camera --proxy-file, --layers) ->
// run_job (no output an input, outputs writable, read the mesh, fit the
// geometry flags not given, read, bake, write atomically, report) -> print
// its warnings as they come and its error or summary line.
// Bad flag values are rejected (exit 2), never clamped; flags of the other
// target are rejected too rather than silently ignored. Outputs are written
// atomically, so a failure never leaves a file behind.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bake/cli/atlas_target.h"
#include "bake/cli/choice_option.h"
#include "bake/cli/commands.h"
#include "bake/cli/file_checks.h"
#include "bake/cli/geometry_flags.h"
#include "bake/cli/photo_target.h"
#include "bake/cli/progress_bar.h"
#include "bake/cli/proxy_for_mesh.h"
#include "bake/cli/texture_flags.h"
#include "mesh_io/file_name.h"
#include "texbake/texbake.h"

namespace texbake::cli {

namespace {

namespace fs = std::filesystem;

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
  AtlasFlags atlas;  // --target, --size, --padding, --uv, --format
  bool ascii = false;
  VertexFilter filter = VertexFilter::kArea;
  std::optional<int> samples;  // default: 16 (vertex, --filter area), 4 (atlas)
  Visibility visibility = Visibility::kFirst;
  KeywordOrColor occluded{"fill"};
  KeywordOrColor outside{"clamp"};
  std::optional<WrapMode> wrap;
  bool linear = false;
  TextureColorSpace texture_colorspace = TextureColorSpace::kAuto;
  std::size_t cache_mb = kDefaultCacheMb;
  std::string report;
  int threads = 0;
  bool quiet = false;
  PhotoFlags photos;                                  // --cameras, --images, --blend, --exposure
  std::string layers;                                 // --layers LAYERS.json
  const CLI::App* command = nullptr;                  // to ask which flags were given
  std::function<void(const std::string&)> on_report;  // CliHooks::on_report
};

// Parses "R,G,B" or "R,G,B,A", each a number in [0, 1] (texbake::parse_color).
// Throws CLI::ValidationError with the library's message, naming the flag (exit 2).
Rgba parse_color(const std::string& text, const std::string& flag) {
  Expected<Rgba> c = texbake::parse_color(text, flag);
  if (!c) throw CLI::ValidationError(c.error().message);
  return *c;
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

// "--a, --b" of the flags in `names` that were given on the command line.
std::vector<std::string> given_flags(const CLI::App& cmd, const std::vector<std::string>& names) {
  std::vector<std::string> given;
  for (const std::string& n : names) {
    if (cmd.count(n) > 0) given.push_back(n);
  }
  return given;
}

VertexBakeOptions shading_options(const BakeCliOptions& o) {
  VertexBakeOptions options;
  options.filter = o.filter;
  options.samples = o.samples.value_or(16);
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
  return options;
}

Status check_wrap(const BakeCliOptions& o, std::optional<ProxyKind> kind) {
  if (o.wrap && kind && *kind != ProxyKind::kPlane) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--wrap applies to the plane proxy only (the others' wrap is fixed)");
  }
  return ok_status();
}

// The geometry flags that make the proxy. --up also orients a .glb (its
// node matrix turns --up to glTF's +Y), so for a .glb output it is allowed
// where it is no geometry flag: with --proxy-file (the file holds the whole
// proxy) and with a kind without pole/axis/normal; there it is the GLB's
// alone. Elsewhere (a .ply or .obj) it stays the error it was.
GeometryFlags proxy_geometry(const GeometryFlags& flags, const fs::path& output) {
  GeometryFlags g = flags;
  if (lower_extension(output) != ".glb" || !g.up) return g;
  if (g.proxy_file) g.up.reset();
  if (g.kind) {
    const std::vector<std::string> allowed = flags_of_kind(*g.kind);
    if (std::find(allowed.begin(), allowed.end(), "--up") == allowed.end()) g.up.reset();
  }
  return g;
}

// Runs `job` (texbake/job.h) as the command line shows it: a progress bar
// on a terminal, warnings and the fit's line as they happen, the error or
// the summary line; returns the exit code.
int run_cli_job(Job& job, const BakeCliOptions& o) {
  job.report = o.report;
  job.threads = o.threads;
  job.cache_mb = o.cache_mb;
  ProgressBar bar(!o.quiet && ProgressBar::stderr_is_terminal());
  job.progress = bar.callback();
  job.on_warning = [](const std::string& w) { std::cerr << "texbake: warning: " << w << "\n"; };
  if (!o.quiet) job.on_note = [](const std::string& n) { std::cerr << "texbake: " << n << "\n"; };
  const JobResult result = run_job(job);
  if (!result.ok()) return report_error(*result.error);
  if (o.on_report) o.on_report(result.report);
  if (!o.quiet) {
    std::printf("%s\n", result.summary.c_str());
    std::fflush(stdout);
  }
  return 0;
}

// The occluded colour of --occluded R,G,B[,A] into the photo or layers
// bake's options (a keyword keeps their default, fill).
template <class Options>
void set_occluded(const BakeCliOptions& o, Options& options) {
  if (o.occluded.keyword.empty()) {
    options.occluded = OccludedMode::kColor;
    options.occluded_color = o.occluded.color;
  }
}

// bake --cameras: the photo flags against the projection flags and the
// target's (exit 2), then the job with Job::cameras (or Job::photo).
// With `camera` (a camera --proxy-file): the one photo --texture through
// that camera, seen up to 90 degrees (SPEC section 9's camera proxy).
int run_bake_photos(const BakeCliOptions& o, const CameraProjector* camera = nullptr) {
  const std::string what = camera ? "a camera --proxy-file" : "--cameras";
  std::vector<std::string> names = {"--filter", "--visibility", "--outside", "--wrap", "--linear"};
  if (!camera) names.insert(names.end(), {"--texture", "--proxy", "--proxy-file"});
  if (!given_flags(*o.command, {"--cache-mb"}).empty()) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--cache-mb does not apply to " + what +
                            " (photos are read whole, at most 16384 x 16384 pixels)");
  }
  const std::vector<std::string> projection = given_flags(*o.command, names);
  if (!projection.empty()) {
    return report_error(ErrorCode::kInvalidArgument,
                        projection.front() + " does not apply to " + what +
                            (camera ? " (the photo is sampled bilinearly through the lens "
                                      "model, in linear light, visible along the segment to "
                                      "the camera)"
                                    : " (the photos and their cameras are the projection)"));
  }
  for (const std::string& flag : given_geometry_flags(o.geometry)) {
    if (flag == "--up") continue;  // a .glb's node matrix
    return report_error(ErrorCode::kInvalidArgument, flag + " does not apply to " + what);
  }
  Expected<BakeTarget> target = resolve_target(o.atlas, o.output);
  if (!target) return report_error(target.error());
  const bool atlas = *target == BakeTarget::kAtlas;
  if (!atlas) {
    // The vertex photo bake samples each photo at the vertex itself.
    const std::vector<std::string> atlas_only =
        given_flags(*o.command, {"--samples", "--size", "--padding", "--uv", "--format"});
    if (!atlas_only.empty()) {
      return report_error(ErrorCode::kInvalidArgument,
                          atlas_only.front() + " applies to --target atlas only with " + what +
                              " (this bake's target is vertex, writing " + o.output + ")");
    }
  } else if (given_flags(*o.command, {"--ascii"}).size() > 0) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--ascii applies to --target vertex only (this bake's target is atlas, "
                        "writing " +
                            o.output + ")");
  }
  Job job;
  job.mesh = o.mesh;
  job.output = o.output;
  PhotoBakeOptions& options = job.photo_options;
  options.blend = o.photos.blend;
  options.exposure = o.photos.exposure.value_or(ExposureMode::kGain);
  options.strict_photos = o.photos.strict_photos;
  if (camera) {
    job.proxy_file = *o.geometry.proxy_file;
    job.texture = o.texture;
    job.photo = Photo{fs::path(o.texture).filename().string(), *camera, o.texture};
    options.exposure = ExposureMode::kNone;  // one photo: nothing to balance
    options.strict_photos = true;            // --texture itself: never left out
    options.color_space = o.texture_colorspace;
  } else {
    job.cameras = o.photos.cameras;
    job.images = o.photos.images;
    if (given_flags(*o.command, {"--texture-colorspace"}).size() > 0) {
      options.color_space = o.texture_colorspace;
    }
  }
  set_occluded(o, options);
  job.write = atlas_write_options(o.atlas);
  job.write.ascii = o.ascii;
  job.write.up = up_direction(o.geometry);
  if (atlas) {
    job.target = JobTarget::kAtlas;
    if (o.atlas.uv == UvLayout::kProxy) {
      return report_error(ErrorCode::kInvalidArgument, "--uv proxy needs a proxy, and " + what +
                                                           (camera ? " is a camera" : " has none") +
                                                           " (use --uv generate or --uv mesh)");
    }
    Expected<AtlasOptions> a = atlas_options(o.atlas, o.samples, VertexBakeOptions{}, o.output);
    if (!a) return report_error(a.error());
    job.atlas = *a;
  }
  return run_cli_job(job, o);
}

// bake --layers: the layers file holds every projection, so the flags of
// the single projection and of --cameras are usage errors (exit 2), then
// the job with Job::layers.
int run_bake_layers(const BakeCliOptions& o) {
  // --samples is the atlas's supersample count (the vertex target has none).
  const std::vector<std::string> projection = given_flags(
      *o.command, {"--texture", "--proxy", "--proxy-file", "--filter", "--samples", "--visibility",
                   "--outside", "--wrap", "--linear", "--texture-colorspace", "--cameras",
                   "--images", "--blend", "--exposure"});
  Expected<BakeTarget> target = resolve_target(o.atlas, o.output);
  const bool atlas = target && *target == BakeTarget::kAtlas;
  if (!projection.empty() &&
      !(atlas && projection.front() == "--samples" && projection.size() == 1)) {
    const std::string& flag =
        projection.front() == "--samples" && atlas ? projection[1] : projection.front();
    return report_error(ErrorCode::kInvalidArgument,
                        flag +
                            " does not apply to --layers (the layers file holds every "
                            "projection and its options)");
  }
  for (const std::string& flag : given_geometry_flags(o.geometry)) {
    if (flag == "--up") continue;  // a .glb's node matrix
    return report_error(ErrorCode::kInvalidArgument, flag + " does not apply to --layers");
  }
  if (!target) return report_error(target.error());
  const std::vector<std::string> wrong_target =
      atlas ? given_flags(*o.command, {"--ascii"})
            : given_flags(*o.command, {"--size", "--padding", "--uv", "--format"});
  if (!wrong_target.empty()) {
    return report_error(ErrorCode::kInvalidArgument,
                        wrong_target.front() + " applies to --target " +
                            (atlas ? "vertex" : "atlas") + " only (this bake's target is " +
                            (atlas ? "atlas" : "vertex") + ", writing " + o.output + ")");
  }
  Job job;
  job.mesh = o.mesh;
  job.layers = o.layers;
  job.output = o.output;
  set_occluded(o, job.layers_options);
  job.layers_options.strict_photos = o.photos.strict_photos;
  if (atlas) {
    if (o.atlas.uv == UvLayout::kProxy) {
      return report_error(ErrorCode::kInvalidArgument,
                          "--uv proxy needs a proxy, and --layers has none (use --uv generate "
                          "or --uv mesh)");
    }
    Expected<AtlasOptions> a = atlas_options(o.atlas, o.samples, VertexBakeOptions{}, o.output);
    if (!a) return report_error(a.error());
    job.target = JobTarget::kAtlas;
    job.atlas = *a;
    // Not given: the base texture's size (base "mesh"), else 2048.
    if (given_flags(*o.command, {"--size"}).empty()) job.atlas.bake.size = 0;
    job.write = atlas_write_options(o.atlas);
  }
  job.write.ascii = o.ascii;
  job.write.up = up_direction(o.geometry);
  return run_cli_job(job, o);
}

int run_bake(const BakeCliOptions& o) {
  if (!o.layers.empty()) return run_bake_layers(o);
  if (!o.photos.cameras.empty()) return run_bake_photos(o);
  if (const std::vector<std::string> photo_only =
          given_flags(*o.command, {"--images", "--blend", "--exposure", "--strict-photos"});
      !photo_only.empty()) {
    return report_error(ErrorCode::kInvalidArgument,
                        photo_only.front() + (photo_only.front() == "--strict-photos"
                                                  ? " applies to --cameras and --layers only"
                                                  : " applies to --cameras only"));
  }
  if (o.texture.empty()) {
    return report_error(
        ErrorCode::kInvalidArgument,
        "--texture is required (or --cameras to bake from photographs, or --layers)");
  }
  const GeometryFlags geometry = proxy_geometry(o.geometry, o.output);

  // ---- Usage checks (exit 2), before touching any file. ----
  if (Status s = check_geometry_flags(geometry, /*require_proxy=*/true); !s) {
    return report_error(s.error());
  }
  // A camera --proxy-file (SPEC section 9) bakes its photo like --cameras
  // with one photo.
  if (geometry.proxy_file) {
    Expected<Projector> projector = projector_from_flags(geometry);
    if (!projector) return report_error(projector.error());
    if (const CameraProjector* camera = as_camera(*projector)) {
      return run_bake_photos(o, camera);
    }
  }
  const fs::path output = o.output;
  Expected<BakeTarget> target = resolve_target(o.atlas, output);
  if (!target) return report_error(target.error());
  const bool atlas = *target == BakeTarget::kAtlas;
  const std::vector<std::string> wrong_target =
      atlas ? given_flags(*o.command, {"--ascii"})
            : given_flags(*o.command, {"--size", "--padding", "--uv", "--format"});
  if (!wrong_target.empty()) {
    return report_error(ErrorCode::kInvalidArgument,
                        wrong_target.front() + " applies to --target " +
                            (atlas ? "vertex" : "atlas") + " only (this bake's target is " +
                            (atlas ? "atlas" : "vertex") + ", writing " + o.output + ")");
  }
  WriteOptions write_options = atlas_write_options(o.atlas);
  write_options.ascii = o.ascii;
  write_options.up = up_direction(o.geometry);  // a .glb's node matrix
  if (!atlas) {
    if (Status s = validate_write(output, write_options, /*atlas=*/false); !s) {
      return report_error(s.error());
    }
  }
  if (atlas && o.command->count("--filter") > 0 && o.filter == VertexFilter::kArea) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--filter area applies to --target vertex only (the atlas takes bilinear "
                        "or ewa; this bake's target is atlas, writing " +
                            o.output + ")");
  }
  if (Status s = check_wrap(o, geometry.kind); !s) return report_error(s.error());
  VertexBakeOptions shading = shading_options(o);
  // The atlas's lookup: bilinear per supersample unless --filter ewa.
  if (atlas && shading.filter != VertexFilter::kEwa) shading.filter = VertexFilter::kBilinear;
  AtlasOptions atlas_opts;
  if (atlas) {
    Expected<AtlasOptions> a = atlas_options(o.atlas, o.samples, shading, output);
    if (!a) return report_error(a.error());
    atlas_opts = *a;
  } else if (Status s = validate_options(shading); !s) {
    return report_error(s.error());
  }
  // All geometry given (or a file): build and validate the proxy now, so a
  // bad value is reported before the long work. Otherwise the job fits it
  // to the mesh.
  std::optional<FlagsProxy> resolved;
  if (geometry.proxy_file || missing_geometry_flags(geometry, *geometry.kind).empty()) {
    Expected<Proxy> proxy = proxy_from_flags(geometry);
    if (!proxy) return report_error(proxy.error());
    resolved = FlagsProxy{std::move(*proxy), {}, {}};
    if (Status s = check_wrap(o, kind_of(params_of(resolved->proxy))); !s) {
      return report_error(s.error());
    }
  }

  // ---- The job (texbake/job.h): file checks, read, fit, bake, write. ----
  Job job;
  job.mesh = o.mesh;
  job.texture = o.texture;
  if (resolved) {
    job.proxy = std::move(resolved->proxy);
  } else {
    job.spec = spec_from_flags(geometry);
  }
  job.proxy_file = geometry.proxy_file.value_or("");
  job.naming = ParamNaming::kFlag;
  job.target = atlas ? JobTarget::kAtlas : JobTarget::kVertex;
  job.output = output;
  job.write = write_options;
  job.shading = shading;
  job.atlas = atlas_opts;
  job.texture_colorspace = o.texture_colorspace;
  return run_cli_job(job, o);
}

}  // namespace

RunFunction add_bake_command(CLI::App& app, const CliHooks& hooks) {
  auto o = std::make_shared<BakeCliOptions>();
  o->on_report = hooks.on_report;
  CLI::App* cmd = app.add_subcommand(
      "bake",
      "Bake an image onto a mesh through a proxy shape: per-vertex colours (--target vertex: "
      ".ply, .obj, .glb) or a texture atlas (--target atlas: .obj + .mtl + image, .glb). "
      "Geometry flags not given are fitted to the mesh (as texbake fit) and printed. With "
      "--cameras, calibrated photos take the place of --texture and the proxy, for either "
      "target (--uv generate or mesh for the atlas).");
  o->command = cmd;
  cmd->add_option("mesh", o->mesh, "input mesh (.obj, .ply, .off, .stl, .glb, .gltf)")->required();
  cmd->add_option("--texture", o->texture,
                  "image to bake (anything OpenImageIO reads); required unless --cameras");
  cmd->add_option("-o,--output", o->output,
                  "output: .ply (vertex colours), .obj (atlas: + .mtl + atlas image beside it; "
                  "vertex: v x y z r g b) or .glb (atlas embedded, or COLOR_0)")
      ->required();
  add_geometry_flags(*cmd, o->geometry);
  cmd->get_option("--up")->description(
      "the mesh's up axis: default pole/axis/normal, and for .glb output the axis the node "
      "matrix turns to glTF's +Y (vertex data unchanged); x, y, z, -x, -y or -z (default z)");

  add_atlas_flags(*cmd, o->atlas);
  cmd->add_flag("--ascii", o->ascii, "vertex target, .ply: ASCII instead of binary little-endian");

  add_choice_option<VertexFilter>(
      *cmd, "--filter", o->filter,
      "vertex: bilinear (sample at the vertex), area (average of --samples over "
      "the vertex's share of its triangles, default) or ewa (one elliptical "
      "weighted average over a MIP pyramid, sized by the vertex's share; a "
      "MIP-mapped texture file's own levels, as maketx writes them, are used); "
      "atlas: bilinear (default) or ewa (each supersample filtered by its "
      "footprint)");
  cmd->add_option_function<int>(
      "--samples",
      [o](int n) {
        // The vertex range (the library's message); an atlas's smaller one
        // is checked with the atlas options.
        if (Status s = check_range("--samples", n, 1, kMaxVertexSamples); !s) {
          throw CLI::ValidationError(s.error().message);
        }
        o->samples = n;
      },
      "vertex: samples per vertex for --filter area (default 16, 1..65536); atlas: "
      "supersamples per texel (default 4, 1..256)");

  add_choice_option<Visibility>(
      *cmd, "--visibility", o->visibility,
      "first: only what the projector sees is coloured (default); all: no test");
  add_keyword_or_color(*cmd, "--occluded", o->occluded, {"fill", "project"},
                       "occluded points: fill (smooth from visible neighbours, default), "
                       "project (projected colour anyway) or a colour R,G,B[,A] in [0,1]");
  add_keyword_or_color(*cmd, "--outside", o->outside, {"clamp"},
                       "points outside the proxy's (u,v) domain: clamp (edge texel, default) "
                       "or a colour R,G,B[,A] in [0,1]");
  add_choice_option<WrapMode>(*cmd, "--wrap", o->wrap,
                              "plane proxy only: clamp (default) or repeat (tile)");
  cmd->add_flag("--linear", o->linear,
                "interpolate and average in linear light (an sRGB texture; a linear one always "
                "is)");
  add_texture_colorspace_flag(*cmd, o->texture_colorspace, "--texture");
  add_cache_mb_flag(*cmd, o->cache_mb);
  add_photo_flags(*cmd, o->photos);
  cmd->add_option("--layers", o->layers,
                  "bake several projections composited over a base from a layers file (SPEC "
                  "section 10: base, and per layer proxy | proxy_file, texture, mask, opacity, "
                  "mode, angle_fade, visibility, outside) instead of --texture and a proxy "
                  "(vertex or atlas target; the atlas takes --size, --samples, --padding, "
                  "--uv generate|mesh|auto, --format)")
      ->type_name("LAYERS.json");
  cmd->add_option("--report", o->report, "write what was done as JSON to this file");
  cmd->add_option("--threads", o->threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  cmd->add_flag("-q,--quiet", o->quiet,
                "no progress bar, no fitted-proxy line, no summary (warnings still print)");
  return [o] { return run_bake(*o); };
}

}  // namespace texbake::cli
