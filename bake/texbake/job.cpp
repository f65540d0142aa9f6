#include "texbake/job.h"

#include <cstdarg>
#include <cstdio>
#include <exception>
#include <new>
#include <utility>

#include "bake/texbake/run.h"
#include "bake/util/timing.h"
#include "mapping/proxy_schema.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/file_name.h"
#include "mesh_io/mesh_texture.h"
#include "mesh_io/proxy_json.h"
#include "texbake/job_options.h"
#include "texbake/report.h"

namespace texbake {

namespace fs = std::filesystem;

namespace {

// A file's contents as a job holds them: read for it alone (its own, which
// a bake may consume), or shared with the jobs around it (Job::cache).
template <class T>
class Held {
 public:
  static Expected<Held> of(Expected<T> own) {
    if (!own) return own.error();
    Held h;
    h.own_ = std::move(*own);
    return h;
  }
  static Expected<Held> of(Expected<std::shared_ptr<const T>> shared) {
    if (!shared) return shared.error();
    Held h;
    h.shared_ = std::move(*shared);
    return h;
  }
  const T& get() const { return own_ ? *own_ : *shared_; }
  // The shared one (null when it is its own).
  const std::shared_ptr<const T>& shared() const { return shared_; }
  bool own() const { return own_.has_value(); }
  // For a step that consumes it: its own moved out, a shared one copied.
  T take() {
    if (own_) return std::move(*own_);
    return *shared_;
  }

 private:
  std::optional<T> own_;
  std::shared_ptr<const T> shared_;
};

// The mesh of a job.
Expected<Held<LoadedMesh>> read_held_mesh(const fs::path& path, const RunOptions& run,
                                          JobCache* cache) {
  return cache ? Held<LoadedMesh>::of(cache->mesh(path, run))
               : Held<LoadedMesh>::of(read_mesh(path, run));
}

// The job's state while it runs: the result and the proxy report being filled.
class JobRun {
 public:
  explicit JobRun(const Job& job) : job_(job) {}

  JobResult run() {
    start_ = Clock::now();
    Status s = ok_status();
    try {
      s = !job_.layers.empty()                  ? run_layers()
          : !job_.cameras.empty() || job_.photo ? run_photos()
                                                : run_proxy();
    } catch (const std::bad_alloc&) {
      s = make_error(ErrorCode::kInternal, "out of memory");
    } catch (const std::exception& e) {
      s = make_error(ErrorCode::kInternal, std::string("unexpected failure: ") + e.what());
    }
    if (!s) {
      result_.error = s.error();
      result_.exit_code = exit_code(s.error());
      result_.report.clear();
      result_.summary.clear();
    }
    result_.seconds = seconds_since(start_);
    return std::move(result_);
  }

 private:
  bool atlas() const { return job_.target == JobTarget::kAtlas; }

  void warn(const std::string& text) {
    result_.warnings.push_back(text);
    if (job_.on_warning) job_.on_warning(text);
  }

  void note(const std::string& text) {
    result_.notes.push_back(text);
    if (job_.on_note) job_.on_note(text);
  }

  // A bake's warnings and notes, as the job's.
  void pass_on(const Stats& stats) {
    for (const std::string& w : stats.warnings) warn(w);
    for (const std::string& n : stats.notes) note(n);
  }

  RunOptions run_options() const { return RunOptions{job_.threads, job_.progress}; }

  // An error of a call on the mesh: the API's errors do not name its file,
  // so a kInput message not naming it yet is prefixed "MESH: ".
  Error mesh_error(Error error) const {
    const std::string mesh = job_.mesh.string();
    if (category(error) == ErrorCategory::kInput && error.message.find(mesh) == std::string::npos)
      error.message = mesh + ": " + error.message;
    return error;
  }

  JobFileNames files() const { return job_file_names(job_); }

  // Before any file is read: the writer's options, no output an input or
  // another output, every output writable.
  Status check_files() const {
    if (job_.mesh.empty() || job_.output.empty()) {
      return make_error(ErrorCode::kInvalidArgument, "a job needs a mesh and an output");
    }
    if (Status s = validate_write(job_.output, job_.write, atlas()); !s) return s;
    const JobFileNames f = files();
    if (Status s = check_job_files(f); !s) return s;
    for (const NamedFile& out : job_outputs(f)) {
      if (Status s = check_writable(out.path); !s) return s;
    }
    return ok_status();
  }

