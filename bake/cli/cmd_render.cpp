// texbake render MESH: a Phong-shaded, ray-traced preview (SPEC section 5;
// bake/render/render_preview.h has the camera, lighting and sampling conventions).
// Thin: parse -> options -> load -> (fit the geometry flags not given, as
// bake does) -> one render_mesh call (texbake/texbake.h) -> atomic write.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bake/cli/choice_option.h"
#include "bake/cli/commands.h"
#include "bake/cli/file_checks.h"
#include "bake/cli/geometry_flags.h"
#include "bake/cli/proxy_for_mesh.h"
#include "bake/cli/texture_flags.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/colmap_model.h"
#include "mesh_io/mesh_texture.h"
#include "texbake/texbake.h"

namespace texbake::cli {
namespace {

enum class ColorChoice { kAuto, kVertex, kAtlas, kNone };

struct RenderArgs {
  std::string mesh;
  std::string output;
  std::string size = "512x512";
  std::vector<double> view;  // AZ,EL
  int views = 1;
  bool shadows = false;
  int samples = kRenderSamples;
  int threads = 0;
  bool flat = false;
  std::vector<float> background;
  ColorChoice colors = ColorChoice::kAuto;
  std::string texture;
  std::string outside = "clamp";  // --outside clamp | R,G,B[,A]
  std::optional<WrapMode> wrap;   // --wrap clamp | repeat (plane proxy only)
  TextureColorSpace texture_colorspace = TextureColorSpace::kAuto;
  std::size_t cache_mb = kDefaultCacheMb;
  GeometryFlags geometry;
  bool unlit = false;
  std::string colmap;  // --colmap DIR: each view a photo of a COLMAP workspace
};

// "WxH" with integers (their range: validate_options).
std::optional<std::pair<int, int>> parse_size(const std::string& s) {
  int w = 0, h = 0;
  char x = 0, extra = 0;
  if (std::sscanf(s.c_str(), "%d%c%d%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) {
    return std::nullopt;
  }
  return std::make_pair(w, h);
}

std::filesystem::path default_output(const std::string& mesh) {
  return std::filesystem::path(mesh).stem().string() + "_render.png";
}

// --colmap DIR: the --views views, each as one photo DIR/images/view_NN.png
// of a COLMAP PINHOLE camera (pinhole_of_view), with the model in
// DIR/sparse/0/ (text): the layout `bake --cameras DIR/sparse/0` reads.
// Photos and model are one atomic set (mesh_io/atomic_file.h), which also
// removes an earlier binary model there: all of it appears, or nothing.
int render_workspace(const MeshData& mesh, const ColorSource& source, const RenderOptions& options,
                     const RunOptions& run, const RenderArgs& args) {
  const std::filesystem::path dir = args.colmap;
  Expected<BoundingSphere> bounds = bounding_sphere(mesh);
  if (!bounds) return report_mesh_error(bounds.error(), args.mesh);
  for (const std::filesystem::path& sub : {dir / "images", dir / "sparse" / "0"}) {
    std::error_code ec;
    std::filesystem::create_directories(sub, ec);
    if (ec)
      return report_error(ErrorCode::kIo, "cannot create " + sub.string() + ": " + ec.message());
  }
  AtomicFileSet set;
  ImageWriteOptions photo_options;
  photo_options.file_set = &set;
  std::vector<ColmapImage> images;
  for (int k = 0; k < options.views; ++k) {
    RenderOptions view = options;
    view.views = 1;
    view.azimuth_deg = options.azimuth_deg + k * 360.0 / options.views;
    Expected<Rendered> rendered = render_mesh(mesh, source, view, run);
    if (!rendered) return report_mesh_error(rendered.error(), args.mesh);
    const std::string name = colmap_view_name(k);
    if (Status st = write_image(dir / "images" / name, rendered->image.view(), photo_options); !st)
      return report_error(st.error());
    Expected<Camera> camera = make_camera(*bounds, view, view.azimuth_deg);
    if (!camera) return report_error(camera.error());
    images.push_back({static_cast<uint32_t>(k + 1), 1, name, pinhole_of_view(*camera)});
  }
  if (Status st = write_colmap_model(dir / "sparse" / "0", images, /*binary=*/false, &set); !st) {
    return report_error(st.error());
  }
  if (Status st = set.commit(); !st) return report_error(st.error());
  std::printf("rendered %d views as a COLMAP workspace: %s (images/, sparse/0/)\n", options.views,
              dir.string().c_str());
  return 0;
}

int run_render(const RenderArgs& args) {
  RenderOptions options;
  const auto size = parse_size(args.size);
  if (!size) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--size: expected WxH with positive integers up to " +
                            std::to_string(kMaxRenderSize) + ", got '" + args.size + "'");
  }
  options.width = size->first;
  options.height = size->second;
  if (!args.view.empty()) {
    options.azimuth_deg = args.view[0];
    options.elevation_deg = args.view[1];
  }
  options.views = args.views;
  options.shadows = args.shadows;
  options.samples_per_pixel = args.samples;
  options.smooth_normals = !args.flat;
  options.up = up_direction(args.geometry);
  if (args.unlit) {  // the colour source's albedo as it is: photos of a bake's ground truth
    options.phong.ambient = 1;
    options.phong.key_diffuse = options.phong.fill_diffuse = 0;
    options.phong.key_specular = options.phong.fill_specular = 0;
  }
  if (!args.colmap.empty() && !args.output.empty()) {
    return report_error(ErrorCode::kInvalidArgument,
                        "-o does not apply to --colmap (the views go to DIR/images/)");
  }
  if (!args.background.empty()) {
    for (int c = 0; c < 3; ++c) options.background[c] = args.background[c];
  }
  // The library's checks and messages (texbake::validate_options).
  if (Status st = validate_options(options); !st) return report_error(st.error());

