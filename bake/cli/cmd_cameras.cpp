// texbake cameras check MESH --cameras PATH [--images DIR] [--json]
// (SPEC section 9): per camera the share of the mesh's vertices in front of
// it, inside its photo and visible, and a warning when a pose looks like a
// convention error (bake/photo/camera_check.h); then, for a COLMAP model
// with sparse points, whether it is in the mesh's frame (the figures of
// bake/fit/model_alignment.h, and a warning when it is not or may not be).
#include <cstdio>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "bake/cli/commands.h"
#include "texbake/texbake.h"

namespace texbake::cli {

namespace {

struct CamerasArgs {
  std::string mesh, cameras, images;
  bool json = false;
  int threads = 0;
};

int run_check(const CamerasArgs& a) {
  // Only the poses and photo sizes are needed, which the model holds: no
  // photos folder (and no photo) is needed.
  Expected<std::vector<Photo>> photos = read_cameras(a.cameras, a.images, PhotoFolder::kNotNeeded);
  if (!photos) return report_error(photos.error());
  RunOptions run;
  run.threads = a.threads;
  Expected<LoadedMesh> mesh = read_mesh(a.mesh, run);
  if (!mesh) return report_error(mesh.error());
  Expected<std::vector<CameraCheck>> checks = check_cameras(mesh->mesh, *photos, run);
  if (!checks) return report_mesh_error(checks.error(), a.mesh);
  // The model's sparse points against the mesh (a COLMAP model with points3D).
  Expected<ModelAlignment> alignment = check_model_alignment(mesh->mesh, a.cameras, run);
  if (!alignment) return report_mesh_error(alignment.error(), a.mesh);
  std::size_t warned = 0;
  for (const CameraCheck& c : *checks) warned += !c.warnings.empty();
  if (a.json) {
    nlohmann::ordered_json j = nlohmann::ordered_json::array();
    for (const CameraCheck& c : *checks) {
      j.push_back({{"image", c.name},
                   {"in_front", c.in_front},
                   {"inside", c.inside},
                   {"visible", c.visible},
                   {"warnings", c.warnings}});
    }
    std::printf("%s\n", j.dump(2).c_str());
  } else {
    std::printf("%-32s %9s %9s %9s\n", "image", "in front", "inside", "visible");
    for (const CameraCheck& c : *checks) {
      std::printf("%-32s %8.1f%% %8.1f%% %8.1f%%\n", c.name.c_str(), 100 * c.in_front,
                  100 * c.inside, 100 * c.visible);
    }
  }
  if (!a.json && alignment->verdict != AlignmentVerdict::kNotMeasured) {
    std::printf("model alignment: %s: %s\n", to_string(alignment->verdict),
                alignment_figures(*alignment).c_str());
  }
  std::fflush(stdout);
  if (alignment->verdict == AlignmentVerdict::kMisaligned ||
      alignment->verdict == AlignmentVerdict::kDoubtful) {
    std::fprintf(stderr, "texbake: warning: %s: the model %s in the frame of %s: %s\n",
                 a.cameras.c_str(),
                 alignment->verdict == AlignmentVerdict::kMisaligned ? "is not" : "may not be",
                 a.mesh.c_str(), alignment_figures(*alignment).c_str());
  }
  for (const CameraCheck& c : *checks) {
    for (const std::string& w : c.warnings) {
      std::fprintf(stderr, "texbake: warning: %s: %s\n", c.name.c_str(), w.c_str());
    }
  }
  return 0;
}

}  // namespace

RunFunction add_cameras_command(CLI::App& app) {
  auto args = std::make_shared<CamerasArgs>();
  CLI::App* cmd = app.add_subcommand("cameras", "Inspect calibrated cameras against a mesh.");
  cmd->require_subcommand(1);
  CLI::App* check = cmd->add_subcommand(
      "check",
      "Per camera: the share of the mesh's vertices in front of it, inside its photo and "
      "visible from it, with a warning when a pose looks like a convention error "
      "(camera-to-world given as world-to-camera, OpenGL axes).");
  check->add_option("mesh", args->mesh, "input mesh (.obj, .ply, .off, .stl, .glb, .gltf)")
      ->required();
  check
      ->add_option("--cameras", args->cameras,
                   "a COLMAP sparse model folder or a JSON camera list (as bake --cameras)")
      ->required();
  check->add_option("--images", args->images,
                    "the photos' folder (not needed: the check reads no photo; accepted as in "
                    "bake --cameras)");
  check->add_flag("--json", args->json, "print the table as JSON");
  check->add_option("--threads", args->threads, "worker threads (default: all cores)")
      ->check(CLI::Range(1, 4096));
  return [args] { return run_check(*args); };
}

}  // namespace texbake::cli