  // The mesh; with `check_uv`, --uv mesh on a mesh without UVs is refused.
  Expected<Held<LoadedMesh>> read_job_mesh(bool check_uv = true) const {
    Expected<Held<LoadedMesh>> mesh =
        read_held_mesh(job_.mesh, RunOptions{job_.threads, {}}, job_.cache.get());
    // Only a proxy's per-vertex bake with visibility uses the cache's scene
    // (run_proxy); any other job lets it go, so that a batch never holds
    // the cached scene beside a job's own.
    const bool uses_scene = job_.layers.empty() && job_.cameras.empty() && !atlas() &&
                            job_.shading.visibility == Visibility::kFirst;
    if (job_.cache && !uses_scene) job_.cache->drop_scene();
    if (mesh && check_uv && atlas() && job_.atlas.uv == UvLayout::kMesh &&
        !mesh->get().mesh.has_uvs()) {
      // The option does not fit the given mesh: a usage error.
      const bool proxy = job_.layers.empty() && job_.cameras.empty() && !job_.photo;
      return make_error(ErrorCode::kInvalidArgument,
                        "--uv mesh: " + job_.mesh.string() + " has no UV coordinates (use --uv " +
                            (proxy ? "generate or --uv proxy)" : "generate)"));
    }
    return mesh;
  }

  // Writes the atlas set, then the report made by make_report(write seconds).
  template <class MakeReport>
  Status write_atlas_set(const Atlas& baked, MakeReport make_report) {
    const auto stage = Clock::now();
    if (Status s = write_atlas(job_.output, baked, job_.write); !s) return s;
    result_.outputs = atlas_files(job_.output, job_.write);
    return write_report_of(make_report(seconds_since(stage)));
  }

  // Writes the vertex colours, then the report made by make_report(write seconds).
  template <class MakeReport>
  Status write_vertex_set(const MeshData& mesh, const std::vector<Rgba>& colors,
                          MakeReport make_report) {
    const auto stage = Clock::now();
    if (Status s = write_vertex_colors(job_.output, mesh, colors, job_.write); !s) return s;
    result_.outputs = {job_.output};
    return write_report_of(make_report(seconds_since(stage)));
  }

  Status write_report_of(std::string report) {
    result_.report = std::move(report);
    if (job_.report.empty()) return ok_status();
    if (Status s = write_report_text(job_.report, result_.report); !s) return s;
    result_.outputs.push_back(job_.report);
    return ok_status();
  }

  // The summary line: "WHAT in S s -> OUT" (an atlas .obj: "OUT (+ M.mtl, M.png)").
  __attribute__((format(printf, 2, 3))) void summarise(const char* format, ...) {
    char what[512];
    va_list args;
    va_start(args, format);
    std::vsnprintf(what, sizeof what, format, args);
    va_end(args);
    std::string written = job_.output.string();
    if (atlas()) {
      const std::vector<fs::path> files = atlas_files(job_.output, job_.write);
      if (files.size() == 3) {
        written +=
            " (+ " + files[1].filename().string() + ", " + files[2].filename().string() + ")";
      }
    }
    char seconds[64];
    std::snprintf(seconds, sizeof seconds, " in %.2f s -> ", seconds_since(start_));
    result_.summary = what + std::string(seconds) + written;
  }

  // ---- An image through a proxy ----

  // The job's proxy: given, or its spec completed by a fit to the mesh.
  Expected<Proxy> job_proxy(const MeshData& mesh, const RunOptions& run) {
    if (job_.proxy) return *job_.proxy;
    Expected<ResolvedProxy> done =
        resolve_proxy(job_.spec, mesh, job_.mesh.string(), job_.naming, run);
    if (!done) return done.error();
    result_.fitted = done->fitted;
    report_.fit = done->stats.timings.fit;
    if (!done->note.empty()) note(done->note);
    return std::move(done->proxy);
  }

