// read_cameras, bake_vertex_colors_from_photos and
// bake_atlas_texture_from_photos: mesh_io's COLMAP and camera file readers
// and bake/photo behind the API's conventions.
#include <string>
#include <system_error>
#include <utility>

#include "bake/texbake/run.h"
#include "bake/util/progress.h"
#include "bake/util/timing.h"
#include "mesh_io/camera_formats.h"
#include "mesh_io/colmap_model.h"
#include "mesh_io/proxy_json.h"
#include "mesh_io/regular_file.h"
#include "texbake/texbake.h"

namespace texbake {

namespace {

namespace fs = std::filesystem;

// COLMAP's workspace layout: W/sparse/<k>/ (or W/sparse/) holds the model,
// W/images/ the photos. Empty when `model` is in no `sparse` folder.
fs::path workspace_images(const fs::path& model) {
  std::error_code ec;
  fs::path p = fs::weakly_canonical(model, ec);
  if (ec) p = model;
  for (fs::path dir = p; dir.has_relative_path(); dir = dir.parent_path()) {
    if (dir.filename() == "sparse") return dir.parent_path() / "images";
    if (dir == dir.parent_path()) break;
  }
  return {};
}

// The API's photo reader: mesh_io's read_image (with the colour space rule
// `cs`, --texture-colorspace), advancing `progress` by one
// per photo read after the first and cancelling when asked.
PhotoReader progress_reader(Progress& progress, std::size_t& done, TextureColorSpace cs) {
  return [&progress, &done, cs](const Photo& photo) -> Expected<PhotoImage> {
    if (done > 0) progress.advance(1);
    ++done;
    if (progress.cancelled()) return cancelled_error();
    Expected<Image> image = read_image(photo.path, {cs});
    if (!image) return image.error();
    return PhotoImage{image->width, image->height, std::move(image->pixels), image->color_space};
  };
}

}  // namespace

Expected<std::vector<Photo>> read_cameras(const fs::path& cameras, const fs::path& images,
                                          PhotoFolder need, std::vector<std::string>* notes) {
  std::error_code ec;
  std::vector<Photo> photos;
  fs::path folder = images;
  if (fs::is_directory(cameras, ec)) {
    Expected<std::vector<ColmapImage>> model = read_colmap_model(cameras);
    if (!model) return model.error();
    if (folder.empty()) {
      folder = workspace_images(cameras);
      if (folder.empty() && need == PhotoFolder::kNeeded) {
        return make_error(ErrorCode::kInvalidArgument,
                          "--cameras " + cameras.string() +
                              " is not inside a COLMAP workspace's sparse/ folder: give the "
                              "photos' folder with --images");
      }
    }
    for (ColmapImage& image : *model) {
      photos.push_back({image.name, std::move(image.camera), folder / image.name, {}});
    }
  } else {
    Expected<CameraFile> file = read_camera_file(cameras);
    if (!file) return file.error();
    if (notes) notes->insert(notes->end(), file->notes.begin(), file->notes.end());
    if (folder.empty()) folder = cameras.parent_path();
    for (CameraListEntry& entry : file->cameras) {
      const fs::path path = camera_photo_path(file->format, entry.image, folder);
      photos.push_back({entry.image, std::move(entry.camera), path, {}});
    }
  }
  // The photos themselves are read by the bakes, which leave out those
  // that cannot be read (PhotoBakeOptions::strict_photos).
  return photos;
}

fs::path mask_file(const fs::path& masks, const std::string& name) {
  std::error_code ec;
  // An absolute image name (a camera file may give one) is looked up under `masks` too.
  const fs::path relative = fs::path(name).relative_path();
  fs::path p = masks / (relative.string() + ".png");
  if (fs::is_regular_file(p, ec)) return p;
  if (relative.has_extension()) {
    p = masks / fs::path(relative).replace_extension(".png");
    if (fs::is_regular_file(p, ec)) return p;
  }
  return {};
}

Status find_masks(std::vector<Photo>& photos, const fs::path& masks, const std::string& label,
                  std::vector<std::string>* warnings) {
  const std::string where = label + " " + masks.string() + ": ";
  std::error_code ec;
  if (!fs::exists(masks, ec)) return make_error(ErrorCode::kIo, where + "no such folder");
  if (!fs::is_directory(masks, ec)) return make_error(ErrorCode::kIo, where + "not a folder");
  std::size_t missing = 0;
  const Photo* first_missing = nullptr;
  for (Photo& photo : photos) {
    photo.mask = mask_file(masks, photo.name);
    if (photo.mask.empty() && missing++ == 0) first_missing = &photo;
  }
  if (photos.empty() || missing == 0) return ok_status();
  const std::string looked = (masks / (first_missing->name + ".png")).string();
  if (missing == photos.size()) {
    return make_error(ErrorCode::kIo, where + "no mask for any of the " +
                                          std::to_string(photos.size()) +
                                          " photos (COLMAP's convention: a mask per photo named "
                                          "after its image name, e.g. " +
                                          looked + ")");
  }
  if (warnings) {
    warnings->push_back(
        where + "no mask for " + std::to_string(missing) + " of " + std::to_string(photos.size()) +
        " photos (the first: " + first_missing->name + ", looked for " + looked + "): used whole");
  }
  return ok_status();
}

Expected<std::vector<Photo>> read_camera_proxy(const fs::path& camera_file, const fs::path& photo) {
  Expected<Projector> projector = read_projector_file(camera_file);
  if (!projector) return projector.error();
  const CameraProjector* camera = as_camera(*projector);
  if (!camera) {
    return make_error(ErrorCode::kInvalidArgument,
                      camera_file.string() +
                          " holds an analytic proxy, not a camera (bake it with an image "
                          "through the proxy)");
  }
  return std::vector<Photo>{{photo.filename().string(), *camera, photo, {}}};
}

PhotoBakeOptions camera_proxy_options(PhotoBakeOptions options) {
  options.exposure = ExposureMode::kNone;
  options.max_view_angle_deg = 90;
  options.strict_photos = true;  // one photo: without it there is nothing to bake
  return options;
}

Expected<PhotoColors> detail::photo_vertex_colors(const MeshData& mesh,
                                                  const std::vector<Photo>& photos,
                                                  const PhotoBakeOptions& options,
                                                  const RunOptions& run) {
  const auto start = Clock::now();
  if (Status s = validate_options(options); !s) return s.error();
  if (photos.empty()) return make_error(ErrorCode::kInvalidArgument, "no photos to bake from");
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<PhotoColors>(run, [&]() -> Expected<PhotoColors> {
    progress.start("photos", photos.size());
    std::size_t done = 0;
    const PhotoReader reader = progress_reader(progress, done, options.color_space);
    Expected<PhotoBakeResult> baked = bake_vertex_from_photos(mesh, photos, options, reader);
    if (progress.cancelled()) return cancelled_error();
    if (!baked) return detail::as_input(baked.error());
    progress.finish();
    if (progress.cancelled()) return cancelled_error();
    PhotoColors out;
    out.colors = std::move(baked->colors);
    out.cameras = std::move(baked->cameras);
    out.consistency = baked->consistency;
    Counts& c = out.stats.counts;
    c.vertices = mesh.positions.size();
    c.triangles = mesh.triangles.size();
    for (const PhotoCameraStats& cam : out.cameras) c.samples += cam.visible;
    c.occluded = c.vertices - baked->seen;
    c.filled = baked->filled;
    c.unfilled = baked->unfilled;
    out.stats.warnings = std::move(baked->warnings);
    out.skipped = std::move(baked->skipped);
    Timings& t = out.stats.timings;
    t.scene_build = baked->seconds_scene;
    t.bake = baked->seconds_photos;
    t.fill = baked->seconds_blend + baked->seconds_fill;
    t.total = seconds_since(start);
    return out;
  });
}

Expected<PhotoAtlas> detail::photo_atlas_texture(const MeshData& mesh,
                                                 const std::vector<Photo>& photos,
                                                 const PhotoBakeOptions& options,
                                                 const AtlasOptions& atlas, const RunOptions& run) {
  const auto start = Clock::now();
  if (Status s = validate_options(atlas); !s) return s.error();
  if (Status s = validate_options(options); !s) return s.error();
  if (atlas.uv == UvLayout::kProxy) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--uv proxy needs a proxy, and a bake from photos has none (use --uv "
                      "generate or --uv mesh)");
  }
  if (photos.empty()) return make_error(ErrorCode::kInvalidArgument, "no photos to bake from");
  if (Status s = check_uv_layout(mesh, atlas.uv); !s) return s.error();
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<PhotoAtlas>(run, [&]() -> Expected<PhotoAtlas> {
    PhotoAtlas out;
    if (Status s = detail::lay_out_atlas(mesh, nullptr, atlas, progress, out.atlas); !s) {
      return s.error();
    }
    progress.start("photos", 2 * photos.size());
    std::size_t done = 0;
    PhotoAtlasBakeOptions o;
    o.size = atlas.bake.size;
    o.samples = atlas.bake.samples;
    o.padding = atlas.bake.padding;
    o.photo = options;
    Expected<PhotoAtlasBakeResult> baked = bake_atlas_from_photos(
        out.atlas.mesh, photos, o, progress_reader(progress, done, options.color_space));
    if (progress.cancelled()) return cancelled_error();
    if (!baked) return detail::as_input(baked.error());
    progress.finish();
    if (progress.cancelled()) return cancelled_error();
    out.atlas.image = std::move(baked->atlas);
    out.cameras = std::move(baked->cameras);
    out.skipped = std::move(baked->skipped);
    out.consistency = baked->consistency;
    Stats& st = out.atlas.stats;
    for (std::string& w : baked->warnings) st.warnings.push_back(std::move(w));
    Counts& c = st.counts;
    c = detail::mesh_counts(mesh);
    c.texels = baked->texels;
    c.samples = baked->samples;
    c.occluded = baked->samples - baked->seen;
    c.filled = baked->filled;
    c.unfilled = baked->vertices_unfilled;
    c.border_samples = baked->border_samples;
    c.padded = baked->padded;
    Timings& t = st.timings;
    t.rasterize = baked->seconds_rasterize;
    t.scene_build = baked->seconds_scene;
    t.bake = baked->seconds_geometry + baked->seconds_photos;
    t.fill = baked->seconds_vertex + baked->seconds_fill;
    t.pad = baked->seconds_texels;
    t.total = seconds_since(start);
    return out;
  });
}

