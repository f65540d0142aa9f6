// texbake cameras check MESH --cameras PATH [--images DIR] [--masks DIR] [--json]
// (SPEC section 9): per camera the share of the mesh's vertices in front of
// it, inside its photo, masked out (--masks) and visible, and a warning when a pose looks like a
// convention error (bake/photo/camera_check.h); then, for a COLMAP model
// with sparse points, whether it is in the mesh's frame (the figures of
// bake/fit/model_alignment.h, and a warning when it is not or may not be).
// texbake cameras align MESH --cameras MODEL -o OUT: the model moved into the
// mesh's frame (bake/fit/model_alignment.h's fit, or --transform).
// texbake cameras refine MESH --cameras MODEL -o OUT: every photo's pose
// refined so that the photos agree on the mesh (bake/photo/pose_refine.h),
// written as a COLMAP model of the input's form.
// texbake cameras convert IN -o OUT [--binary]: any camera format --cameras
// reads, written as a COLMAP model (mesh_io/colmap_model.h's writer, the one
// render --colmap uses).
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include "bake/cli/commands.h"
#include "bake/util/timing.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/camera_formats.h"
#include "mesh_io/colmap_model.h"
#include "mesh_io/point_pairs.h"
#include "texbake/geometry_options.h"
#include "texbake/report.h"
#include "texbake/texbake.h"

