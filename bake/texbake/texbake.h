// texbake's public API (SPEC section 11): the one header another program
// includes. Every job of the command line is one call here; the `texbake`
// executable (bake/cli/) is a thin client of exactly these functions.
//
//   #include <texbake/texbake.h>
//   auto mesh  = texbake::read_mesh("bunny.off");          // Expected<LoadedMesh>
//   auto image = texbake::read_image("earth.jpg");         // Expected<Image>, sRGB
//   texbake::ProxySpec spec{texbake::ProxyKind::kSphere};  // nothing given:
//   auto proxy = texbake::complete_proxy(spec, mesh->mesh);  //   all fitted
//   auto baked = texbake::bake_vertex_colors(mesh->mesh, image->view(), proxy->proxy);
//   texbake::write_vertex_colors("bunny.ply", mesh->mesh, baked->colors);
//
// Conventions of every function here:
//  - Errors are values (Expected<T> / Status, mapping/error.h), never
//    exceptions. category(error) says whose fault it is: kUsage (a bad
//    option or parameter: the caller's), kInput (a file or its content, a
//    mesh the job cannot work on), kInternal (a library failed), kCancelled
//    (the progress callback returned false). Messages name the file, line,
//    key or option, as the CLI prints them after "texbake: error: ".
//  - Options are plain structs whose defaults are the CLI's defaults.
//    Options are validated before any long work (usage errors first).
//  - RunOptions (last argument) carries the thread count for this call
//    (a tbb::task_arena of that many threads; 0 = all cores; results never
//    depend on it) and an optional progress callback.
//  - Every result carries Stats: counts and per-stage timings in seconds
//    (the CLI's --report is built from them), and warnings (not printed).
//  - Nothing is printed to stdout or stderr.
//  - Writers are atomic: a file appears complete under its name or not at
//    all (a textured OBJ's OBJ + MTL + image set included).
//
// The types used here come from the headers included below (all installed
// with this one): MeshData (mesh_io/mesh_data.h), Image / ImageView,
// Proxy / ProxyParams / make_proxy / inverse_map (mapping/proxy.h),
// ProxySpec (mapping/proxy_schema.h), the bake options (bake/shade/options.h,
// bake/engine/bake_atlas.h), the UV layout choice (bake/uv/uv_layout.h) and
// the render options and colour sources (bake/render/render_preview.h).
//
// Colour spaces (issue #11; README "Colour spaces"): read_image reports the
// texture's (Image::color_space, ImageReadOptions::color_space overrides it:
// TextureColorSpace, --texture-colorspace), and an ImageView carries it
// into the bakes: an sRGB texture is sampled as stored (or in linear light
// with `linear`), a linear one in linear light. Every colour a bake returns
// (VertexColors::colors, Atlas::image) is sRGB-encoded, whatever the input;
// the writers encode for their format: PLY and OBJ vertex colours and PNG
// atlases sRGB, GLB COLOR_0 and EXR atlases linear.
//
// Errors about the mesh (kInput from bake_vertex_colors, bake_atlas_texture,
// render_mesh and check_triangles) do not name a file: the API never sees
// the mesh's path. A caller that read the mesh from a file prefixes its name
// (the CLI prints "texbake: error: MESH: all 3 triangles are degenerate").
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "bake/atlas/atlas_raster.h"  // kMaxAtlasSize, kMaxAtlasSamples
#include "bake/engine/bake_atlas.h"
#include "bake/engine/layers_bake.h"
#include "bake/engine/photo_atlas.h"
#include "bake/engine/photo_vertex.h"
#include "bake/fit/model_alignment.h"
#include "bake/photo/camera_check.h"
#include "bake/photo/photo_bake.h"
#include "bake/photo/pose_refine.h"
#include "bake/render/render_preview.h"
#include "bake/shade/options.h"
#include "bake/uv/uv_layout.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mapping/proxy_schema.h"
#include "mesh_io/image_compare.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"
#include "mesh_io/mesh_texture.h"  // read_mesh_texture: an OBJ's map_Kd, a glTF's base colour
#include "mesh_io/proxy_json.h"
#include "mesh_io/read_mesh.h"