  // --texture and --proxy/--proxy-file go together: direct projection.
  const bool projecting = args.geometry.kind || args.geometry.proxy_file;
  if (projecting != !args.texture.empty()) {
    return report_error(ErrorCode::kInvalidArgument,
                        projecting ? "--proxy/--proxy-file needs --texture IMG"
                                   : "--texture needs --proxy KIND or --proxy-file F");
  }
  // --up also orients the camera, so it is the one geometry flag allowed
  // without a projection.
  std::vector<std::string> geometry = given_geometry_flags(args.geometry);
  std::erase(geometry, std::string("--up"));
  if (!projecting && (!geometry.empty() || args.outside != "clamp")) {
    return report_error(ErrorCode::kInvalidArgument,
                        "geometry flags and --outside need --texture and --proxy");
  }
  if (args.wrap && !projecting) {
    return report_error(ErrorCode::kInvalidArgument, "--wrap needs --texture and --proxy plane");
  }
  std::optional<Rgba> outside;
  if (args.outside != "clamp") {
    Expected<Rgba> color = parse_color(args.outside, "--outside");
    if (!color) return report_error(color.error());
    outside = *color;
  }
  // A complete proxy (all geometry flags, or a file) is validated now;
  // missing geometry flags are fitted to the mesh once it is loaded.
  std::optional<Proxy> proxy;
  std::optional<CameraProjector> camera;  // a camera --proxy-file (SPEC section 9)
  // --up also orients the camera, so with --proxy-file (which holds the whole
  // proxy) it is the camera's alone, not a geometry flag.
  GeometryFlags projection = args.geometry;
  if (projection.proxy_file) projection.up.reset();
  if (projecting) {
    if (Status st = check_geometry_flags(projection, /*require_proxy=*/true); !st) {
      return report_error(st.error());
    }
    if (projection.proxy_file || missing_geometry_flags(projection, *projection.kind).empty()) {
      auto p = projector_from_flags(projection);
      if (!p) return report_error(p.error());
      if (const CameraProjector* c = as_camera(*p)) {
        camera = *c;
      } else {
        proxy = *as_proxy(*p);
      }
    }
    if (camera && args.wrap) {
      return report_error(ErrorCode::kInvalidArgument,
                          "--wrap applies to the plane proxy only (a camera's photo clamps)");
    }
    if (!camera && args.wrap &&
        (proxy ? kind_of(*proxy) : *args.geometry.kind) != ProxyKind::kPlane) {
      return report_error(ErrorCode::kInvalidArgument,
                          "--wrap applies to the plane proxy only (the others' wrap is fixed)");
    }
  }