namespace texbake::cli {

namespace {

struct CamerasArgs {
  std::string mesh, cameras, images, masks;
  bool json = false;
  bool no_photos = false;
  int threads = 0;
};

struct ConvertArgs {
  std::string input, output, images;
  bool binary = false;
};

void print_notes(const std::vector<std::string>& notes) {
  for (const std::string& n : notes) std::fprintf(stderr, "texbake: %s\n", n.c_str());
}

int run_check(const CamerasArgs& a) {
  // The poses and photo sizes, which the model holds, are all the geometric
  // checks need; only the photo-consistency figures read the photos (and
  // are left out, with a note, when none can be read).
  std::vector<std::string> notes;
  Expected<std::vector<Photo>> photos =
      read_cameras(a.cameras, a.images, PhotoFolder::kNotNeeded, &notes);
  if (!photos) return report_error(photos.error());
  print_notes(notes);
  if (!a.masks.empty()) {
    std::vector<std::string> warnings;
    if (Status s = find_masks(*photos, a.masks, "--masks", &warnings); !s) {
      return report_error(s.error());
    }
    for (const std::string& w : warnings) std::fprintf(stderr, "texbake: warning: %s\n", w.c_str());
  }
  RunOptions run;
  run.threads = a.threads;
  Expected<LoadedMesh> mesh = read_mesh(a.mesh, run);
  if (!mesh) return report_error(mesh.error());
  // The geometric figures, the model's sparse points against the mesh and,
  // unless --no-photos, the photo agreement (read the photos one at a time;
  // not measured, with a note, when none can be read).
  Expected<CameraModelCheck> check =
      check_camera_model(mesh->mesh, *photos, a.cameras, !a.no_photos, run);
  if (!check) {
    // A mask file's error names it; others are the mesh's.
    if (check.error().message.rfind("the mask of camera ", 0) == 0) {
      return report_error(check.error());
    }
    return report_mesh_error(check.error(), a.mesh);
  }
  const std::vector<CameraCheck>& checks = check->cameras;
  const ModelAlignment& alignment = check->alignment;
  const bool masks = !a.masks.empty();
  const bool agreement = check->agreement_measured;
  // The bake's figures of camera `name` (null: not measured, or left out).
  const auto agreement_of = [&](const std::string& name) -> const PhotoCameraStats* {
    for (const PhotoCameraStats& c : check->agreement) {
      if (c.name == name) return &c;
    }
    return nullptr;
  };
  if (a.json) {
    nlohmann::ordered_json j = nlohmann::ordered_json::array();
    for (const CameraCheck& c : checks) {
      j.push_back({{"image", c.name},
                   {"in_front", c.in_front},
                   {"inside", c.inside},
                   {"masked", c.masked},
                   {"has_mask", c.has_mask},
                   {"visible", c.visible},
                   {"warnings", c.warnings}});
      if (agreement) {
        // null for a photo the bake left out (unreadable).
        nlohmann::ordered_json& last = j.back();
        last["shared"] = last["deviation"] = last["gain"] = nullptr;
        if (const PhotoCameraStats* p = agreement_of(c.name)) {
          last["shared"] = p->shared;
          last["deviation"] = p->deviation;
          last["gain"] = p->gain;
        }
      }
    }
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    // With --masks, a "masked" column: inside the photo but masked out (a
    // photo without a mask file: "-").
    // With the photos, "shared" (vertices it sees with another photo),
    // "deviation" (its mean relative deviation from their consensus) and
    // "gain" (its mean exposure gain); "-" for a photo left out.
    std::printf("%-32s %9s %9s", "image", "in front", "inside");
    if (masks) std::printf(" %9s", "masked");
    std::printf(" %9s", "visible");
    if (agreement) std::printf(" %9s %9s %6s", "shared", "deviation", "gain");
    std::printf("\n");
    for (const CameraCheck& c : checks) {
      std::printf("%-32s %8.1f%% %8.1f%%", c.name.c_str(), 100 * c.in_front, 100 * c.inside);
      if (masks && c.has_mask) std::printf(" %8.1f%%", 100 * c.masked);
      if (masks && !c.has_mask) std::printf(" %9s", "-");
      std::printf(" %8.1f%%", 100 * c.visible);
      if (const PhotoCameraStats* p = agreement_of(c.name)) {
        std::printf(" %9zu %8.1f%% %6.2f", p->shared, 100 * p->deviation,
                    (p->gain[0] + p->gain[1] + p->gain[2]) / 3);
      } else if (agreement) {
        std::printf(" %9s %9s %6s", "-", "-", "-");
      }
      std::printf("\n");
    }
  }
  if (!a.json && alignment.verdict != AlignmentVerdict::kNotMeasured) {
    std::printf("model alignment: %s: %s\n", to_string(alignment.verdict),
                alignment_figures(alignment).c_str());
  }
  if (!a.json && agreement) {
    std::printf("photo agreement: %s\n", consistency_figures(check->consistency).c_str());
  }
  std::fflush(stdout);
  if (!check->agreement_not_measured.empty()) {
    std::fprintf(stderr, "texbake: note: photo agreement not measured: %s\n",
                 check->agreement_not_measured.c_str());
  }
  for (const std::string& w : check->warnings) {
    std::fprintf(stderr, "texbake: warning: %s\n", w.c_str());
  }
  if (alignment.verdict == AlignmentVerdict::kMisaligned ||
      alignment.verdict == AlignmentVerdict::kDoubtful) {
    std::fprintf(stderr, "texbake: warning: %s: the model %s in the frame of %s: %s\n",
                 a.cameras.c_str(),
                 alignment.verdict == AlignmentVerdict::kMisaligned ? "is not" : "may not be",
                 a.mesh.c_str(), alignment_figures(alignment).c_str());
  }
  for (const CameraCheck& c : checks) {
    for (const std::string& w : c.warnings) {
      std::fprintf(stderr, "texbake: warning: %s: %s\n", c.name.c_str(), w.c_str());
    }
  }
  return 0;
}

// Before writing a COLMAP model into `out` (-o): its files, and those of the
// other form, which the write removes, may be none of `inputs` (a model
// written into its own folder), and `out` must be a folder if it exists.
Status check_model_output(std::vector<NamedFile> inputs, const std::filesystem::path& out) {
  std::vector<NamedFile> written;
  for (const char* stem : {"cameras", "images", "points3D"}) {
    for (const char* ext : {".txt", ".bin"}) {
      written.push_back({"-o", out / (std::string(stem) + ext)});
    }
  }
  if (Status s = check_distinct_files(inputs, written); !s) return s;
  std::error_code ec;
  if (std::filesystem::exists(out, ec) && !std::filesystem::is_directory(out, ec)) {
    return make_error(ErrorCode::kInvalidArgument,
                      "-o " + out.string() + " is a file: -o names the COLMAP model's folder");
  }
  return ok_status();
}

// texbake cameras align MESH --cameras MODEL -o OUT [--transform M |
// --correspondences FILE] [--binary]
struct AlignArgs {
  std::string mesh, cameras, output, transform, correspondences;
  bool binary = false;
  int threads = 0;
};

// The 16 numbers of --transform ("a,b,c,...", row by row) as a similarity.
Expected<Similarity> parse_transform(const std::string& text) {
  std::vector<double> m;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = text.find(',', start);
    Expected<double> v =
        parse_number_option(std::string_view(text).substr(
                                start, comma == std::string::npos ? text.npos : comma - start),
                            "--transform");
    if (!v) return v.error();
    m.push_back(*v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return similarity_from_matrix(m, "--transform");
}

// "a,b,c,...": the 4x4 matrix of `s`, row by row, as --transform takes it.
std::string transform_text(const Similarity& s) {
  std::string text;
  char buf[40];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      std::snprintf(buf, sizeof buf, "%.9g,", s.scale * s.r[3 * i + j]);
      text += buf;
    }
    std::snprintf(buf, sizeof buf, "%.9g,", i == 0 ? s.t.x : i == 1 ? s.t.y : s.t.z);
    text += buf;
  }
  return text + "0,0,0,1";
}

int run_align(const AlignArgs& a) {
  namespace fs = std::filesystem;
  const fs::path out = a.output;
  std::vector<NamedFile> inputs = camera_files(a.cameras, {}, "--cameras");
  inputs.push_back({"MESH", a.mesh});
  if (!a.correspondences.empty()) inputs.push_back({"--correspondences", a.correspondences});
  if (Status s = check_model_output(inputs, out); !s) return report_error(s.error());
  std::error_code ec;
  if (!fs::is_directory(a.cameras, ec)) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--cameras " + a.cameras +
                            ": cameras align takes a COLMAP model folder (texbake cameras "
                            "convert writes one from the other formats)");
  }
  std::optional<Similarity> given;
  std::size_t paired_line = 0, paired_count = 0;
  if (!a.transform.empty()) {
    Expected<Similarity> t = parse_transform(a.transform);
    if (!t) return report_error(t.error());
    given = *t;
  }
  std::optional<PairFit> paired;
  if (!a.correspondences.empty()) {
    Expected<PointPairs> pairs = read_point_pairs(a.correspondences);
    if (!pairs) return report_error(pairs.error());
    Expected<PairFit> f = similarity_from_pairs(pairs->model, pairs->mesh);
    if (!f) {
      // The file's content: exit 1, as a file that does not parse.
      return report_error(ErrorCode::kParse, a.correspondences + ": " + f.error().message);
    }
    paired = *f;
    paired_line = pairs->lines[f->worst];
    paired_count = pairs->model.size();
    given = f->transform;
  }
  Expected<std::vector<ColmapImage>> images = read_colmap_model(a.cameras);
  if (!images) return report_error(images.error());
  Expected<std::vector<Vec3>> points = read_colmap_points(a.cameras);
  if (!points) return report_error(points.error());
  RunOptions run;
  run.threads = a.threads;
  Expected<LoadedMesh> mesh = read_mesh(a.mesh, run);
  if (!mesh) return report_error(mesh.error());
  const double mesh_size = bounding_diagonal(mesh->mesh);

  ModelFit fit;
  if (given) {
    fit.transform = *given;
    std::vector<Vec3> moved;
    for (const Vec3& p : *points) moved.push_back(given->apply(p));
    Expected<ModelAlignment> before = measure_model_alignment(mesh->mesh, *points, a.threads);
    Expected<ModelAlignment> after = measure_model_alignment(mesh->mesh, moved, a.threads);
    if (!before) return report_mesh_error(before.error(), a.mesh);
    if (!after) return report_mesh_error(after.error(), a.mesh);
    fit.before = *before;
    fit.after = *after;
  } else {
    Expected<ModelFit> found = fit_model_to_mesh(mesh->mesh, *points, a.threads);
    if (!found) {
      Error e = found.error();
      e.message = a.cameras + ": " + e.message;
      return report_error(e);
    }
    fit = *found;
    if (fit.after.verdict == AlignmentVerdict::kMisaligned) {
      return report_error(ErrorCode::kParse,
                          a.cameras + ": no similarity brings the model's sparse points onto " +
                              a.mesh + " (best: " + alignment_figures(fit.after) +
                              "); give the transform with --transform");
    }
  }
  for (ColmapImage& image : *images) {
    Expected<CameraProjector> moved = transform_camera(image.camera, fit.transform);
    if (!moved) return report_error(moved.error());
    image.camera = std::move(*moved);
  }
  std::vector<Vec3> moved_points;
  for (const Vec3& p : *points) moved_points.push_back(fit.transform.apply(p));
  if (Status s = write_colmap_model(out, *images, a.binary, nullptr, moved_points); !s) {
    return report_error(s.error());
  }
  if (fit.after.verdict == AlignmentVerdict::kDoubtful ||
      (given && fit.after.verdict == AlignmentVerdict::kMisaligned)) {
    std::fprintf(stderr, "texbake: warning: %s: the aligned model %s in the frame of %s: %s\n",
                 out.c_str(),
                 fit.after.verdict == AlignmentVerdict::kMisaligned ? "is not" : "may not be",
                 a.mesh.c_str(), alignment_figures(fit.after).c_str());
  }
  std::printf("aligned %zu images and %zu sparse points of %s to %s -> %s\n", images->size(),
              points->size(), a.cameras.c_str(), a.mesh.c_str(), out.c_str());
  std::printf("transform: %s (scale %.6g)\n", transform_text(fit.transform).c_str(),
              fit.transform.scale);
  if (fit.before.verdict != AlignmentVerdict::kNotMeasured) {
    std::printf("before: %s\nafter: %s\n", alignment_figures(fit.before).c_str(),
                alignment_figures(fit.after).c_str());
  }
  if (paired) {
    auto percent = [&](double d) { return mesh_size > 0 ? 100 * d / mesh_size : 0.0; };
    std::printf(
        "correspondences: %zu pairs, RMS %.6g (%.3g %% of the mesh's size), largest %.6g "
        "(line %zu)\n",
        paired_count, paired->rms, percent(paired->rms), paired->largest, paired_line);
    if (paired->rms > kAlignmentNearDistance * mesh_size) {
      std::fprintf(stderr,
                   "texbake: warning: %s: the pairs do not agree on one similarity: RMS %.3g %% "
                   "of the mesh's size, the largest %.3g %% at line %zu (a mistyped or "
                   "misplaced pair?)\n",
                   a.correspondences.c_str(), percent(paired->rms), percent(paired->largest),
                   paired_line);
    }
  }
  return 0;
}