Expected<std::vector<CameraCheck>> check_cameras(const MeshData& mesh,
                                                 const std::vector<Photo>& photos,
                                                 const RunOptions& run) {
  if (Status s = check_triangles(mesh); !s) return s.error();
  return detail::run_call<std::vector<CameraCheck>>(
      run, [&]() -> Expected<std::vector<CameraCheck>> {
        Expected<std::vector<CameraCheck>> checks = check_camera_poses(mesh, photos);
        if (!checks) return detail::as_input(checks.error());
        return checks;
      });
}

Expected<ModelAlignment> check_model_alignment(const MeshData& mesh, const fs::path& cameras,
                                               const RunOptions& run) {
  std::error_code ec;
  if (!fs::is_directory(cameras, ec)) return ModelAlignment{};  // a JSON list has no points
  Expected<std::vector<Vec3>> points = read_colmap_points(cameras);
  if (!points) return points.error();
  Expected<ModelAlignment> a = measure_model_alignment(mesh, *points, run.threads);
  if (!a) return detail::as_input(a.error());
  return a;
}

Expected<CameraModelCheck> check_camera_model(const MeshData& mesh,
                                              const std::vector<Photo>& photos,
                                              const fs::path& model, bool measure_agreement,
                                              const RunOptions& run) {
  CameraModelCheck out;
  Expected<std::vector<CameraCheck>> checks = check_cameras(mesh, photos, run);
  if (!checks) return checks.error();
  out.cameras = std::move(*checks);
  Expected<ModelAlignment> alignment = check_model_alignment(mesh, model, run);
  if (!alignment) return alignment.error();
  out.alignment = *alignment;
  if (!measure_agreement || photos.size() < 2) return out;
  // The photo bake's own figures (the photos read one at a time; the fill
  // left out); its consistency warning is given here, naming the model.
  PhotoBakeOptions o;
  o.occluded = OccludedMode::kColor;
  o.consistency_warning = false;
  Expected<PhotoColors> baked = bake_vertex_colors_from_photos(mesh, photos, o, run);
  if (!baked) {
    const ErrorCode code = baked.error().code;
    if (code == ErrorCode::kInternal || code == ErrorCode::kCancelled) return baked.error();
    out.agreement_not_measured = baked.error().message;  // the geometric figures stand
    return out;
  }
  out.agreement_measured = true;
  out.agreement = std::move(baked->cameras);
  out.consistency = baked->consistency;
  out.warnings = std::move(baked->stats.warnings);
  if (!photo_consistency_warning(out.consistency).empty()) {
    out.warnings.push_back(model.string() + ": the photos disagree on the mesh (" +
                           consistency_figures(out.consistency) +
                           "): are the cameras in the mesh's frame and their poses right? "
                           "(texbake cameras align, texbake cameras refine)");
  }
  return out;
}

}  // namespace texbake