  const std::filesystem::path output =
      args.output.empty() ? default_output(args.mesh) : std::filesystem::path(args.output);
  // No output (the image, or the --colmap workspace's views and model) may
  // be an input.
  JobFileNames files;
  files.mesh = args.mesh;
  files.texture = args.texture;
  files.proxy_file = args.geometry.proxy_file.value_or("");
  if (args.colmap.empty()) files.output = output;
  const std::vector<NamedFile> written =
      args.colmap.empty() ? job_outputs(files) : colmap_workspace_files(args.colmap, args.views);
  if (Status st = check_distinct_files(job_inputs(files), written); !st) {
    return report_error(st.error());
  }
  if (args.colmap.empty()) {
    if (Status st = check_writable(output); !st) return report_error(st.error());
  }
  RunOptions run;
  run.threads = args.threads;

  auto loaded = read_mesh(args.mesh, run);
  if (!loaded) return report_error(loaded.error());
  const MeshData& mesh = loaded->mesh;
  // Nothing to render is the mesh's problem, reported before a fit's.
  if (Status st = check_triangles(mesh); !st) return report_mesh_error(st.error(), args.mesh);
  if (projecting && !proxy && !camera) {
    auto fitted = proxy_for_mesh(projection, mesh, args.mesh, &std::cerr, run);
    if (!fitted) return report_error(fitted.error());
    proxy = std::move(fitted->proxy);
  }

  // The colour source: --texture/--proxy, else the mesh's own atlas or
  // vertex colours (--colors picks one), else grey.
  ColorSource source = GreySource{};
  Image texture;
  const bool has_atlas = mesh.has_uvs() && mesh.has_texture();
  ColorChoice choice = args.colors;
  if (proxy || camera) {
    auto img = read_image(
        args.texture, texture_read_options(args.texture_colorspace, args.cache_mb, false, false));
    if (!img) return report_error(img.error());
    warn_image(*img, args.texture);
    texture = std::move(img).value();
    if (camera) {
      const CameraSpec& spec = camera->spec();
      const PhotoFit fit = photo_fit(spec, texture.width, texture.height);
      const std::string sizes = std::to_string(texture.width) + " x " +
                                std::to_string(texture.height) + ", its camera " +
                                std::to_string(spec.width) + " x " + std::to_string(spec.height);
      if (fit == PhotoFit::kWrong) {
        return report_error(ErrorCode::kParse, args.texture + ": the photo is " + sizes +
                                                   " (neither that size nor that aspect)");
      }
      if (fit == PhotoFit::kScaled) {
        std::cerr << "texbake: warning: " << args.texture << ": the photo is " << sizes
                  << "; sampled at the camera's (u, v)\n";
      }
      source = CameraProjectionSource{*camera, texture.view(), outside};
    } else {
      source =
          ProjectionSource{*proxy, texture.view(), outside, args.wrap.value_or(WrapMode::kClamp)};
    }
    choice = ColorChoice::kNone;  // handled
  } else if (choice == ColorChoice::kAuto) {
    choice = has_atlas                  ? ColorChoice::kAtlas
             : mesh.has_vertex_colors() ? ColorChoice::kVertex
                                        : ColorChoice::kNone;
  }
  if (choice == ColorChoice::kAtlas) {
    if (!has_atlas) {
      return report_error(ErrorCode::kInvalidArgument,
                          "--colors atlas: '" + args.mesh + "' has no UVs with a texture");
    }
    // The mesh's own texture is an input too: no output may overwrite it.
    if (Status st = check_distinct_files({{"the texture of MESH", mesh.texture_path}}, written);
        !st) {
      return report_error(st.error());
    }
    // The file's own texture: an image file (OBJ map_Kd, a .gltf's URI) or
    // one embedded in a .glb / .gltf (mesh_io/mesh_texture.h).
    auto img = read_mesh_texture(mesh, {args.texture_colorspace});
    if (!img) return report_error(img.error());
    const std::string name = mesh_texture_label(mesh);
    warn_image(*img, name);
    if (loaded->issues.other_material_primitives > 0) {
      std::cerr << "texbake: warning: " << args.mesh << ": "
                << loaded->issues.other_material_primitives
                << " primitives have another material than the first; they are drawn with its "
                   "texture\n";
    }
    texture = std::move(img).value();
    source = AtlasSource{texture.view()};
  } else if (choice == ColorChoice::kVertex) {
    if (!mesh.has_vertex_colors()) {
      return report_error(ErrorCode::kInvalidArgument,
                          "--colors vertex: '" + args.mesh + "' has no vertex colours");
    }
    source = VertexColorSource{};
  }