// texbake cameras refine MESH --cameras MODEL -o OUT [options]
struct RefineArgs {
  std::string mesh, cameras, images, masks, output, report;
  PoseRefineOptions options;
  std::string colorspace = "auto";
  int threads = 0;
  bool quiet = false;
};

// The --report of cameras refine: inputs and options, per photo its
// changes, residuals and flags, the photos left out, timings.
std::string refine_report(const RefineArgs& a, const RefinedCameras& r, bool binary, double load,
                          double write, double total) {
  nlohmann::ordered_json photos = nlohmann::ordered_json::array();
  for (const RefinedPose& p : r.photos) {
    nlohmann::ordered_json j = {{"image", p.name},
                                {"skipped", p.skipped},
                                {"rotation_change_deg", p.rotation_change_deg},
                                {"translation_change", p.translation_change}};
    if (a.options.intrinsics) j["focal_change"] = p.focal_change;
    j["residual_before"] = p.residual_before;
    j["residual_after"] = p.residual_after;
    j["samples_before"] = p.samples_before;
    j["samples_after"] = p.samples_after;
    j["iterations"] = p.iterations;
    j["clamped"] = p.clamped;
    j["gain"] = p.gain;
    photos.push_back(std::move(j));
  }
  const PoseRefineOptions& o = a.options;
  nlohmann::ordered_json j = {{"command", "cameras refine"},
                              {"inputs",
                               {{"mesh", a.mesh},
                                {"cameras", a.cameras},
                                {"images", a.images},
                                {"output", a.output},
                                {"format", binary ? "binary" : "text"},
                                {"options",
                                 {{"intrinsics", o.intrinsics},
                                  {"max_rotation", o.max_rotation_deg},
                                  {"max_translation", o.max_translation},
                                  {"iterations", o.iterations},
                                  {"threads", a.threads}}}}},
                              {"points", r.points},
                              {"levels", r.levels},
                              {"mesh_size", r.mesh_size},
                              {"photos", std::move(photos)},
                              {"photos_skipped", skipped_photos_json(r.skipped)},
                              {"warnings", r.stats.warnings},
                              {"timings",
                               {{"load", load},
                                {"scene_build", r.stats.timings.scene_build},
                                {"refine", r.stats.timings.bake},
                                {"write", write},
                                {"total", total}}}};
  return j.dump(2) + "\n";
}