  // The texture: read for this job, or shared with the jobs around it (Job::cache).
  Expected<Held<Image>> read_texture() {
    const bool ewa = job_.shading.filter == VertexFilter::kEwa;
    const bool linear = job_.shading.linear;
    const ImageReadOptions read =
        texture_read_options(job_.texture_colorspace, job_.cache_mb, linear, ewa);
    Expected<Held<Image>> held = job_.cache ? Held<Image>::of(job_.cache->image(job_.texture, read))
                                            : Held<Image>::of(read_image(job_.texture, read));
    if (!held) return held.error();
    const Image& image = held->get();
    if (ewa) {
      if (Status s = check_ewa_budget(image, job_.cache_mb, linear); !s) return s.error();
    }
    report_.image_width = image.width;
    report_.image_height = image.height;
    report_.image_cached = image.tiles != nullptr;
    // The file's levels, unless linear light needs its own (working_image).
    if (ewa && image.mip && !(linear && image.color_space == ColorSpace::kSrgb)) {
      report_.image_mip_levels = static_cast<int>(image.mip->levels.size());
    }
    for (const std::string& w : image_warnings(image, job_.texture.string())) warn(w);
    return held;
  }

  Status check_proxy_options() const {
    if (job_.texture.empty()) {
      return make_error(ErrorCode::kInvalidArgument,
                        "a job needs a texture (or cameras to bake from photographs, or layers)");
    }
    if (!atlas()) return validate_options(job_.shading);
    AtlasOptions a = job_.atlas;
    a.bake.shading = job_.shading;
    return validate_options(a);
  }

  Status run_proxy() {
    if (Status s = check_proxy_options(); !s) return s;
    if (Status s = check_files(); !s) return s;
    const RunOptions run = run_options();
    report_.mesh_path = job_.mesh.string();
    report_.texture_path = job_.texture.string();
    report_.output_path = job_.output.string();
    report_.threads = job_.threads;
    report_.options = job_.shading;

    auto stage = Clock::now();
    Expected<Held<LoadedMesh>> mesh = read_job_mesh();
    if (!mesh) return mesh.error();
    report_.load = seconds_since(stage);
    // Nothing to bake is the mesh's problem, reported before a fit's.
    if (Status s = check_triangles(mesh->get().mesh); !s) return mesh_error(s.error());
    Expected<Proxy> proxy = job_proxy(mesh->get().mesh, run);
    if (!proxy) return proxy.error();
    report_.proxy = params_of(*proxy);
    report_.fitted_flags = result_.fitted;

    stage = Clock::now();
    Expected<Held<Image>> image = read_texture();
    if (!image) return image.error();
    report_.load += seconds_since(stage);

    if (atlas()) {
      AtlasOptions options = job_.atlas;
      options.bake.shading = job_.shading;
      // The bake takes the loaded mesh (one mesh in memory, not two).
      Expected<Atlas> baked =
          bake_atlas_texture(mesh->take().mesh, image->get().view(), *proxy, options, run);
      if (!baked) return mesh_error(baked.error());
      pass_on(baked->stats);
      report_.stats = result_.stats = baked->stats;
      report_.atlas = AtlasReport{options.bake, baked->uv};
      if (Status s = write_atlas_set(*baked,
                                     [&](double write) {
                                       report_.write = write;
                                       report_.total = seconds_since(start_);
                                       return report_json(report_);
                                     });
          !s) {
        return s;
      }
      const Counts& c = baked->stats.counts;
      summarise(
          "baked a %dx%d atlas (uv %s, %zu texels, %zu samples, %zu occluded, %zu outside, %zu "
          "padded)",
          options.bake.size, options.bake.size, to_string(baked->uv.used), c.texels, c.samples,
          c.occluded, c.outside, c.padded);
      return ok_status();
    }
    // The visibility scene of a mesh the jobs share, built once for them.
    std::shared_ptr<const EmbreeScene> scene;
    double scene_build = 0;
    if (job_.cache && mesh->shared() && job_.shading.visibility == Visibility::kFirst) {
      stage = Clock::now();
      bool built = false;
      std::optional<Expected<std::shared_ptr<const EmbreeScene>>> cached;
      run_in_arena(job_.threads,
                   [&] { cached.emplace(job_.cache->scene(mesh->shared(), &built)); });
      if (!*cached) return mesh_error(cached->error());
      scene = std::move(**cached);
      if (built) scene_build = seconds_since(stage);
    }
    // Sample, free the image (unless the cache keeps it for the next job), fill; write.
    std::optional<Image> owned;
    if (image->own()) owned.emplace(image->take());
    Expected<VertexColors> baked = detail::bake_vertex_colors_on(
        mesh->get().mesh, owned ? owned->view() : image->get().view(), owned ? &*owned : nullptr,
        *proxy, job_.shading, run, scene.get());
    if (!baked) return mesh_error(baked.error());
    if (scene) baked->stats.timings.scene_build = scene_build;
    pass_on(baked->stats);
    report_.stats = result_.stats = baked->stats;
    if (Status s = write_vertex_set(mesh->get().mesh, baked->colors,
                                    [&](double write) {
                                      report_.write = write;
                                      report_.total = seconds_since(start_);
                                      return report_json(report_);
                                    });
        !s) {
      return s;
    }
    const Counts& c = baked->stats.counts;
    summarise("baked %zu vertices (%zu occluded, %zu filled, %zu unfilled, %zu outside samples)",
              c.vertices, c.occluded, c.filled, c.unfilled, c.outside);
    return ok_status();
  }