  if (!args.colmap.empty()) return render_workspace(mesh, source, options, run, args);
  Expected<Rendered> rendered = render_mesh(mesh, source, options, run);
  if (!rendered) return report_mesh_error(rendered.error(), args.mesh);
  // sRGB-encoded pixels, encoded for the output's format (PNG sRGB, EXR linear).
  ImageWriteOptions wo;
  wo.encode_for_format = true;
  if (Status st = write_image(output, rendered->image.view(), wo); !st) {
    return report_error(st.error());
  }
  return 0;
}

}  // namespace

RunFunction add_render_command(CLI::App& app) {
  auto args = std::make_shared<RenderArgs>();
  CLI::App* cmd = app.add_subcommand(
      "render",
      "Phong-shaded ray-traced preview of a mesh (Embree). Colours: --texture/--proxy (direct "
      "projection, the ground truth of a bake), else the mesh's atlas or vertex colours, else "
      "grey. Background pixels get alpha 0.");
  cmd->add_option("MESH", args->mesh, "mesh file (OBJ, PLY, OFF, STL, glTF .glb/.gltf)")
      ->required();
  cmd->add_option("-o,--output", args->output,
                  "output image (PNG, or any format by extension; default: "
                  "<mesh name>_render.png in the current folder)");
  cmd->add_option("--size", args->size, "WxH pixels of each view")->capture_default_str();
  cmd->add_option("--view", args->view,
                  "AZ,EL: azimuth (degrees, counter-clockwise seen from above; 0 looks from -Y "
                  "for --up z, from +Z for --up y) and elevation above the horizon in [-90, 90] "
                  "(default 0,20)")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--views", args->views,
                  "contact sheet of N views at evenly spaced azimuths, in a grid (1..64)")
      ->capture_default_str();
  cmd->add_flag("--shadows", args->shadows, "shadow rays towards the key light");
  cmd->add_option("--samples", args->samples, "jittered samples per pixel (antialiasing, 1..1024)")
      ->capture_default_str();
  cmd->add_option("--threads", args->threads, "worker threads (0 = all cores)")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option(
      "--texture", args->texture,
      "image projected through --proxy/--proxy-file onto every hit (no visibility "
      "test): the ground truth a bake is compared with; with a camera --proxy-file, its "
      "photo. Geometry flags not given are fitted to the mesh, as in texbake bake");
  cmd->add_option("--outside", args->outside,
                  "points outside the proxy's (u, v) domain: clamp (to the edge texel) or "
                  "R,G,B[,A] in [0, 1]; a camera's points off its photo or behind it are grey "
                  "unless R,G,B[,A] is given")
      ->capture_default_str();
  add_choice_option<WrapMode>(
      *cmd, "--wrap", args->wrap,
      "plane proxy only: clamp (default) or repeat (tile), as in texbake bake");
  add_texture_colorspace_flag(*cmd, args->texture_colorspace,
                              "the texture read (--texture, or the mesh's own atlas)");
  add_cache_mb_flag(*cmd, args->cache_mb);
  add_geometry_flags(*cmd, args->geometry);
  cmd->add_flag("--flat", args->flat, "flat shading (geometric normals)");
  cmd->add_flag("--unlit", args->unlit,
                "no lighting: each pixel is the colour source's albedo (photos for "
                "bake --cameras)");
  cmd->add_option("--colmap", args->colmap,
                  "write each of the --views views as a photo of a COLMAP workspace: "
                  "DIR/images/view_NN.png and the PINHOLE cameras in DIR/sparse/0/ (text; an "
                  "earlier binary model there is removed), which bake --cameras DIR/sparse/0 "
                  "reads; written all together or not at all");
  cmd->add_option("--background", args->background, "R,G,B background in [0, 1]")
      ->delimiter(',')
      ->expected(3);
  add_choice_option<ColorChoice>(
      *cmd, "--colors", args->colors,
      {{"auto", ColorChoice::kAuto},
       {"vertex", ColorChoice::kVertex},
       {"atlas", ColorChoice::kAtlas},
       {"none", ColorChoice::kNone}},
      "colour source without --texture: auto (atlas, else vertex colours, "
      "else grey), vertex, atlas or none");
  return [args] { return run_render(*args); };
}

}  // namespace texbake::cli
