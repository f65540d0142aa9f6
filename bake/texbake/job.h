// A bake job as a whole (SPEC sections 3 to 7), the library's front door:
// run_job reads the mesh, resolves the proxy (the fields not given are
// fitted to the mesh, complete_proxy), reads the image, bakes (vertex
// colours or an atlas), writes the outputs atomically and the report, and
// returns what happened as a JobResult instead of printing it. The command
// line's `texbake bake MESH --texture IMG ...` builds a Job from its flags
// and prints the JobResult; a C++ or Python caller does the same without
// the command line.
//
//   texbake::Job job;
//   job.mesh = "statue.ply";
//   job.texture = "panorama.exr";
//   job.spec.kind = texbake::ProxyKind::kSphere;  // centre and radius fitted
//   job.output = "statue_colored.ply";
//   texbake::JobResult r = texbake::run_job(job);
//   if (!r.ok()) std::cerr << "texbake: error: " << r.error->message << "\n";
//
// A job never overwrites an input or writes one file twice (check_job_files,
// before any work), checks its outputs are writable before the long work,
// and leaves no output behind when it fails.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "texbake.h"  // its sibling, in the source tree and installed

namespace texbake {

enum class JobTarget { kVertex, kAtlas };

// What jobs run one after another in one process share (run_batch makes
// one for its jobs; Python's texbake.run_batch too): the last mesh and the
// last texture read, handed to a later job that reads the same file (the
// same path, size and modification time; a texture also with the same read
// options) instead of reading and decoding it again. It holds one mesh and
// one texture at most: a job that reads another file drops the old one
// first, so a batch's memory peak is that of its largest job plus, at most,
// the last mesh and texture while a job that needs neither runs. With the
// mesh it keeps the mesh's visibility scene (Embree's BVH), built by the
// first per-vertex job that tests visibility on it, for meshes of at most
// kSceneKeepTriangles triangles (a larger scene costs more memory than its
// build costs time), until a job that does not use it runs (drop_scene).
// Results are the same bytes as without it. Thread-safe.
class EmbreeScene;
class JobCache {
 public:
  JobCache();
  ~JobCache();
  JobCache(const JobCache&) = delete;
  JobCache& operator=(const JobCache&) = delete;

  // read_mesh(path, run), or the cached result of the same file. The mesh is
  // shared: a caller that changes it copies it first.
  Expected<std::shared_ptr<const LoadedMesh>> mesh(const std::filesystem::path& path,
                                                   const RunOptions& run = {});
  // read_image(path, options), or the cached result of the same file and options.
  Expected<std::shared_ptr<const Image>> image(const std::filesystem::path& path,
                                               const ImageReadOptions& options);

  // The visibility scene of `mesh`, a mesh this cache returned and still
  // holds: built on the first call (`built` set), the same scene after.
  // Null when the mesh is not the one held or has more than
  // kSceneKeepTriangles triangles. Errors: kInternal (Embree).
  static constexpr std::size_t kSceneKeepTriangles = std::size_t{1} << 22;
  // Lets the scene go (a job that does not use it: the memory for its own).
  void drop_scene();
  Expected<std::shared_ptr<const EmbreeScene>> scene(const std::shared_ptr<const LoadedMesh>& mesh,
                                                     bool* built = nullptr);

  struct Counts {
    std::size_t mesh_reads = 0, mesh_hits = 0, image_reads = 0, image_hits = 0;
    std::size_t scene_builds = 0, scene_hits = 0;
  };
  Counts counts() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// One bake onto a mesh, of one of three kinds by the inputs given: an
// image through a proxy (texture + proxy or spec), calibrated photographs
// (cameras, or a camera proxy_file with its one photo), or a stack of
// layers (layers).
struct Job {
  // ---- Inputs ----
  std::filesystem::path mesh;     // any format read_mesh reads
  std::filesystem::path texture;  // any image read_image reads (also a camera proxy's photo)
  // The proxy: `proxy` when given whole (e.g. read_proxy_file), else
  // `spec` with the fields not given fitted to the mesh (complete_proxy).
  std::optional<Proxy> proxy;
  ProxySpec spec;
  std::filesystem::path proxy_file;  // where `proxy` was read from ("" if not a file)
  // How messages and JobResult::fitted name the proxy's fields: by key
  // ("center") or by the command line's flag ("--center").
  ParamNaming naming = ParamNaming::kKey;

  // Or calibrated photographs (SPEC section 9): a COLMAP model folder or a
  // JSON camera list, and the photos' folder ("": its default) and their
  // masks' folder (COLMAP's convention, find_masks; "": none but the
  // photos' own alpha) ...
  std::filesystem::path cameras, images, masks;
  // ... or one photo (`texture`) through the camera of a camera proxy_file.
  std::optional<Photo> photo;
  PhotoBakeOptions photo_options;  // photo bakes: blend, exposure, occluded, colour space, strict
  // Photo bakes of a COLMAP model (and a layers file's "cameras" layers):
  // its sparse points against the mesh first
  // (check_model_alignment): a misaligned model is an error (kParse, exit
  // 1) that says so, a doubtful one a warning; false bakes without looking.
  bool alignment_check = true;