  // ---- Photographs ----

  // A bake error about a photo (bake/photo/photo_view.h: "the photo of
  // camera ...", "the mask of camera ...", "no usable photo: ...") names the
  // photo; other input errors are the mesh's.
  Error photo_error(const Error& error) const {
    const std::string& m = error.message;
    if (m.rfind("the photo of camera ", 0) == 0 || m.rfind("the mask of camera ", 0) == 0 ||
        m.rfind("no usable photo", 0) == 0)
      return error;
    return mesh_error(error);
  }

  // A COLMAP model's sparse points against the mesh (check_model_alignment):
  // misaligned, an error naming the way out; doubtful, a warning; aligned,
  // a note with the figures.
  Status check_alignment(const MeshData& mesh) {
    if (job_.photo) return ok_status();
    return check_alignment(mesh, job_.cameras);
  }
  Status check_alignment(const MeshData& mesh, const fs::path& cameras) {
    if (!job_.alignment_check) return ok_status();
    Expected<ModelAlignment> a = check_model_alignment(mesh, cameras, run_options());
    if (!a) return mesh_error(a.error());
    const std::string model = cameras.string();
    switch (a->verdict) {
      case AlignmentVerdict::kNotMeasured:
        break;
      case AlignmentVerdict::kMisaligned:
        return make_error(ErrorCode::kParse,
                          model + ": the model is not in the frame of " + job_.mesh.string() +
                              ": " + alignment_figures(*a) +
                              ". Align it to the mesh first (texbake cameras align " +
                              job_.mesh.string() + " --cameras " + model +
                              " -o ALIGNED), or bake anyway with --no-alignment-check");
      case AlignmentVerdict::kDoubtful:
        warn(model + ": the model may not be in the frame of " + job_.mesh.string() + ": " +
             alignment_figures(*a) + " (--no-alignment-check: no check)");
        break;
      case AlignmentVerdict::kAligned:
        note("model " + model + " is in the mesh's frame: " + alignment_figures(*a));
        break;
    }
    return ok_status();
  }