int run_refine(const RefineArgs& a) {
  namespace fs = std::filesystem;
  const auto start = Clock::now();
  const fs::path out = a.output;
  std::error_code ec;
  if (!fs::is_directory(a.cameras, ec)) {
    return report_error(ErrorCode::kInvalidArgument,
                        "--cameras " + a.cameras +
                            ": cameras refine takes a COLMAP model folder (texbake cameras "
                            "convert writes one from the other formats)");
  }
  std::vector<NamedFile> inputs = camera_files(a.cameras, a.images, "--cameras", a.masks);
  inputs.push_back({"MESH", a.mesh});
  if (Status s = check_model_output(inputs, out); !s) return report_error(s.error());
  if (!a.report.empty()) {
    std::vector<NamedFile> taken = inputs;
    for (const char* stem : {"cameras", "images", "points3D"}) {
      for (const char* ext : {".txt", ".bin"}) {
        taken.push_back({"-o", out / (std::string(stem) + ext)});
      }
    }
    if (Status s = check_distinct_files(taken, {{"--report", a.report}}); !s) {
      return report_error(s.error());
    }
  }
  PoseRefineOptions options = a.options;
  Expected<TextureColorSpace> cs =
      parse_choice<TextureColorSpace>(a.colorspace, "--texture-colorspace");
  if (!cs) return report_error(cs.error());
  options.color_space = *cs;
  // The model as stored (ids, names, its sparse points) and its photos.
  const bool binary = fs::exists(fs::path(a.cameras) / "cameras.bin", ec) &&
                      fs::exists(fs::path(a.cameras) / "images.bin", ec);
  Expected<std::vector<ColmapImage>> images = read_colmap_model(a.cameras);
  if (!images) return report_error(images.error());
  Expected<std::vector<Vec3>> points = read_colmap_points(a.cameras);
  if (!points) return report_error(points.error());
  Expected<std::vector<Photo>> photos = read_cameras(a.cameras, a.images);
  if (!photos) return report_error(photos.error());
  if (!a.masks.empty()) {
    std::vector<std::string> warnings;
    if (Status s = find_masks(*photos, a.masks, "--masks", &warnings); !s) {
      return report_error(s.error());
    }
    for (const std::string& w : warnings) std::fprintf(stderr, "texbake: warning: %s\n", w.c_str());
  }
  RunOptions run;
  run.threads = a.threads;
  Expected<LoadedMesh> mesh = read_mesh(a.mesh, run);
  if (!mesh) return report_error(mesh.error());
  const double load = seconds_since(start);
  Expected<RefinedCameras> refined = refine_cameras(mesh->mesh, *photos, options, run);
  if (!refined) return report_mesh_error(refined.error(), a.mesh);
  for (std::size_t i = 0; i < images->size(); ++i) {
    (*images)[i].camera = refined->photos[i].camera;
  }
  const auto write_start = Clock::now();
  AtomicFileSet set;
  if (Status s = write_colmap_model(out, *images, binary, &set, *points); !s) {
    return report_error(s.error());
  }
  if (!a.report.empty()) {
    const double write = seconds_since(write_start);
    const std::string text = refine_report(a, *refined, binary, load, write, seconds_since(start));
    Status s = set.stage(a.report, [&](const fs::path& temp) -> Status {
      FILE* f = std::fopen(temp.c_str(), "wb");
      if (!f) return make_error(ErrorCode::kIo, a.report + ": cannot be written");
      const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
      if (std::fclose(f) != 0 || !ok) {
        return make_error(ErrorCode::kIo, a.report + ": cannot be written");
      }
      return ok_status();
    });
    if (!s) return report_error(s.error());
  }
  if (Status s = set.commit(); !s) return report_error(s.error());
  for (const std::string& w : refined->stats.warnings) {
    std::fprintf(stderr, "texbake: warning: %s\n", w.c_str());
  }
  if (!a.quiet) {
    std::printf("%-28s %9s %9s %21s %6s\n", "image", "rotation", "centre", "residual", "steps");
    for (const RefinedPose& p : refined->photos) {
      if (p.skipped) {
        std::printf("%-28s (left out: its photo cannot be read)\n", p.name.c_str());
        continue;
      }
      std::printf("%-28s %8.4f%c %8.4f%% %9.5f -> %9.5f %6d%s\n", p.name.c_str(),
                  p.rotation_change_deg, 'd', 100 * p.translation_change, p.residual_before,
                  p.residual_after, p.iterations, p.clamped ? "  clamped" : "");
    }
    std::printf("refined %zu photos of %s on %s (%zu points, %d levels) -> %s\n",
                refined->photos.size() - refined->skipped.size(), a.cameras.c_str(), a.mesh.c_str(),
                refined->points, refined->levels, out.c_str());
  }
  return 0;
}

