// refine_cameras: bake/photo/pose_refine.h behind the API's conventions.
#include "bake/texbake/run.h"
#include "bake/util/progress.h"
#include "bake/util/timing.h"
#include "texbake/texbake.h"

namespace texbake {

Expected<RefinedCameras> refine_cameras(const MeshData& mesh, const std::vector<Photo>& photos,
                                        const PoseRefineOptions& options, const RunOptions& run) {
  const auto start = Clock::now();
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<RefinedCameras>(run, [&]() -> Expected<RefinedCameras> {
    progress.start("photos", photos.size());
    const TextureColorSpace cs = options.color_space;
    const PhotoReader reader = [&progress, cs](const Photo& photo) -> Expected<PhotoImage> {
      if (progress.cancelled()) return cancelled_error();
      Expected<Image> image = read_image(photo.path, {cs});
      progress.advance(1);
      if (!image) return image.error();
      return PhotoImage{image->width, image->height, std::move(image->pixels), image->color_space};
    };
    Expected<PoseRefineResult> refined = refine_poses(mesh, photos, options, reader, &progress);
    if (progress.cancelled()) return cancelled_error();
    if (!refined) {
      // Option and photo-count errors are the caller's; the rest the input's.
      if (refined.error().code == ErrorCode::kInvalidArgument) return refined.error();
      return detail::as_input(refined.error());
    }
    RefinedCameras out;
    out.photos = std::move(refined->photos);
    out.skipped = std::move(refined->skipped);
    out.points = refined->points;
    out.levels = refined->levels;
    out.mesh_size = refined->mesh_size;
    Counts& c = out.stats.counts;
    c = detail::mesh_counts(mesh);
    c.samples = refined->points;
    out.stats.warnings = std::move(refined->warnings);
    Timings& t = out.stats.timings;
    t.scene_build = refined->seconds_scene;
    t.bake = refined->seconds_photos + refined->seconds_refine;
    t.total = seconds_since(start);
    return out;
  });
}

}  // namespace texbake