  Status run_photos() {
    if (Status s = check_files(); !s) return s;
    auto stage = Clock::now();
    std::vector<std::string> notes;
    Expected<std::vector<Photo>> photos =
        job_.photo ? Expected<std::vector<Photo>>(std::vector<Photo>{*job_.photo})
                   : read_cameras(job_.cameras, job_.images, PhotoFolder::kNeeded, &notes);
    if (!photos) return photos.error();
    for (const std::string& n : notes) note(n);
    if (!job_.masks.empty()) {
      std::vector<std::string> mask_warnings;
      if (Status s = find_masks(*photos, job_.masks, "--masks", &mask_warnings); !s) return s;
      for (const std::string& w : mask_warnings) warn(w);
    }
    Expected<Held<LoadedMesh>> mesh = read_job_mesh();
    if (!mesh) return mesh.error();
    if (Status s = check_alignment(mesh->get().mesh); !s) return s;
    const double load = seconds_since(stage);
    PhotoBakeOptions options = job_.photo_options;
    options.consistency_warning = job_.alignment_check;
    if (job_.photo) options = camera_proxy_options(options);
    const RunOptions run = run_options();
    if (atlas()) {
      Expected<PhotoAtlas> baked =
          bake_atlas_texture_from_photos(mesh->get().mesh, *photos, options, job_.atlas, run);
      if (!baked) return photo_error(baked.error());
      pass_on(baked->atlas.stats);
      result_.stats = baked->atlas.stats;
      if (Status s = write_atlas_set(baked->atlas,
                                     [&](double write) {
                                       return photo_atlas_report(job_, *baked, load, write,
                                                                 seconds_since(start_));
                                     });
          !s) {
        return s;
      }
      const Counts& c = baked->atlas.stats.counts;
      summarise(
          "baked a %dx%d atlas (uv %s, %zu texels, %zu samples, %zu unseen, %zu padded) from %zu "
          "photos",
          job_.atlas.bake.size, job_.atlas.bake.size, to_string(baked->atlas.uv.used), c.texels,
          c.samples, c.occluded, c.padded, baked->cameras.size());
      return ok_status();
    }
    Expected<PhotoColors> baked =
        bake_vertex_colors_from_photos(mesh->get().mesh, *photos, options, run);
    if (!baked) return photo_error(baked.error());
    pass_on(baked->stats);
    result_.stats = baked->stats;
    if (Status s = write_vertex_set(mesh->get().mesh, baked->colors,
                                    [&](double write) {
                                      return photo_report(job_, *baked, load, write,
                                                          seconds_since(start_));
                                    });
        !s) {
      return s;
    }
    const Counts& c = baked->stats.counts;
    summarise("baked %zu vertices from %zu photos (%zu unseen, %zu filled, %zu unfilled)",
              c.vertices, baked->cameras.size(), c.occluded, c.filled, c.unfilled);
    return ok_status();
  }

  // ---- Layers ----

  // A layers bake's error about one layer ("layers[i]...": its files, its
  // cameras' model, photos or masks) names that layer; others are the mesh's.
  Error layer_error(const Error& error) const {
    if (error.message.rfind("layers[", 0) == 0) return error;
    return mesh_error(error);
  }

  Status run_layers() {
    if (Status s = check_files(); !s) return s;
    auto stage = Clock::now();
    Expected<LayersSpec> spec = read_layers(job_.layers);
    if (!spec) return spec.error();
    Expected<Held<LoadedMesh>> mesh = read_job_mesh(/*check_uv=*/false);
    if (!mesh) return mesh.error();
    if (atlas() && mesh->get().mesh.has_texture()) {
      // Nor the base texture, named by the mesh.
      const std::vector<NamedFile> read{{"the texture of MESH", mesh->get().mesh.texture_path}};
      if (Status s = check_distinct_files(read, job_outputs(files())); !s) return s;
    }
    // Each "cameras" layer's model, as a photo bake's.
    for (const LayerSpec& layer : spec->layers) {
      if (layer.cameras.empty()) continue;
      if (Status s = check_alignment(mesh->get().mesh, layer.cameras); !s) return s;
    }
    const double load = seconds_since(stage);
    LayersBakeOptions options = job_.layers_options;
    options.base = spec->base;
    options.base_color = spec->base_color;
    options.cache_mb = job_.cache_mb;
    const RunOptions run = run_options();
    if (atlas()) {
      if (spec->base == LayerBase::kMesh && mesh->get().mesh.has_texture() &&
          mesh->get().issues.other_material_primitives > 0) {
        warn(job_.mesh.string() + ": " +
             std::to_string(mesh->get().issues.other_material_primitives) +
             " primitive(s) use another material: base \"mesh\" is the first material's "
             "texture (" +
             mesh_texture_label(mesh->get().mesh) + ") over every triangle");
      }
      Expected<LayerAtlas> baked =
          bake_atlas_texture_from_layers(mesh->get().mesh, *spec, options, job_.atlas, run);
      if (!baked) return layer_error(baked.error());
      pass_on(baked->atlas.stats);
      result_.stats = baked->atlas.stats;
      if (Status s = write_atlas_set(baked->atlas,
                                     [&](double write) {
                                       return layers_atlas_report(job_, *baked, load, write,
                                                                  seconds_since(start_));
                                     });
          !s) {
        return s;
      }
      const Counts& c = baked->atlas.stats.counts;
      summarise(
          "baked a %dx%d atlas (uv %s, %zu texels, %zu samples, %zu uncovered, %zu padded) from "
          "%zu layers",
          baked->atlas.image.width, baked->atlas.image.height, to_string(baked->atlas.uv.used),
          c.texels, c.samples, c.occluded, c.padded, baked->layers.size());
      return ok_status();
    }
    Expected<LayerColors> baked =
        bake_vertex_colors_from_layers(mesh->get().mesh, *spec, options, run);
    if (!baked) return layer_error(baked.error());
    pass_on(baked->stats);
    result_.stats = baked->stats;
    if (Status s = write_vertex_set(mesh->get().mesh, baked->colors,
                                    [&](double write) {
                                      return layers_report(job_, *baked, load, write,
                                                           seconds_since(start_));
                                    });
        !s) {
      return s;
    }
    const Counts& c = baked->stats.counts;
    summarise("baked %zu vertices from %zu layers (%zu uncovered, %zu filled)", c.vertices,
              baked->layers.size(), c.occluded, c.filled);
    return ok_status();
  }