namespace texbake {

// ---- Errors ---------------------------------------------------------------

enum class ErrorCategory {
  kUsage,      // bad option or parameter (CLI exit 2)
  kInput,      // a file, its content, or a mesh the job cannot work on (exit 1)
  kInternal,   // a library failed unexpectedly (exit 1)
  kCancelled,  // the progress callback asked to stop (exit 1)
};
ErrorCategory category(const Error& error);

// The library's version, "MAJOR.MINOR.PATCH".
const char* version();

// ---- Running --------------------------------------------------------------

// Called from the calling thread or a worker, never concurrently with itself,
// at most about every percent of a stage: `stage` names it ("uv_layout",
// "bake", "fill", "sample", "render", ...) and `fraction` runs 0 -> 1 within
// it. Returning false cancels: the call returns an error of category
// kCancelled soon after, having written nothing.
using ProgressCallback = std::function<bool(std::string_view stage, double fraction)>;

struct RunOptions {
  int threads = 0;            // worker threads for this call; 0 = all cores
  ProgressCallback progress;  // may be empty
};

// ---- Stats ----------------------------------------------------------------

struct Counts {
  std::size_t vertices = 0;
  std::size_t triangles = 0;             // non-degenerate triangles
  std::size_t degenerate_triangles = 0;  // left out of tracing and charts
  std::size_t unreferenced_vertices = 0;
  std::size_t samples = 0;         // sample points mapped (vertex) / supersamples (atlas)
  std::size_t occluded = 0;        // vertices (vertex target) or samples (atlas) occluded
  std::size_t undefined = 0;       // ... without a mapping
  std::size_t outside = 0;         // samples outside the proxy's (u, v) domain
  std::size_t filled = 0;          // vertex: coloured by the occlusion fill
  std::size_t unfilled = 0;        // vertex: fill-bound, in a component with no visible vertex
  std::size_t texels = 0;          // atlas: covered texels
  std::size_t border_samples = 0;  // atlas: samples clamped onto a triangle
  std::size_t padded = 0;          // atlas: texels filled by padding
};

struct Timings {  // seconds; 0 for stages a job did not run
  double fit = 0;
  double uv_layout = 0;
  double rasterize = 0;
  double scene_build = 0;
  double bake = 0;  // vertex: mapping, visibility, sampling; atlas: the samples
  double fill = 0;
  double pad = 0;
  double render = 0;
  double total = 0;  // the whole call
};

struct Stats {
  Counts counts;
  Timings timings;
  std::vector<std::string> warnings;  // e.g. "12 UV corners lie outside [0, 1] ..."
  // What the call did that the user must know, not a fault: e.g. a camera
  // file reader's "transforms.json: applied_transform undone ..." (a layers
  // bake's cameras layers). The command line prints them unless --quiet.
  std::vector<std::string> notes;
};

// ---- Proxies --------------------------------------------------------------

struct CompletedProxy {
  Proxy proxy;
  // Keys of the fields filled by fitting (e.g. {"center", "radius"}), in the
  // kind's field order; empty when the spec was complete.
  std::vector<std::string> fitted;
  std::size_t points = 0;  // vertices the fit used (0 when nothing was fitted)
  Stats stats;             // timings.fit (0 when nothing was fitted)
};

// The proxy of `spec`, every field not given fitted to the mesh's referenced
// vertices (SPEC section 6, bake/fit/fit_proxy.h): a given direction is the
// fit's fixed direction, with its sign; without one, spec.up fixes a
// cylinder's or cone's axis line and is the sphere's pole; a given anchor
// (sphere/disk centre, cylinder base, cone apex, plane origin) and a cone's
// height are kept and the rest is fitted around them; other given values
// replace the fitted ones. A complete spec is validated and returned without
// looking at the mesh. Errors: kUsage (a given value is invalid, e.g. a zero
// axis, naming the key, or the CLI flag with naming = ParamNaming::kFlag),
// kInput (the mesh cannot be fitted, e.g. all points coincident).
// The rules: bake/fit/complete_proxy.h (complete_spec).
Expected<CompletedProxy> complete_proxy(const ProxySpec& spec, const MeshData& mesh,
                                        const RunOptions& run = {},
                                        ParamNaming naming = ParamNaming::kKey);

// ---- Option values (every client's checks) --------------------------------
//
// The command line, batch and Python spell an option each their own way
// (--samples 0, "samples": 0, samples=0) but check it here, so a bad value
// gets one message naming the option by its CLI flag, whoever gave it
// (kUsage). The option structs hold the defaults; the tables below hold
// the names of the keyword values; the checks hold the ranges.

// The names of an enum option's values, in --help's order: choices(E{})
// for VertexFilter (--filter), Visibility (--visibility), WrapMode
// (--wrap), UvLayout (--uv), AtlasFormat (--format), PhotoBlend (--blend),
// ExposureMode (--exposure), TextureColorSpace (--texture-colorspace).
template <class E>
struct Choice {
  const char* name;
  E value;
};
std::span<const Choice<VertexFilter>> choices(VertexFilter);
std::span<const Choice<Visibility>> choices(Visibility);
std::span<const Choice<WrapMode>> choices(WrapMode);
std::span<const Choice<UvLayout>> choices(UvLayout);
enum class AtlasFormat;
std::span<const Choice<AtlasFormat>> choices(AtlasFormat);
std::span<const Choice<PhotoBlend>> choices(PhotoBlend);
std::span<const Choice<ExposureMode>> choices(ExposureMode);
std::span<const Choice<TextureColorSpace>> choices(TextureColorSpace);

// "FLAG: unknown value 'TEXT' (expected a, b or c)" for `names`.
Error unknown_choice(std::string_view flag, std::string_view text,
                     std::span<const char* const> names);

// The value named `text` among choices(E{}); kUsage unknown_choice otherwise.
template <class E>
Expected<E> parse_choice(std::string_view text, std::string_view flag) {
  std::vector<const char*> names;
  for (const Choice<E>& c : choices(E{})) {
    if (text == c.name) return c.value;
    names.push_back(c.name);
  }
  return unknown_choice(flag, text, names);
}

// The name of `value` in choices(E{}).
template <class E>
const char* choice_name(E value) {
  for (const Choice<E>& c : choices(E{})) {
    if (c.value == value) return c.name;
  }
  return "";
}

inline constexpr std::size_t kMaxCacheMb = std::size_t{1} << 24;  // --cache-mb
inline constexpr int kMaxThreads = 4096;                          // --threads
inline constexpr int kMaxRenderSize = 32768;                      // render --size, per side
inline constexpr int kMaxRenderViews = 64;                        // render --views
inline constexpr int kMaxRenderSamples = 1024;                    // render --samples
inline constexpr int kRenderSamples = 4;  // render --samples' default (RenderOptions' is 1)

// "FLAG VALUE is out of range (LO .. HI)" unless lo <= value <= hi.
Status check_range(std::string_view flag, long long value, long long lo, long long hi);

// --cache-mb: 1 .. kMaxCacheMb MiB.
Status check_cache_mb(long long cache_mb);

// A colour of 3 or 4 components (alpha = false: exactly 3), each in [0, 1]:
// "FLAG: 'C' is not a colour R,G,B[,A] with components in [0, 1] (e.g. 1,0,0
// for red)", C the components as given (the text, or the numbers with %g).
Expected<Rgba> color_from_components(std::span<const double> components, std::string_view flag,
                                     bool alpha = true);
// The same from the CLI's text "R,G,B[,A]" (numbers separated by commas).
Expected<Rgba> parse_color(std::string_view text, std::string_view flag, bool alpha = true);

// --padding as text: "" (kPaddingDefault), "inf" (kPaddingInfinite) or a
// texel count 0 .. kMaxAtlasSize: "--padding 'T' is not a texel count (0 ..
// 16384) or 'inf'" otherwise.
Expected<int> parse_padding(std::string_view text);

// texbake render's options: --size (1 .. kMaxRenderSize per side), --views
// (1 .. kMaxRenderViews), --samples (1 .. kMaxRenderSamples), --view (a
// finite azimuth, an elevation in [-90, 90]), --up (finite, not zero) and
// --background (components in [0, 1]). render_mesh checks them first.
Status validate_options(const RenderOptions& options);

// texbake compare's --background (components in [0, 1]).
Status validate_options(const CompareOptions& options);

// The photo bakes' --occluded colour (components in [0, 1]) and
// max_view_angle_deg in (0, 90]; the photo bakes check them first.
Status validate_options(const PhotoBakeOptions& options);

// The layers bakes' --occluded and base colours (components in [0, 1]);
// the layers bakes check them first. cache_mb 0 (decoded whole) is the
// API's; the CLI's --cache-mb is check_cache_mb's range.
Status validate_options(const LayersBakeOptions& options);

// ---- Large textures (SPEC section 13) -------------------------------------

// How a bake reads its texture with the memory budget `cache_mb` (MiB,
// --cache-mb; 0: always decoded whole): the colour space rule and the float
// RGBA copies the bake holds besides the image (a linear working copy with
// `linear`, a MIP pyramid's third with `ewa`), past which read_image reads
// the texture in tiles through OpenImageIO's ImageCache (mesh_io/image_io.h).
// `ewa`: also read a MIP-mapped file's own levels (Image::mip), which
// --filter ewa then uses instead of reducing the image (mapping/mipmap.h).
ImageReadOptions texture_read_options(TextureColorSpace color_space, std::size_t cache_mb,
                                      bool linear, bool ewa);

// --filter ewa on a texture read through the cache builds its MIP levels
// above the full size in memory (mapping/mipmap.h), a third of the image's
// float RGBA size: kUsage naming the sizes and --cache-mb when they exceed
// `cache_mb`; ok for an image in memory, and for a MIP-mapped file whose
// levels are read through the cache too (unless `linear` on an sRGB
// texture, whose linear-light levels are built).
Status check_ewa_budget(const Image& image, std::size_t cache_mb, bool linear = false);

// ---- Vertex colours -------------------------------------------------------

// What a bake gives per vertex, whatever it projects (bake_vertex_colors
// over a Bake, below); the fields of the other kinds of bake stay empty.
struct VertexColors {
  // One per vertex, input order, RGBA in [0, 1], sRGB-encoded (layers:
  // straight alpha = coverage).
  std::vector<Rgba> colors;
  Stats stats;
  // Photographs: per photo used, in view, visible, weight share and gains;
  // the photos left out (cannot be read; also warnings); how well the
  // photos agree (bake/photo/photo_bake.h).
  std::vector<PhotoCameraStats> cameras;
  std::vector<SkippedPhoto> skipped;
  PhotoConsistency consistency;
  // Layers: per layer, in domain, visible, blended, mean alpha, lookups.
  std::vector<LayerStats> layers;
};

// The most samples per vertex of VertexFilter::kArea.
inline constexpr int kMaxVertexSamples = 65536;

// SPEC sections 3 and 4, per vertex (the contract of bake/engine/bake_vertex.h).
// Errors: kUsage (options out of range, an image without pixels), kInput (a
// mesh with no non-degenerate triangle: see check_triangles), kInternal,
// kCancelled. Progress stages: "bake" (per vertex), "fill".
Expected<VertexColors> bake_vertex_colors(const MeshData& mesh, const ImageView& image,
                                          const Proxy& proxy, const VertexBakeOptions& options = {},
                                          const RunOptions& run = {});

// The same, taking the image over: it is released as soon as nothing reads
// it any more (before the occlusion fill's solve, the memory peak).
Expected<VertexColors> bake_vertex_colors(const MeshData& mesh, Image&& image, const Proxy& proxy,
                                          const VertexBakeOptions& options = {},
                                          const RunOptions& run = {});

// The option checks bake_vertex_colors makes first, for callers that check
// before loading anything. kUsage naming the option by its CLI flag:
// --samples outside 1 .. kMaxVertexSamples (kArea only), a colour component
// outside [0, 1].
Status validate_options(const VertexBakeOptions& options);

// ---- Photographs (SPEC section 9) -----------------------------------------

// Whether read_cameras must find the photos' folder: kNeeded for a bake;
// kNotNeeded for what needs only the poses and photo sizes, which the model
// holds (texbake cameras check): Photo::path is then the image name as
// stored when no folder is found.
enum class PhotoFolder { kNeeded, kNotNeeded };

// The cameras of `cameras` with their photos: a COLMAP sparse model folder
// (cameras.txt + images.txt or the .bin pair, mesh_io/colmap_model.h) or a
// camera file of any format mesh_io/camera_formats.h reads (texbake's JSON
// camera list, nerfstudio / instant-ngp transforms.json, Metashape
// cameras.xml, Meshroom / AliceVision .sfm), told by its
// content. Photos are looked up in `images` when given; otherwise, for a
// COLMAP model, in the `images` folder of the workspace whose `sparse/`
// holds the model (COLMAP's layout: W/sparse/0 -> W/images), and for a
// camera file relative to the file's folder. The photos are not opened
// here: the bakes read them one at a time, and leave out those that cannot
// be read (PhotoBakeOptions::strict_photos). `notes`, when given, receives
// what the reader did that the user must know (a nerfstudio file's
// applied_transform undone), one sentence each. Errors: kInput (the model
// or file), kUsage (kNeeded and no images folder can be found: give one).
Expected<std::vector<Photo>> read_cameras(const std::filesystem::path& cameras,
                                          const std::filesystem::path& images = {},
                                          PhotoFolder need = PhotoFolder::kNeeded,
                                          std::vector<std::string>* notes = nullptr);

// The mask of the photo named `name` (Photo::name, the image name as the
// model gives it) in the folder `masks`, by COLMAP's convention:
// masks/<name>.png (its extension and any subfolder kept:
// masks/IMG_1.jpg.png), else, as COLMAP 3.10 on also looks,
// masks/<name with its extension replaced by .png> (masks/IMG_1.png); empty
// when neither file exists.
std::filesystem::path mask_file(const std::filesystem::path& masks, const std::string& name);

// Sets Photo::mask of every photo whose mask_file exists in `masks`
// (`--masks DIR`; the bakes then weigh the photo by it, see
// bake/photo/photo_bake.h "Masks"). A photo without a mask file is used
// whole, as COLMAP up to 3.9 extracts its features (3.10 on skips it), and
// is counted in one warning added to `warnings`: "LABEL DIR: no mask for K
// of N photos (the first: NAME, looked for DIR/NAME.png): used whole".
// Errors (kInput, starting "LABEL DIR: "): the folder does not exist or is
// not a folder; no photo has a mask file (naming the first file looked
// for, as is surely a wrong folder or naming). `label` names the option
// ("--masks", "layers[1].masks").
Status find_masks(std::vector<Photo>& photos, const std::filesystem::path& masks,
                  const std::string& label, std::vector<std::string>* warnings = nullptr);

// A camera proxy file (SPEC section 9: a proxy file of "kind": "camera")
// and its photo as the one-photo list of the photo bakes, which take it
// with camera_proxy_options: `texbake bake MESH --texture PHOTO
// --proxy-file CAMERA`. The photo is read by the bake. Errors: kInput (the
// file or its content, naming it and the key), kUsage (the file holds an
// analytic proxy: bake_vertex_colors and bake_atlas_texture take it).
Expected<std::vector<Photo>> read_camera_proxy(const std::filesystem::path& camera_file,
                                               const std::filesystem::path& photo);

// `options` with the rules of one camera given as a proxy: exposure kNone
// (one photo: nothing to balance), max_view_angle_deg 90 (a point is seen
// unless it faces away) and strict_photos (a photo that cannot be read is an
// error: without it there is nothing to bake).
PhotoBakeOptions camera_proxy_options(PhotoBakeOptions options);

// A photo bake's VertexColors: colors, cameras, skipped, consistency;
// stats: counts.vertices, samples (camera samples blended), filled,
// unfilled; timings.scene_build, bake (photos), fill (blend and fill), total.
using PhotoColors = VertexColors;

// Vertex colours from photos (the contract of bake/photo/photo_bake.h). A
// photo that cannot be read is left out with a warning (stats.warnings) and
// listed in `skipped`, unless options.strict_photos. Errors: kInput (a photo
// unreadable under strict_photos, no photo readable, a photo of the wrong
// size, a mesh with no non-degenerate triangle), kUsage (no photos),
// kInternal. Progress stage:
// "photos" (per photo).
Expected<PhotoColors> bake_vertex_colors_from_photos(const MeshData& mesh,
                                                     const std::vector<Photo>& photos,
                                                     const PhotoBakeOptions& options = {},
                                                     const RunOptions& run = {});

// texbake cameras check (the contract of bake/photo/camera_check.h): per
// photo the share of the mesh in front, inside the photo, masked out (by
// Photo::mask, find_masks) and visible, and warnings for poses that look
// like convention errors. Errors: kInput (a mesh with no non-degenerate
// triangle, a mask file unreadable or of the wrong size), kInternal.
Expected<std::vector<CameraCheck>> check_cameras(const MeshData& mesh,
                                                 const std::vector<Photo>& photos,
                                                 const RunOptions& run = {});

// Is the camera model at `cameras` in the frame of `mesh`? Its sparse points
// (a COLMAP model's points3D, read_colmap_points) against the mesh's
// surface, with the figures and verdict of bake/fit/model_alignment.h; a
// JSON camera list or a model without points is kNotMeasured. Every photo
// bake of a COLMAP model runs it first (a misaligned model is an error,
// Job::alignment_check), and `texbake cameras check` prints it. Errors:
// read_colmap_points', kInput (a mesh with no non-degenerate triangle).
Expected<ModelAlignment> check_model_alignment(const MeshData& mesh,
                                               const std::filesystem::path& cameras,
                                               const RunOptions& run = {});

// texbake cameras check in one call: per camera the geometric checks
// (check_cameras), the model's sparse points against the mesh
// (check_model_alignment) and, with `measure_agreement`, the photo
// agreement of a photo bake (bake_vertex_colors_from_photos, occluded
// vertices left uncoloured: its cameras' shared, deviation and gain, and its
// consistency). The agreement is not measured for fewer than two photos, or
// when the photos cannot be baked for a reason of their own (none readable,
// a size that does not match the camera's): `agreement_not_measured` says
// why. Errors: those of check_cameras and check_model_alignment, and the
// photo bake's kInternal and kCancelled.
struct CameraModelCheck {
  std::vector<CameraCheck> cameras;
  ModelAlignment alignment;
  bool agreement_measured = false;
  std::vector<PhotoCameraStats> agreement;  // the photos baked, in the model's order
  PhotoConsistency consistency;
  std::string agreement_not_measured;
  // The photo bake's warnings (photos left out) and, when the photos
  // disagree, one that names `model` and the figures.
  std::vector<std::string> warnings;
};
Expected<CameraModelCheck> check_camera_model(const MeshData& mesh,
                                              const std::vector<Photo>& photos,
                                              const std::filesystem::path& model,
                                              bool measure_agreement, const RunOptions& run = {});

// texbake cameras refine (the contract of bake/photo/pose_refine.h): every
// photo's pose (with options.intrinsics also its focal length and principal
// point) refined so that the photos agree on the mesh, photometrically in
// linear light with exposure gains solved jointly, each change bounded by
// options.max_rotation_deg and max_translation (times the mesh's
// bounding-box diagonal) and reported per photo. A photo that cannot be
// read is left out with a warning (its pose returned unchanged, `skipped`
// set), unless options.strict_photos. Errors: kUsage (options out of range,
// fewer than two photos: one has nothing to agree with), kInput (a photo
// unreadable under strict_photos, fewer than two readable photos, a photo
// of the wrong size, no point seen by two photos, a mesh with no
// non-degenerate triangle), kInternal, kCancelled. Progress stages:
// "photos" (per photo read), "refine" (per level and iteration).
struct RefinedCameras {
  std::vector<RefinedPose> photos;    // one per input photo, in order
  std::vector<SkippedPhoto> skipped;  // photos left out (cannot be read; also warnings)
  std::size_t points = 0;             // surface sample points
  int levels = 0;                     // pyramid levels
  double mesh_size = 0;               // the bounding-box diagonal translations are relative to
  Stats stats;  // counts.vertices, triangles, samples (= points); timings.scene_build,
                // bake (reading the photos and refining), total; warnings
};
Expected<RefinedCameras> refine_cameras(const MeshData& mesh, const std::vector<Photo>& photos,
                                        const PoseRefineOptions& options = {},
                                        const RunOptions& run = {});

// ---- Layers (SPEC section 10) ---------------------------------------------

// Reads a layers file (mesh_io/layers_json.h: keys, defaults, paths relative
// to the file). Errors: kInput naming the file and the key.
Expected<LayersSpec> read_layers(const std::filesystem::path& layers_file);

// A layers bake's VertexColors: colors (alpha = coverage), layers; stats:
// counts.vertices, samples (vertices x layers), occluded (uncovered),
// filled; timings.scene_build, bake (layers), fill, total.
using LayerColors = VertexColors;

// Vertex colours composited from the layers of `spec` over its base
// (spec.base and base_color; of `options` only the occluded rule is used;
// the contract of bake/engine/layers_bake.h): every layer's texture and mask
// are read here (any format OpenImageIO reads; sampled in linear light). A
// "cameras" layer's photos (read_cameras with its "images") are baked first
// with the photo bake's rules (bake/photo/photo_bake.h: --blend soft,
// exposure gains, the 75-degree cut, visibility along the segment to each
// camera), and the layer composites that blend where some photo sees the
// point, with the angle fade at the blend-weighted mean angle to its
// cameras; elsewhere it is transparent. Its photo warnings (a photo scaled
// to its camera) are in stats.warnings, prefixed "layers[i]: ". Errors:
// kInput (an image unreadable; base "mesh" on a mesh without vertex
// colours; a camera model, list or photo unreadable or of the wrong size,
// prefixed "layers[i]: "), kUsage (a COLMAP model outside a workspace and
// no "images"), kInternal, kCancelled. Progress stages: "layers" (per
// layer read, a "cameras" layer's photos blended), "bake" (per vertex,
// through every layer), "fill".
Expected<LayerColors> bake_vertex_colors_from_layers(const MeshData& mesh, const LayersSpec& spec,
                                                     const LayersBakeOptions& options = {},
                                                     const RunOptions& run = {});

// ---- Atlas ----------------------------------------------------------------

// UvLayout (auto | mesh | generate | proxy), to_string(UvLayout) and
// UvLayoutStats: bake/uv/uv_layout.h.

struct AtlasOptions {
  UvLayout uv = UvLayout::kAuto;
  AtlasBakeOptions bake;  // size, samples, padding, shading
};

struct Atlas {
  MeshData mesh;          // the input with the per-corner UVs baked against
  Image image;            // size x size RGBA, sRGB-encoded (color_space kSrgb)
  bool repeat_u = false;  // the layout is periodic in u (kProxy on a periodic proxy)
  // A covered texel is not opaque (layers over a transparent base): a .glb
  // gets alphaMode BLEND. The background's alpha 0 of the default padding
  // does not count.
  bool blend = false;
  UvLayoutStats uv;
  Stats stats;
};

// What an atlas bake gives, whatever it projects (bake_atlas_texture over
// a Bake, below): the atlas, and the fields of VertexColors that describe
// the projection (the other kinds' stay empty): per photo over the atlas
// samples (in_view, visible, weight_share; the exposure gains, solved on
// the vertices, bake/engine/photo_atlas.h), the photos left out, their
// consistency (measured on the vertices); per layer over the supersamples.
struct BakedAtlas {
  Atlas atlas;
  std::vector<PhotoCameraStats> cameras;
  std::vector<SkippedPhoto> skipped;
  PhotoConsistency consistency;
  std::vector<LayerStats> layers;
};

// The whole atlas pipeline: UV layout (bake/uv/uv_layout.h, with the gutter
// rule: generated charts at least kMinGutter texels apart), bake
// (bake/engine/bake_atlas.h), padding (by default rings, then a mip-safe
// push-pull of the colour with alpha 0). Warnings of the layout (UVs outside
// [0, 1], overlaps, stretched pole triangles) are in stats.warnings. When
// the layout overlaps (uv.overlap_texels > 0: --uv mesh or --uv proxy), the
// bake gives shared texels the visible surface's colour
// (AtlasBakeOptions::resolve_overlaps, set here whatever options.bake says).
// Errors: kUsage (options out of range, an image without pixels; kMesh on a
// mesh without UVs), kInput (no non-degenerate triangle, a mesh the layout
// cannot chart or whose UVs are unusable), kInternal, kCancelled. Progress
// stages: "uv_layout", "sample" (per atlas row).
Expected<Atlas> bake_atlas_texture(const MeshData& mesh, const ImageView& image, const Proxy& proxy,
                                   const AtlasOptions& options = {}, const RunOptions& run = {});
// The same, taking the caller's mesh: the input's memory is given back as
// soon as the atlas mesh (the input with its UVs) replaces it, and with
// --uv mesh it becomes the atlas mesh without a copy, so the bake holds one
// mesh, not two. On return `mesh` is empty, whether the call succeeded or not.
Expected<Atlas> bake_atlas_texture(MeshData&& mesh, const ImageView& image, const Proxy& proxy,
                                   const AtlasOptions& options = {}, const RunOptions& run = {});

// The option checks bake_atlas_texture makes first (kUsage naming the CLI
// flag): --size outside 1 .. kMaxAtlasSize, --samples outside
// 1 .. kMaxAtlasSamples, a padding neither a count in 0 .. kMaxAtlasSize nor
// kPaddingDefault / kPaddingInfinite, a colour component outside [0, 1].
Status validate_options(const AtlasOptions& options);

// ---- Atlas from layers (SPEC section 10) -----------------------------------

// A layers bake's BakedAtlas: atlas (mesh with the UVs, image: sRGB,
// straight alpha = coverage; uv, blend, stats) and layers (per layer, over
// the atlas supersamples: in domain, visible, blended, mean alpha).
// atlas.stats: counts.texels, samples, occluded (samples with coverage 0),
// border_samples, padded; timings.uv_layout, fill (the vertex pass giving
// the fill's colours), scene_build, bake (the layers over every sample),
// pad, total; warnings of the layout.
using LayerAtlas = BakedAtlas;

// The atlas target of bake --layers (the contract of bake_atlas_layers in
// bake/engine/layers_bake.h): the UV layout of atlas.uv (kAuto, kMesh or
// kGenerate; kProxy has no single proxy here), then per supersample every
// layer of `spec` composited over its base, texel = the samples' mean in
// premultiplied linear light, then atlas.bake.padding (an overlapping
// layout, kMesh with shared UVs: a shared sample takes the lowest-index
// triangle under it that some layer sees). Base "mesh" is the
// mesh's own texture (MeshData::texture_path or texture_bytes, read with
// read_mesh_texture) through the mesh's own UVs, which needs atlas.uv kMesh
// (or kAuto on a mesh with UVs); a mesh without a texture but with vertex
// colours gives them, interpolated over each triangle (any layout).
// atlas.bake.size 0 means the base texture's size (its larger side), else
// 2048. atlas.bake.shading is not used (options holds the occluded rule;
// the base is spec's). A "cameras" layer is the photo atlas bake's blend
// per supersample (bake/engine/photo_atlas.h) on the same layout, before
// any texel averaging, composited per sample as in the vertex target.
// Errors: kUsage (atlas options out of range, --uv proxy, kMesh on a mesh
// without UVs, base "mesh" as a texture with another layout), kInput (an
// image or the mesh's texture unreadable, base "mesh" on a mesh with
// neither texture nor vertex colours, a mesh with no non-degenerate
// triangle or that the layout cannot chart; a "cameras" layer's as for
// the vertex target), kInternal, kCancelled. Progress stages: "layers" (per layer
// read), "uv_layout", "sample" (per atlas row).
Expected<LayerAtlas> bake_atlas_texture_from_layers(const MeshData& mesh, const LayersSpec& spec,
                                                    const LayersBakeOptions& options = {},
                                                    const AtlasOptions& atlas = {},
                                                    const RunOptions& run = {});

// ---- Atlas from photographs (SPEC section 9) -------------------------------

// A photo bake's BakedAtlas: atlas (mesh with the UVs, image: sRGB; uv,
// stats), cameras, skipped, consistency. atlas.stats: counts.texels,
// samples (atlas supersamples), occluded (samples no photo sees), filled
// (of those, coloured by the fill), unfilled (vertices in components no
// photo sees), border_samples, padded; timings.uv_layout, rasterize,
// scene_build, bake (the atlas's geometry and photo passes), fill (the
// vertex blend: gains, and the fill's solve), pad (texels and padding), total.
using PhotoAtlas = BakedAtlas;

// The atlas target of bake --cameras (the contract of
// bake/engine/photo_atlas.h): the UV layout of atlas.uv (kAuto, kMesh or
// kGenerate, as bake_atlas_texture lays it out; kProxy has no proxy here),
// then every atlas supersample blended from the photos that see it with
// the vertex bake's quality, blend and exposure rules, unseen samples as
// options.occluded says, then atlas.bake.padding. atlas.bake.shading is not
// used (options holds the photo bake's occluded rule). Photos are read one
// at a time, twice each; one that cannot be read is left out as for
// bake_vertex_colors_from_photos. Errors: kUsage (atlas options out of
// range, --uv proxy, kMesh on a mesh without UVs, no photos), kInput (a
// photo unreadable under strict_photos, no photo readable, a photo of the
// wrong size, a mesh with no non-degenerate triangle
// or that the layout cannot chart), kInternal, kCancelled. Progress
// stages: "uv_layout", "photos" (per photo read: two per photo).
Expected<PhotoAtlas> bake_atlas_texture_from_photos(const MeshData& mesh,
                                                    const std::vector<Photo>& photos,
                                                    const PhotoBakeOptions& options = {},
                                                    const AtlasOptions& atlas = {},
                                                    const RunOptions& run = {});

// ---- One bake description, two targets -------------------------------------
//
// Every bake above is one of three kinds of projection onto the mesh, and
// the six per-kind calls above that take their inputs by const reference
// are one-line conveniences over the two calls below, which take the kind
// as a value (a client holding bakes of several kinds needs no branch per
// kind). The two that take over their input to free it early
// (bake_vertex_colors with an Image&&, bake_atlas_texture with a
// MeshData&&) have no counterpart here: a Bake does not own its image, and
// these calls copy what they need of the mesh.
//
//   texbake::Bake bake = texbake::PhotoProjection{*photos, {}};
//   auto colors = texbake::bake_vertex_colors(mesh->mesh, bake);      // per vertex
//   auto atlas = texbake::bake_atlas_texture(mesh->mesh, bake, {});   // an atlas

// An image through an analytic proxy (SPEC sections 3 and 4). `image` is
// not owned: it must outlive the call.
struct ImageProjection {
  ImageView image;
  Proxy proxy;
  // The lookup (filter, samples), visibility, occluded, outside, wrap and
  // linear; on the atlas target the lookup of each supersample
  // (AtlasOptions::bake.shading is replaced by these).
  VertexBakeOptions options;
};
// Calibrated photographs (SPEC section 9; one photo through a camera proxy
// file: read_camera_proxy, with camera_proxy_options).
struct PhotoProjection {
  std::vector<Photo> photos;
  PhotoBakeOptions options;  // blend, exposure, occluded (+ colour), strict photos, ...
};
// A stack of layers over a base (SPEC section 10; read_layers).
struct LayersProjection {
  LayersSpec spec;
  LayersBakeOptions options;  // occluded, strict photos, cache budget (the base is spec's)
};
using Bake = std::variant<ImageProjection, PhotoProjection, LayersProjection>;

// Per-vertex colours of `bake`: bake_vertex_colors (image),
// bake_vertex_colors_from_photos or bake_vertex_colors_from_layers above,
// by its kind, with their contracts, errors and progress stages.
Expected<VertexColors> bake_vertex_colors(const MeshData& mesh, const Bake& bake,
                                          const RunOptions& run = {});

// An atlas of `bake`: bake_atlas_texture (image),
// bake_atlas_texture_from_photos or bake_atlas_texture_from_layers above,
// by its kind, with their contracts, errors and progress stages.
Expected<BakedAtlas> bake_atlas_texture(const MeshData& mesh, const Bake& bake,
                                        const AtlasOptions& atlas = {}, const RunOptions& run = {});

// ---- Render and compare ---------------------------------------------------

struct Rendered {
  RenderImage image;
  RenderStats rays;
  Stats stats;  // timings.scene_build, timings.render
};

// texbake render (bake/render/render_preview.h): builds the Embree scene and
// renders. Errors: kUsage (invalid colour source; invalid options, found
// once the scene is built), kInput (no non-degenerate triangle), kInternal,
// kCancelled. Progress stage: "render" (per tile).
Expected<Rendered> render_mesh(const MeshData& mesh, const ColorSource& source,
                               const RenderOptions& options = {}, const RunOptions& run = {});

// compare_image_files and compare_images: mesh_io/image_compare.h.

// ---- Meshes ---------------------------------------------------------------

// read_mesh (mesh_io/read_mesh.h) run in this call's task arena: its
// triangulation and edge count run on run.threads threads (the plain
// read_mesh runs them in the caller's arena: all cores unless the caller
// limits them). The same mesh and issues for any thread count; run.progress
// is not called.
Expected<LoadedMesh> read_mesh(const std::filesystem::path& path, const RunOptions& run);

// Ok when `mesh` has a non-degenerate triangle (what bake and render need).
// Errors (kInput): "the mesh has no faces"; "all N triangles are
// degenerate", N counting the triangles of the faces' triangulation before
// degenerate ones were removed (mesh_io/read_mesh.h: a polygon of n >= 3
// corners gives n - 2, a face of fewer corners counts as one). The bakes
// and render_mesh call it first; a caller that fits a proxy may call it
// before the fit, to report the mesh's problem rather than the fit's.
Status check_triangles(const MeshData& mesh);

// ---- Writing --------------------------------------------------------------

enum class AtlasFormat { kPng8, kPng16, kExr };

struct WriteOptions {
  bool ascii = false;                       // .ply only
  AtlasFormat format = AtlasFormat::kPng8;  // atlas image of a textured .obj
  // .glb only: the mesh's up direction (non-zero), turned to glTF's +Y by
  // the node matrix; the vertex data stay the mesh's (mesh_io/write_textured.h).
  Vec3 up{0, 0, 1};
};

// A mesh with per-vertex colours (sRGB-encoded, as bakes give them), by
// extension: .ply (binary little-endian, or ASCII; uchar sRGB), .obj
// (v x y z r g b, sRGB in [0, 1]), .glb (COLOR_0, linear; NORMAL; Y-up node
// matrix from options.up). Errors: kUsage
// (unknown extension, ascii with non-PLY, not one colour per vertex),
// kInput for I/O (naming the file).
Status write_vertex_colors(const std::filesystem::path& path, const MeshData& mesh,
                           std::span<const Rgba> colors, const WriteOptions& options = {});

// An atlas bake, by extension: .obj (+ .mtl + the atlas image beside it,
// atlas_files() names them) or .glb (atlas embedded as PNG; kExr is kUsage).
// The image is encoded for its format from atlas.image.color_space: PNG
// sRGB-encoded (tagged "sRGB"; untagged inside a GLB), EXR linear light
// (tagged "Linear").
// The set is replaced all together or not at all. Errors: kUsage (another
// extension, kExr with .glb), kInput for I/O (naming the file).
Status write_atlas(const std::filesystem::path& path, const Atlas& atlas,
                   const WriteOptions& options = {});

// The option checks the writers make first, for callers that check before
// any long work (kUsage naming the CLI flag): `atlas` = write_atlas's
// ("--format exr cannot be embedded in F.glb ..."), else
// write_vertex_colors's ("--ascii applies to .ply output only"); an
// unknown extension for either.
Status validate_write(const std::filesystem::path& path, const WriteOptions& options, bool atlas);

// Every file write_atlas(path, ..., options) writes, the mesh file first.
std::vector<std::filesystem::path> atlas_files(const std::filesystem::path& path,
                                               const WriteOptions& options = {});

// write_image (mesh_io/image_io.h) writes a single image; write_proxy_file
// (mesh_io/proxy_json.h) a proxy.

// ---- The files of a job (SPEC section 12) ---------------------------------
//
// No output may be an input of the same job or another output, after links:
// a caller lists the job's files (job_inputs, job_outputs, or its own lists)
// and calls check_distinct_files before any work, so nothing is read, made
// or overwritten when the check fails.

// A file a job reads or writes and how the caller named it, for messages:
// a flag ("-o", "--texture"), a positional ("MESH"), a key of a file
// ("layers[1].mask") or a role ("the atlas image of -o", "a photo of
// --cameras").
struct NamedFile {
  std::string name;
  std::filesystem::path path;
};

// The paths a job names (empty: not given), as the command line's flags
// and the batch's keys name them.
struct JobFileNames {
  std::filesystem::path mesh;        // MESH
  std::filesystem::path texture;     // --texture (also the photo of a camera --proxy-file)
  std::filesystem::path proxy_file;  // --proxy-file
  std::filesystem::path cameras;     // --cameras: a COLMAP model folder or a JSON camera list
  std::filesystem::path images;      // --images
  std::filesystem::path masks;       // --masks (COLMAP's mask folder)
  std::filesystem::path layers;      // --layers
  std::filesystem::path manifest;    // the batch's jobs file (every job of it reads it)
  std::filesystem::path output;      // -o
  bool atlas = false;                // -o is an atlas: atlas_files(output, write) are written
  WriteOptions write;                // the atlas image's format
  std::filesystem::path report;      // --report
  std::filesystem::path results;     // the batch's --results (every job of it writes it)
};

// Every file the job reads, paths as given: MESH "MESH" and the files it
// names ("a file MESH names:", mesh_io/mesh_files.h: an OBJ's material
// libraries and textures, a .gltf's or .glb's external buffers and
// images), --texture, --proxy-file, the camera files of --cameras
// (camera_files), the layers file and what it names (layers_files), the
// batch's jobs file "JOBS".
// A layers file or camera model that cannot be read adds what could be
// listed: the job then fails reading it, before it writes anything.
std::vector<NamedFile> job_inputs(const JobFileNames& job);

// Every file the job writes: -o "-o" (an atlas .obj: also "the material of
// -o" and "the atlas image of -o", atlas_files), --report, --results.
std::vector<NamedFile> job_outputs(const JobFileNames& job);

// The files a set of cameras is read from, named `name` ("--cameras",
// "layers[2].cameras"): a JSON camera list itself, or a COLMAP model
// folder's cameras, images and points3D files (.txt and .bin, those that
// exist), then "a photo of NAME" for every photo they name, resolved
// against `images` as read_cameras resolves them, whether it exists or not,
// and with `masks` "the mask of a photo of NAME" for every mask_file found.
std::vector<NamedFile> camera_files(const std::filesystem::path& cameras,
                                    const std::filesystem::path& images, const std::string& name,
                                    const std::filesystem::path& masks = {});

// The layers file "--layers" and, recursively, what it names:
// "layers[i].proxy_file", "layers[i].texture", "layers[i].mask" and the
// camera_files of "layers[i].cameras" (with its "images" and "masks").
std::vector<NamedFile> layers_files(const std::filesystem::path& layers);

// The name of view k (0-based) of a COLMAP workspace that render --colmap
// writes ("view_00.png"), and every file that workspace gets, named
// "--colmap": DIR/images/<view names> for `views` views, then
// DIR/sparse/0/cameras.txt and images.txt (write_colmap_model).
std::string colmap_view_name(int k);
std::vector<NamedFile> colmap_workspace_files(const std::filesystem::path& dir, int views);

// kUsage when an output is the same file as an input or as another output:
// the same device and inode after links, or, for a file that does not exist
// yet, the same absolute path with links, "." and ".." resolved:
//   "-o photos/a.png and a photo of --cameras photos/a.png are the same
//    file: texbake never overwrites an input"
//   "--report x.ply and -o x.ply are the same file: two outputs cannot
//    share one file"
// Empty paths are skipped.
Status check_distinct_files(const std::vector<NamedFile>& inputs,
                            const std::vector<NamedFile>& outputs);

// check_distinct_files(job_inputs(job), job_outputs(job)).
Status check_job_files(const JobFileNames& job);

}  // namespace texbake
