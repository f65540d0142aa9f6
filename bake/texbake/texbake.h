// texbake's public API (SPEC section 11): the one header another program
// includes. Every job of the command line is one call here; the `texbake`
// executable (bake/cli/) is a thin client of exactly these functions.
//
//   #include <texbake/texbake.h>
//   auto mesh  = texbake::read_mesh("bunny.off");          // Expected<LoadedMesh>
//   auto image = texbake::read_image("earth.jpg");         // Expected<Image>
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
// bake/atlas/bake_atlas.h) and the render options and colour sources
// (bake/render/render_preview.h).
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "bake/atlas/bake_atlas.h"
#include "bake/render/render_preview.h"
#include "bake/shade/options.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mapping/proxy_schema.h"
#include "mesh_io/image_compare.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"
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
};

// ---- Proxies --------------------------------------------------------------

struct CompletedProxy {
  Proxy proxy;
  // Keys of the fields filled by fitting (e.g. {"center", "radius"}), in the
  // kind's field order; empty when the spec was complete.
  std::vector<std::string> fitted;
  Stats stats;  // timings.fit
};

// The proxy of `spec`, every field not given fitted to the mesh's referenced
// vertices (SPEC section 6, bake/fit/fit_proxy.h): a given direction is the
// fit's fixed direction, with its sign; without one, spec.up fixes a
// cylinder's or cone's axis line and is the sphere's pole; a given anchor
// (sphere/disk centre, cylinder base, cone apex, plane origin) and a cone's
// height are kept and the rest is fitted around them; other given values
// replace the fitted ones. A complete spec is validated and returned without
// looking at the mesh. Errors: kUsage (a given value is invalid, e.g. a zero
// axis, naming the key), kInput (the mesh cannot be fitted, e.g. all points
// coincident).
Expected<CompletedProxy> complete_proxy(const ProxySpec& spec, const MeshData& mesh,
                                        const RunOptions& run = {});

// ---- Vertex colours -------------------------------------------------------

struct VertexColors {
  std::vector<Rgba> colors;  // one per vertex, input order, RGBA in [0, 1]
  Stats stats;
};

// SPEC sections 3 and 4, per vertex (the contract of bake/vertex/bake_vertex.h).
// Errors: kUsage (options out of range), kInput (a mesh with no
// non-degenerate triangle: "all N triangles are degenerate", or none at all),
// kInternal, kCancelled.
Expected<VertexColors> bake_vertex_colors(const MeshData& mesh, const ImageView& image,
                                          const Proxy& proxy, const VertexBakeOptions& options = {},
                                          const RunOptions& run = {});

// ---- Atlas ----------------------------------------------------------------

enum class UvLayout {
  kAuto,      // the mesh's own UVs if it has any, else kGenerate
  kMesh,      // the mesh's own per-corner UVs (checked: outside [0,1], overlaps)
  kGenerate,  // new non-overlapping charts (bake/uv/uv_generate.h)
  kProxy,     // the proxy's (u, v), cut at its seam (bake/uv/uv_proxy.h)
};
const char* to_string(UvLayout layout);  // "auto", "mesh", "generate", "proxy"

struct AtlasOptions {
  UvLayout uv = UvLayout::kAuto;
  AtlasBakeOptions bake;  // size, samples, padding, shading
};

// What the UV layout stage found (the report's "uv_check" / chart figures).
struct UvLayoutStats {
  UvLayout used = UvLayout::kMesh;  // kAuto resolved
  std::size_t corners_outside = 0;  // kMesh
  std::size_t overlap_texels = 0;   // kMesh
  std::size_t cut_triangles = 0;    // kProxy
  std::size_t charts = 0;           // kGenerate
  double utilisation = 0;           // kGenerate: covered / all texels
  double stretch_l2 = 0;            // kGenerate
};

struct Atlas {
  MeshData mesh;          // the input with the per-corner UVs baked against
  Image image;            // size x size RGBA, the image's encoding
  bool repeat_u = false;  // the layout is periodic in u (kProxy on a periodic proxy)
  UvLayoutStats uv;
  Stats stats;
};

// The whole atlas pipeline: UV layout (with the gutter rule: charts at
// least two texels apart), bake (bake/atlas/bake_atlas.h), padding.
// Errors: kUsage (options out of range; kMesh on a mesh without UVs),
// kInput (no non-degenerate triangle, a mesh the layout cannot chart),
// kInternal, kCancelled.
Expected<Atlas> bake_atlas_texture(const MeshData& mesh, const ImageView& image, const Proxy& proxy,
                                   const AtlasOptions& options = {}, const RunOptions& run = {});

// ---- Render and compare ---------------------------------------------------

struct Rendered {
  RenderImage image;
  RenderStats rays;
  Stats stats;  // timings.scene_build, timings.render
};

// texbake render (bake/render/render_preview.h): builds the Embree scene and
// renders. Errors: kUsage (invalid options or colour source), kInput (no
// non-degenerate triangle), kInternal, kCancelled.
Expected<Rendered> render_mesh(const MeshData& mesh, const ColorSource& source,
                               const RenderOptions& options = {}, const RunOptions& run = {});

// compare_image_files and compare_images: mesh_io/image_compare.h.

// ---- Writing --------------------------------------------------------------

enum class AtlasFormat { kPng8, kPng16, kExr };

struct WriteOptions {
  bool ascii = false;                       // .ply only
  AtlasFormat format = AtlasFormat::kPng8;  // atlas image of a textured .obj
};

// A mesh with per-vertex colours, by extension: .ply (binary little-endian,
// or ASCII), .obj (v x y z r g b), .glb (COLOR_0, linear). Errors: kUsage
// (unknown extension, ascii with non-PLY), kInput for I/O (naming the file).
Status write_vertex_colors(const std::filesystem::path& path, const MeshData& mesh,
                           std::span<const Rgba> colors, const WriteOptions& options = {});

// An atlas bake, by extension: .obj (+ .mtl + the atlas image beside it,
// atlas_files() names them) or .glb (atlas embedded as PNG; kExr is kUsage).
// The set is replaced all together or not at all.
Status write_atlas(const std::filesystem::path& path, const Atlas& atlas,
                   const WriteOptions& options = {});

// Every file write_atlas(path, ..., options) writes, the mesh file first.
std::vector<std::filesystem::path> atlas_files(const std::filesystem::path& path,
                                               const WriteOptions& options = {});

// write_image (mesh_io/image_io.h) writes a single image; write_proxy_file
// (mesh_io/proxy_json.h) a proxy.

}  // namespace texbake