  const Job& job_;
  Clock::time_point start_;
  JobResult result_;
  BakeReport report_;  // the proxy bake's
};

}  // namespace

Expected<ResolvedProxy> resolve_proxy(const ProxySpec& spec, const MeshData& mesh,
                                      const std::string& mesh_name, ParamNaming naming,
                                      const RunOptions& run) {
  Expected<CompletedProxy> done = complete_proxy(spec, mesh, run, naming);
  if (!done) {
    // The mesh's shape, not the options, is at fault: name the mesh.
    if (category(done.error()) == ErrorCategory::kInput) {
      return make_error(done.error().code, mesh_name + ": " + done.error().message);
    }
    return done.error();
  }
  ResolvedProxy r{std::move(done->proxy), {}, {}, std::move(done->stats)};
  std::string names;
  for (const std::string& key : done->fitted) {
    const ParamField* field = find_field(spec.kind, key);
    r.fitted.emplace_back(naming == ParamNaming::kFlag && field ? field->flag : key);
    names += (names.empty() ? "" : " ") + r.fitted.back();
  }
  if (!r.fitted.empty()) {
    r.note = "fitted " + std::string(to_string(spec.kind)) + " (" + names + ") to " +
             std::to_string(done->points) + " vertices of " + mesh_name + ": " +
             proxy_to_json(r.proxy);
  }
  return r;
}

std::vector<std::string> image_warnings(const Image& image, const std::string& name) {
  std::vector<std::string> w;
  if (image.nonfinite_values > 0) {
    w.push_back(name + ": " + std::to_string(image.nonfinite_values) +
                " NaN or infinite values read as 0");
  }
  if (!image.unrecognised_color_space.empty()) {
    const bool linear = image.color_space == ColorSpace::kLinear;
    w.push_back(name + ": colour space '" + image.unrecognised_color_space +
                "' is neither sRGB nor linear: read as " +
                (linear ? "linear (float data)" : "sRGB (integer data)") +
                " (--texture-colorspace sets it)");
  }
  return w;
}

Expected<JobTarget> job_target(const std::string& target, const fs::path& output) {
  const std::string ext = lower_extension(output);
  if (ext != ".ply" && ext != ".obj" && ext != ".glb") {
    return make_error(ErrorCode::kInvalidArgument,
                      "-o " + output.string() + ": unknown output format '" + ext +
                          "' (texbake bake writes .ply, .obj and .glb)");
  }
  if (target == "atlas" && ext == ".ply") {
    return make_error(ErrorCode::kUnsupported,
                      "--target atlas cannot write " + output.string() +
                          ": PLY has no standard texture (use .obj or .glb)");
  }
  if (target == "vertex") return JobTarget::kVertex;
  if (target == "atlas") return JobTarget::kAtlas;
  if (!target.empty()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--target '" + target + "' is not vertex or atlas");
  }
  return ext == ".ply" ? JobTarget::kVertex : JobTarget::kAtlas;
}

int exit_code(const Error& error) {
  return category(error) == ErrorCategory::kUsage ? 2 : 1;
}

JobResult run_job(const Job& job) {
  return JobRun(job).run();
}

}  // namespace texbake
