#include "bake/cli/photo_target.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "bake/cli/atlas_target.h"
#include "bake/cli/choice_option.h"
#include "bake/cli/commands.h"
#include "bake/cli/file_checks.h"
#include "bake/cli/progress_bar.h"
#include "bake/cli/report.h"
#include "bake/util/timing.h"
#include "mesh_io/atomic_file.h"

namespace texbake::cli {

namespace {

namespace fs = std::filesystem;

const char* blend_name(PhotoBlend b) {
  return b == PhotoBlend::kSoft ? "soft" : b == PhotoBlend::kBest ? "best" : "mean";
}

nlohmann::ordered_json cameras_json(const std::vector<PhotoCameraStats>& cameras) {
  nlohmann::ordered_json cams = nlohmann::ordered_json::array();
  for (const PhotoCameraStats& s : cameras) {
    cams.push_back({{"image", s.name},
                    {"photo", {s.photo_width, s.photo_height}},
                    {"in_view", s.in_view},
                    {"visible", s.visible},
                    {"weight_share", s.weight_share},
                    {"gain", {s.gain[0], s.gain[1], s.gain[2]}}});
  }
  return cams;
}

// A bake error about a photo (bake/photo/photo_view.h: "the photo of
// camera ...", "no usable photo: ...") names the photo; other input errors
// are the mesh's (report_mesh_error).
int report_bake_error(const Error& error, const std::string& mesh) {
  const std::string& m = error.message;
  if (m.rfind("the photo of camera ", 0) == 0 || m.rfind("no usable photo", 0) == 0) {
    return report_error(error);
  }
  return report_mesh_error(error, mesh);
}

}  // namespace

nlohmann::ordered_json skipped_photos_json(const std::vector<SkippedPhoto>& skipped) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const SkippedPhoto& s : skipped) {
    out.push_back({{"image", s.name}, {"path", s.path.string()}, {"reason", s.reason}});
  }
  return out;
}

namespace {

// The report's "inputs": the cameras and photos folder, or for a camera
// --proxy-file its file and --texture.
nlohmann::ordered_json photo_inputs(const PhotoJob& job) {
  nlohmann::ordered_json in = {{"mesh", job.mesh}};
  if (job.single) {
    in["proxy_file"] = job.flags.cameras;
    in["texture"] = job.single->path.string();
  } else {
    in["cameras"] = job.flags.cameras;
    in["images"] = job.flags.images;
  }
  in["output"] = job.output;
  in["options"] = {{"blend", blend_name(job.flags.blend)},
                   {"exposure", job.flags.exposure == ExposureMode::kNone ? "none" : "gain"},
                   {"strict_photos", job.flags.strict_photos},
                   {"threads", job.threads}};
  return in;
}

// The atlas photo bake's --report: inputs, counts (atlas samples), the
// "atlas" object of the proxy atlas's report, one entry per camera (in_view
// and visible count atlas samples), timings.
std::string photo_atlas_report(const PhotoJob& job, const PhotoAtlas& baked, double load,
                               double write, double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "atlas";
  j["inputs"] = photo_inputs(job);
  const Stats& st = baked.atlas.stats;
  const Counts& c = st.counts;
  j["counts"] = {{"vertices", c.vertices},
                 {"triangles", c.triangles},
                 {"texels", c.texels},
                 {"samples", c.samples},
                 {"unseen", c.occluded},
                 {"filled", c.filled},
                 {"unfilled_vertices", c.unfilled},
                 {"padded", c.padded}};
  j["atlas"] = atlas_json(AtlasReport{job.atlas_options.bake, baked.atlas.uv}, st, write);
  j["cameras"] = cameras_json(baked.cameras);
  j["photos_skipped"] = skipped_photos_json(baked.skipped);
  const Timings& t = st.timings;
  j["timings"] = {{"load", load},
                  {"uv_layout", t.uv_layout},
                  {"rasterize", t.rasterize},
                  {"vertex_photos", t.fill},
                  {"scene_build", t.scene_build},
                  {"photos", t.bake},
                  {"pad", t.pad},
                  {"write", write},
                  {"total", total}};
  return j.dump(2) + "\n";
}

// The photo bake's --report: inputs, counts, timings and one entry per camera.
std::string photo_report(const PhotoJob& job, const PhotoColors& baked, double load, double write,
                         double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "vertex";
  j["inputs"] = photo_inputs(job);
  const Counts& c = baked.stats.counts;
  j["counts"] = {{"vertices", c.vertices},      {"triangles", c.triangles},
                 {"camera_samples", c.samples}, {"unseen", c.occluded},
                 {"filled", c.filled},          {"unfilled", c.unfilled}};
  j["cameras"] = cameras_json(baked.cameras);
  j["photos_skipped"] = skipped_photos_json(baked.skipped);
  const Timings& t = baked.stats.timings;
  j["timings"] = {{"load", load},     {"scene_build", t.scene_build},
                  {"photos", t.bake}, {"fill", t.fill},
                  {"write", write},   {"total", total}};
  return j.dump(2) + "\n";
}

}  // namespace

