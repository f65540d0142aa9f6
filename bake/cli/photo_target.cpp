#include "bake/cli/photo_target.h"

#include "bake/cli/choice_option.h"

namespace texbake::cli {

void add_photo_flags(CLI::App& cmd, PhotoFlags& flags) {
  cmd.add_option("--cameras", flags.cameras,
                 "bake from calibrated photos instead of --texture and a proxy: a COLMAP sparse "
                 "model folder (cameras + images .txt or .bin) or a camera file, told by its "
                 "content: a JSON camera list, a nerfstudio / instant-ngp transforms.json or a "
                 "Metashape cameras.xml "
                 "(vertex or atlas target)");
  cmd.add_option("--images", flags.images,
                 "--cameras: the photos' folder (default: a COLMAP workspace's images/ beside "
                 "sparse/, or the camera file's folder)");
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

}  // namespace texbake::cli