int run_convert(const ConvertArgs& a) {
  namespace fs = std::filesystem;
  const fs::path out = a.output;
  if (Status s = check_model_output(camera_files(a.input, {}, "IN"), out); !s) {
    return report_error(s.error());
  }
  std::error_code ec;
  std::vector<ColmapImage> images;
  std::vector<std::string> notes;
  std::string format = "COLMAP model";
  if (fs::is_directory(a.input, ec)) {
    // Read as COLMAP stores it, image ids kept.
    Expected<std::vector<ColmapImage>> model = read_colmap_model(a.input);
    if (!model) return report_error(model.error());
    images = std::move(model).value();
  } else {
    Expected<CameraFile> file = read_camera_file(a.input);
    if (!file) return report_error(file.error());
    format = camera_format_name(file->format);
    notes = std::move(file->notes);
    // The photos' folder: --images, else the file's (as --cameras).
    fs::path base = a.images.empty() ? fs::path(a.input).parent_path() : fs::path(a.images);
    if (base.empty()) base = ".";
    uint32_t id = 0;
    std::size_t unfound = 0;
    for (CameraListEntry& entry : file->cameras) {
      ++id;
      // A Metashape label gets the extension of the photo found for it.
      std::string name = std::move(entry.image);
      const fs::path photo = camera_photo_path(file->format, name, base);
      // An absolute path (Meshroom's) inside the photos' folder becomes
      // relative to it, as the model's names are.
      if (fs::path(name).is_absolute()) {
        const fs::path rel = fs::path(name).lexically_normal().lexically_relative(
            fs::absolute(base, ec).lexically_normal());
        if (!rel.empty() && *rel.begin() != "..") name = rel.generic_string();
      }
      if (!fs::path(name).has_extension()) {
        if (photo.has_extension()) {
          name += photo.extension().string();
        } else {
          ++unfound;
        }
      }
      images.push_back({id, 0, std::move(name), std::move(entry.camera)});
    }
    notes.push_back("the images' names are relative to " + base.string() +
                    ": bake with --cameras " + out.string() + " --images " + base.string());
    if (unfound != 0 && file->format == CameraFormat::kMetashape) {
      notes.push_back(std::to_string(unfound) + " label" + (unfound == 1 ? " has" : "s have") +
                      " no extension and no photo of that name was found in " + base.string() +
                      " to complete it (give the photos' folder with --images)");
    }
  }
  // A name the model cannot hold: a line break or NUL ends a record, and
  // the text form's reader trims blanks at the name's ends.
  for (const ColmapImage& image : images) {
    const std::string& n = image.name;
    const bool blank_end = std::string(" \t").find(n.front()) != std::string::npos ||
                           std::string(" \t").find(n.back()) != std::string::npos;
    if (n.find_first_of(std::string("\n\r\0", 3)) != std::string::npos ||
        (!a.binary && blank_end)) {
      return report_error(ErrorCode::kParse, a.input + ": the image name '" + image.name +
                                                 "' cannot be written in a COLMAP model");
    }
  }
  if (Status s = write_colmap_model(out, images, a.binary); !s) return report_error(s.error());
  print_notes(notes);
  std::printf(
      "converted %zu images from a %s into a COLMAP model: %s (%s)\n", images.size(),
      std::string(format).c_str(), out.string().c_str(),
      a.binary ? "cameras.bin, images.bin, points3D.bin" : "cameras.txt, images.txt, points3D.txt");
  return 0;
}

}  // namespace