void add_photo_flags(CLI::App& cmd, PhotoFlags& flags) {
  cmd.add_option("--cameras", flags.cameras,
                 "bake from calibrated photos instead of --texture and a proxy: a COLMAP sparse "
                 "model folder (cameras + images .txt or .bin) or a JSON camera list "
                 "(vertex or atlas target)");
  cmd.add_option("--images", flags.images,
                 "--cameras: the photos' folder (default: a COLMAP workspace's images/ beside "
                 "sparse/, or the JSON list's folder)");
  add_choice_option(
      cmd, "--blend", flags.blend,
      {{"soft", PhotoBlend::kSoft}, {"best", PhotoBlend::kBest}, {"mean", PhotoBlend::kMean}},
      "--cameras: soft (weights favouring the best views, default), best (one "
      "photo per point) or mean");
  add_choice_option<std::optional<ExposureMode>>(
      cmd, "--exposure", flags.exposure,
      {{"gain", ExposureMode::kGain}, {"none", ExposureMode::kNone}},
      "--cameras: gain (one gain per photo and channel, least squares, default) or none");
  cmd.add_flag("--strict-photos", flags.strict_photos,
               "--cameras and --layers' \"cameras\": a photo that cannot be read (missing, "
               "unreadable) is an error (default: a warning naming it; the photo is left out "
               "and listed in the report's photos_skipped)");
}

namespace {

// The outputs (-o and, for an atlas .obj, its material and image), then
// --report: distinct from the inputs (MESH, the camera files and every photo
// they name, or a camera --proxy-file and its --texture) and each other
// (exit 2), writable (exit 1). Returns 0 or the exit code.
int check_outputs(const PhotoJob& job) {
  JobFileNames files;
  files.mesh = job.mesh;
  if (job.single) {
    files.proxy_file = job.flags.cameras;
    files.texture = job.single->path;
  } else {
    files.cameras = job.flags.cameras;
    files.images = job.flags.images;
  }
  files.output = job.output;
  files.atlas = job.atlas;
  files.write = job.write;
  files.report = job.report;
  if (Status s = check_job_before_work(files); !s) return report_error(s.error());
  return 0;
}

}  // namespace

int run_photo_bake(const PhotoJob& job) {
  const auto start = Clock::now();
  const fs::path output = job.output;
  if (Status s = validate_write(output, job.write, job.atlas); !s) return report_error(s.error());
  if (int code = check_outputs(job); code != 0) return code;
  auto stage = Clock::now();
  Expected<std::vector<Photo>> photos =
      job.single ? Expected<std::vector<Photo>>(std::vector<Photo>{*job.single})
                 : read_cameras(job.flags.cameras, job.flags.images);
  if (!photos) return report_error(photos.error());
  Expected<LoadedMesh> mesh = read_mesh(job.mesh, RunOptions{job.threads, {}});
  if (!mesh) return report_error(mesh.error());
  const double load = seconds_since(stage);
  if (job.atlas && job.atlas_options.uv == UvLayout::kMesh && !mesh->mesh.has_uvs()) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--uv mesh: " + job.mesh + " has no UV coordinates (use --uv generate)");
  }

  PhotoBakeOptions options;
  options.blend = job.flags.blend;
  options.exposure = job.flags.exposure.value_or(ExposureMode::kGain);
  options.occluded = job.occluded;
  options.occluded_color = job.occluded_color;
  options.color_space = job.color_space;
  options.strict_photos = job.flags.strict_photos;
  if (job.single) options = camera_proxy_options(options);
  ProgressBar bar(!job.quiet && ProgressBar::stderr_is_terminal());
  RunOptions run;
  run.threads = job.threads;
  run.progress = bar.callback();
  if (job.atlas) {
    Expected<PhotoAtlas> baked =
        bake_atlas_texture_from_photos(mesh->mesh, *photos, options, job.atlas_options, run);
    if (!baked) return report_bake_error(baked.error(), job.mesh);
    for (const std::string& w : baked->atlas.stats.warnings) {
      std::cerr << "texbake: warning: " << w << "\n";
    }
    std::string written;
    if (int code = write_atlas_outputs(
            output, baked->atlas, job.write, job.report,
            [&](double write) {
              return photo_atlas_report(job, *baked, load, write, seconds_since(start));
            },
            job.on_report, written);
        code != 0) {
      return code;
    }
    if (!job.quiet) {
      const Counts& c = baked->atlas.stats.counts;
      std::printf(
          "baked a %dx%d atlas (uv %s, %zu texels, %zu samples, %zu unseen, %zu padded) from %zu "
          "photos in %.2f s -> %s\n",
          job.atlas_options.bake.size, job.atlas_options.bake.size, to_string(baked->atlas.uv.used),
          c.texels, c.samples, c.occluded, c.padded, baked->cameras.size(), seconds_since(start),
          written.c_str());
      std::fflush(stdout);
    }
    return 0;
  }
  Expected<PhotoColors> baked = bake_vertex_colors_from_photos(mesh->mesh, *photos, options, run);
  if (!baked) return report_bake_error(baked.error(), job.mesh);
  for (const std::string& w : baked->stats.warnings) std::cerr << "texbake: warning: " << w << "\n";
  stage = Clock::now();
  if (Status s = write_vertex_colors(output, mesh->mesh, baked->colors, job.write); !s) {
    return report_error(s.error());
  }
  const double write = seconds_since(stage);
  const double total = seconds_since(start);
  const std::string report = photo_report(job, *baked, load, write, total);
  if (!job.report.empty()) {
    if (Status s = write_report_text(job.report, report); !s) return report_error(s.error());
  }
  if (job.on_report) job.on_report(report);
  if (!job.quiet) {
    const Counts& c = baked->stats.counts;
    std::printf(
        "baked %zu vertices from %zu photos (%zu unseen, %zu filled, %zu unfilled) in "
        "%.2f s -> %s\n",
        c.vertices, baked->cameras.size(), c.occluded, c.filled, c.unfilled, total,
        job.output.c_str());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace texbake::cli