  // Or several projections over a base from a layers file (SPEC section 10).
  std::filesystem::path layers;
  // The layers bake's occluded and strict_photos (base and base colour: the
  // file's; cache_mb: `cache_mb`).
  LayersBakeOptions layers_options;

  // ---- Target and outputs ----
  JobTarget target = JobTarget::kVertex;
  std::filesystem::path output;  // vertex: .ply, .obj, .glb; atlas: .obj (+ .mtl + image), .glb
  std::filesystem::path report;  // the JSON report (texbake/report.h); "" for none
  WriteOptions write;            // .ply ASCII, a .glb's up axis, the atlas image's format

  // ---- Options ----
  // The proxy bake's options (vertex target); for the atlas, the lookup of each
  // supersample (filter bilinear or ewa, visibility, occluded, outside,
  // wrap, linear).
  VertexBakeOptions shading;
  // Atlas target: the UV layout, size, supersamples per texel, padding
  // (atlas.bake.shading is replaced by `shading`; a layers bake's size 0
  // is its base texture's size, else 2048).
  AtlasOptions atlas;
  TextureColorSpace texture_colorspace = TextureColorSpace::kAuto;
  std::size_t cache_mb = kDefaultCacheMb;  // the image cache's budget (large textures)
  int threads = 0;                         // 0: all cores
  ProgressCallback progress;               // may be empty
  // Shared with the jobs before and after it (JobCache); null: every file
  // is read anew.
  std::shared_ptr<JobCache> cache;

  // Called as they happen (e.g. to print them live): each warning (also
  // in JobResult::warnings) and each note (also in JobResult::notes:
  // "fitted sphere (center radius) to 120 vertices of m.ply: {...}", a
  // camera file's reader's, the model's alignment). May be empty.
  std::function<void(const std::string&)> on_warning, on_note;
};

// What a job did.
struct JobResult {
  std::optional<Error> error;  // none: the job succeeded
  int exit_code = 0;           // the command line's: 0 ok, 2 usage (kUsage), 1 otherwise
  std::vector<std::string> warnings;
  std::vector<std::string> notes;   // what the job did that the user must know (Job::on_note)
  std::vector<std::string> fitted;  // the proxy's fields filled by the fit (keys or flags)
  std::vector<std::filesystem::path> outputs;  // the files written (the report last)
  std::string report;   // the report's JSON text (texbake/report.h); "" when it failed
  std::string summary;  // "baked N vertices (...) in S s -> OUT"; "" when it failed
  Stats stats;          // the bake's
  double seconds = 0;   // the whole job

  bool ok() const { return !error; }
};

// The target of output `output` when `target` is "vertex" or "atlas", or,
// for "", the default of its extension: vertex for .ply, atlas for .obj and
// .glb. Errors (kUsage): an unknown extension, "atlas" with a .ply, another
// `target`.
Expected<JobTarget> job_target(const std::string& target, const std::filesystem::path& output);

// The exit code of an error by its category (SPEC section 5): 2 for kUsage,
// 1 for kInput, kInternal and kCancelled.
int exit_code(const Error& error);

// A proxy spec completed by a fit to `mesh` (complete_proxy), as a job
// resolves it: `fitted` names the filled fields by `naming`, `note` is the
// line "fitted KIND (FIELDS) to N vertices of MESH_NAME: {json}" ("" when
// nothing was fitted). Errors: complete_proxy's, a kInput one prefixed
// "MESH_NAME: ".
struct ResolvedProxy {
  Proxy proxy;
  std::vector<std::string> fitted;
  std::string note;
  Stats stats;  // timings.fit
};
Expected<ResolvedProxy> resolve_proxy(const ProxySpec& spec, const MeshData& mesh,
                                      const std::string& mesh_name, ParamNaming naming,
                                      const RunOptions& run = {});

// The warnings about an image read from `name`: "NAME: N NaN or infinite
// values read as 0" (Image::nonfinite_values), "NAME: colour space 'X' is
// neither sRGB nor linear: read as ..." (Image::unrecognised_color_space).
std::vector<std::string> image_warnings(const Image& image, const std::string& name);

// Runs the job. Errors (in JobResult::error, never thrown): the usage
// errors of its options (kInvalidArgument / kUnsupported naming the
// option), an output that is an input or another output, an output that
// cannot be written, and the errors of reading, fitting, baking and
// writing; a kInput error about the mesh names its file ("MESH: ...").
// Nothing is written when it fails.
JobResult run_job(const Job& job);

}  // namespace texbake