RunFunction add_cameras_command(CLI::App& app) {
  auto args = std::make_shared<CamerasArgs>();
  CLI::App* cmd = app.add_subcommand(
      "cameras",
      "Check calibrated cameras against a mesh, align a COLMAP model to it, refine its poses "
      "from the photos, or convert cameras to a COLMAP model.");
  cmd->require_subcommand(1);
  auto convert_args = std::make_shared<ConvertArgs>();
  CLI::App* check = cmd->add_subcommand(
      "check",
      "Per camera: the share of the mesh's vertices in front of it, inside its photo and "
      "visible from it, with a warning when a pose looks like a convention error "
      "(camera-to-world given as world-to-camera, OpenGL axes).");
  check->add_option("mesh", args->mesh, "input mesh (.obj, .ply, .off, .stl, .glb, .gltf)")
      ->required();
  check
      ->add_option(
          "--cameras", args->cameras,
          "a COLMAP sparse model folder or a camera file: a JSON camera list, a "
          "nerfstudio / instant-ngp transforms.json, a Metashape cameras.xml or a Meshroom / "
          "AliceVision .sfm (as bake --cameras)")
      ->required();
  check->add_option("--images", args->images,
                    "the photos' folder, as bake --cameras finds it (only the photo-consistency "
                    "figures read the photos; the rest needs none)");
  check->add_option("--masks", args->masks,
                    "the photos' masks in COLMAP's convention (DIR/<image name>.png, 0 = masked "
                    "out, as bake --masks): the visible share counts only vertices on unmasked "
                    "pixels, and a column 'masked' gives the share inside the photo but masked "
                    "out");
  check->add_flag("--json", args->json, "print the table as JSON");
  check->add_flag("--no-photos", args->no_photos,
                  "do not read the photos: no photo-consistency figures (shared, deviation, "
                  "gain and the photo agreement line; by default they are measured as a photo "
                  "bake measures them when two photos or more can be read)");
  check->add_option("--threads", args->threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  CLI::App* convert = cmd->add_subcommand(
      "convert",
      "Write the cameras of any format --cameras reads (a COLMAP model, a JSON camera list, a "
      "nerfstudio / instant-ngp transforms.json, a Metashape cameras.xml, a Meshroom .sfm) as a "
      "COLMAP model: "
      "cameras, images and an "
      "empty points3D, all written or none.");
  convert->add_option("IN", convert_args->input, "the cameras: a COLMAP model folder or a file")
      ->required();
  convert
      ->add_option("-o,--output", convert_args->output,
                   "the COLMAP model's folder (created if missing; a model of the other form "
                   "there is replaced)")
      ->required();
  convert->add_option("--images", convert_args->images,
                      "the photos' folder, which the images' names are made relative to "
                      "(default: the camera file's folder, as bake --cameras; an absolute path "
                      "inside it is made relative); a Metashape label without an extension "
                      "gets its photo's");
  convert->add_flag("--binary", convert_args->binary,
                    "write cameras.bin, images.bin, points3D.bin (default: the .txt files)");
  auto align_args = std::make_shared<AlignArgs>();
  CLI::App* align = cmd->add_subcommand(
      "align",
      "Bring a COLMAP model into the mesh's frame: the similarity (scale, rotation, "
      "translation) that puts its sparse points on the mesh's surface (found from the points' "
      "principal axes and refined by trimmed ICP with scale), the one --transform gives, or "
      "the one that best fits the point pairs of --correspondences (for a model without "
      "sparse points), applied to every pose and point; written as a COLMAP model.");
  align->add_option("mesh", align_args->mesh, "the mesh (.obj, .ply, .off, .stl, .glb, .gltf)")
      ->required();
  align->add_option("--cameras", align_args->cameras, "the COLMAP sparse model folder to align")
      ->required();
  align
      ->add_option("-o,--output", align_args->output,
                   "the aligned model's folder (created if missing; a model of the other form "
                   "there is replaced)")
      ->required();
  CLI::Option* transform =
      align
          ->add_option("--transform", align_args->transform,
                       "a known similarity instead of the fit: a 4x4 matrix, 16 numbers row by "
                       "row (model to mesh; the last row 0,0,0,1), as align prints it")
          ->type_name("M00,M01,...,M33");
  align
      ->add_option("--correspondences", align_args->correspondences,
                   "the similarity of point pairs instead of the fit (least squares, Umeyama): "
                   "a text file, one pair a line, the model's x y z then the mesh's X Y Z "
                   "(spaces or commas; '#' comments); at least 3 points not on a line")
      ->type_name("FILE")
      ->excludes(transform);
  align->add_flag("--binary", align_args->binary,
                  "write cameras.bin, images.bin, points3D.bin (default: the .txt files)");
  align->add_option("--threads", align_args->threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  auto refine_args = std::make_shared<RefineArgs>();
  CLI::App* refine = cmd->add_subcommand(
      "refine",
      "Refine every photo's pose (6 degrees of freedom; with --intrinsics also its focal length "
      "and principal point) so that the photos agree on the mesh: minimises the differences, in "
      "linear light, between each photo's colour at the mesh's surface points and the other "
      "photos' consensus there, with exposure gains per photo solved jointly, coarse to fine "
      "over a pyramid of the photos, with the visibility of the photo bake and points near "
      "depth discontinuities left out. Each change is bounded (--max-rotation, "
      "--max-translation; a photo that reaches a bound is clamped and flagged) and reported. "
      "Written as a COLMAP model of the input's form (text or binary), its sparse points kept.");
  refine->add_option("mesh", refine_args->mesh, "the mesh (.obj, .ply, .off, .stl, .glb, .gltf)")
      ->required();
  refine->add_option("--cameras", refine_args->cameras, "the COLMAP sparse model folder to refine")
      ->required();
  refine->add_option("--images", refine_args->images,
                     "the photos' folder (default: the workspace's images/ beside sparse/)");
  refine->add_option("--masks", refine_args->masks,
                     "the photos' masks in COLMAP's convention (DIR/<image name>.png, 0 = masked "
                     "out, as bake --masks): masked-out pixels are never sampled");
  refine
      ->add_option("-o,--output", refine_args->output,
                   "the refined model's folder (created if missing; a model of the other form "
                   "there is replaced); never the input's")
      ->required();
  refine->add_flag("--intrinsics", refine_args->options.intrinsics,
                   "also refine each photo's focal length(s) and principal point (per photo: "
                   "images that shared a camera get one each)");
  refine
      ->add_option("--max-rotation", refine_args->options.max_rotation_deg,
                   "the most a photo's rotation may change, in degrees")
      ->default_val(PoseRefineOptions{}.max_rotation_deg)
      ->check(CLI::Range(1e-6, 180.0));
  refine
      ->add_option("--max-translation", refine_args->options.max_translation,
                   "the most a photo's centre may move, as a fraction of the mesh's size (its "
                   "bounding-box diagonal)")
      ->default_val(PoseRefineOptions{}.max_translation)
      ->check(CLI::Range(1e-9, 1e6));
  refine
      ->add_option("--iterations", refine_args->options.iterations,
                   "the most Gauss-Newton steps per pyramid level")
      ->default_val(PoseRefineOptions{}.iterations)
      ->check(CLI::Range(1, 1000));
  refine->add_option("--report", refine_args->report,
                     "write a JSON report: per photo the rotation change (degrees), the centre's "
                     "move (fraction of the mesh's size), the residual before and after, the "
                     "steps taken, whether it was clamped, its gains");
  refine
      ->add_option("--texture-colorspace", refine_args->colorspace,
                   "the photos' encoding: auto (8/16-bit sRGB, float linear), srgb or linear")
      ->default_val("auto");
  refine->add_flag("--strict-photos", refine_args->options.strict_photos,
                   "a photo that cannot be read is an error (default: it is left out with a "
                   "warning and its pose written unchanged)");
  refine->add_flag("-q,--quiet", refine_args->quiet, "print no table");
  refine->add_option("--threads", refine_args->threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  return [args, convert_args, align_args, refine_args, check, align, refine] {
    if (check->parsed()) return run_check(*args);
    if (align->parsed()) return run_align(*align_args);
    if (refine->parsed()) return run_refine(*refine_args);
    return run_convert(*convert_args);
  };
}

}  // namespace texbake::cli
