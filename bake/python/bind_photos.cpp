// The bakes from photographs (a camera model or list, or one camera proxy
// file with its photo), from a layers file, and cameras check: the jobs of
// `texbake bake --cameras`, `bake --texture PHOTO --proxy-file CAMERA`,
// `bake --layers` and `texbake cameras check`, each for either target.
#include "bake/python/common.h"

namespace texbake::python {

namespace {

// --occluded of the photo and layers bakes: "fill" or a colour.
void occluded_arg(const py::handle& occluded, OccludedMode& mode, Rgba& color) {
  const std::string keyword = keyword_or_color(occluded, "--occluded", {"fill"}, color);
  mode = keyword.empty() ? OccludedMode::kColor : OccludedMode::kFill;
}

PhotoBakeOptions photo_options(const py::handle& blend, const py::handle& exposure,
                               const py::handle& occluded, const py::handle& colorspace,
                               bool strict_photos = false) {
  PhotoBakeOptions o;
  o.strict_photos = strict_photos;
  o.blend = choice_arg<PhotoBlend>(blend, "--blend");
  o.exposure = choice_arg<ExposureMode>(exposure, "--exposure");
  occluded_arg(occluded, o.occluded, o.occluded_color);
  o.color_space = choice_arg<TextureColorSpace>(colorspace, "--texture-colorspace");
  check(validate_options(o));
  return o;
}

// The photos of a camera model or list (read_cameras) with their masks
// (find_masks, when `masks` is not None; its warnings in `warnings`), or of
// one camera proxy file and its photo (read_camera_proxy; `options` then get
// camera_proxy_options).
struct ReadPhotos {
  std::vector<Photo> photos;
  std::vector<std::string> warnings;
};
ReadPhotos read_photos(const py::handle& cameras, const py::handle& images,
                       const py::handle& masks) {
  const std::filesystem::path c = path_arg(cameras, "cameras");
  const std::filesystem::path i =
      images.is_none() ? std::filesystem::path{} : path_arg(images, "images");
  const std::filesystem::path m =
      masks.is_none() ? std::filesystem::path{} : path_arg(masks, "masks");
  py::gil_scoped_release release;
  ReadPhotos out{check(read_cameras(c, i)), {}};
  if (!m.empty()) check(find_masks(out.photos, m, "masks", &out.warnings));
  return out;
}
ReadPhotos read_camera(const py::handle& camera, const py::handle& photo) {
  const std::filesystem::path c = path_arg(camera, "camera"), p = path_arg(photo, "photo");
  py::gil_scoped_release release;
  return {check(read_camera_proxy(c, p)), {}};
}

// PhotoConsistency, as the report's "photo_agreement".
py::dict consistency_dict(const PhotoConsistency& c) {
  py::dict d;
  d["vertices"] = c.vertices;
  d["agreeing"] = c.agreeing;
  d["median_deviation"] = c.median_deviation;
  d["gain_ratio"] = c.gain_ratio;
  return d;
}

py::tuple vertex_from_photos(const LoadedMesh& mesh, const ReadPhotos& photos,
                             const PhotoBakeOptions& o, py::handle threads, py::object progress) {
  PyRun run(threads, std::move(progress));
  PhotoColors baked = run_released<PhotoColors>(run, [&](const RunOptions& r) {
    return bake_vertex_colors_from_photos(mesh.mesh, photos.photos, o, r);
  });
  std::vector<std::string>& warnings = baked.stats.warnings;
  warnings.insert(warnings.begin(), photos.warnings.begin(), photos.warnings.end());
  py::dict stats = bake_stats(baked.stats, ReportSource::kPhotos, /*atlas=*/false);
  stats["photos_skipped"] = skipped_list(baked.skipped);
  stats["photo_agreement"] = consistency_dict(baked.consistency);
  return py::make_tuple(colors_array(baked.colors), stats, cameras_list(baked.cameras));
}

py::tuple atlas_from_photos(const LoadedMesh& mesh, const ReadPhotos& photos,
                            const PhotoBakeOptions& o, const AtlasOptions& a, py::handle threads,
                            py::object progress) {
  PyRun run(threads, std::move(progress));
  PhotoAtlas baked = run_released<PhotoAtlas>(run, [&](const RunOptions& r) {
    return bake_atlas_texture_from_photos(mesh.mesh, photos.photos, o, a, r);
  });
  std::vector<std::string>& warnings = baked.atlas.stats.warnings;
  warnings.insert(warnings.begin(), photos.warnings.begin(), photos.warnings.end());
  py::list cameras = cameras_list(baked.cameras);
  const PhotoConsistency consistency = baked.consistency;
  py::object atlas =
      atlas_result(std::move(baked.atlas), ReportSource::kPhotos, a.bake, &baked.skipped);
  atlas.attr("_report")["photo_agreement"] = consistency_dict(consistency);
  return py::make_tuple(atlas, cameras);
}

// The atlas options of a bake without a proxy (the shading is not used).
AtlasOptions photo_atlas_options(py::handle uv, py::handle size, py::handle samples,
                                 py::handle padding) {
  return atlas_options(uv, size, samples, padding, VertexBakeOptions{});
}

void bind_photo_bakes(py::module_& m) {
  m.def("bake_vertex_from_photos", [](const LoadedMesh& mesh, py::handle cameras, py::handle images,
                                      py::handle masks, py::handle blend, py::handle exposure,
                                      py::handle occluded, py::handle colorspace,
                                      bool strict_photos, py::handle threads, py::object progress) {
    const PhotoBakeOptions o = photo_options(blend, exposure, occluded, colorspace, strict_photos);
    return vertex_from_photos(mesh, read_photos(cameras, images, masks), o, threads,
                              std::move(progress));
  });
  m.def("bake_atlas_from_photos", [](const LoadedMesh& mesh, py::handle cameras, py::handle images,
                                     py::handle masks, py::handle blend, py::handle exposure,
                                     py::handle occluded, py::handle colorspace, bool strict_photos,
                                     py::handle uv, py::handle size, py::handle samples,
                                     py::handle padding, py::handle threads, py::object progress) {
    const PhotoBakeOptions o = photo_options(blend, exposure, occluded, colorspace, strict_photos);
    const AtlasOptions a = photo_atlas_options(uv, size, samples, padding);
    return atlas_from_photos(mesh, read_photos(cameras, images, masks), o, a, threads,
                             std::move(progress));
  });
  m.def("bake_vertex_from_camera", [](const LoadedMesh& mesh, py::handle camera, py::handle photo,
                                      py::handle occluded, py::handle colorspace,
                                      py::handle threads, py::object progress) {
    const PhotoBakeOptions o =
        camera_proxy_options(photo_options(py::str("soft"), py::str("none"), occluded, colorspace));
    return vertex_from_photos(mesh, read_camera(camera, photo), o, threads, std::move(progress));
  });
  m.def("bake_atlas_from_camera", [](const LoadedMesh& mesh, py::handle camera, py::handle photo,
                                     py::handle occluded, py::handle colorspace, py::handle uv,
                                     py::handle size, py::handle samples, py::handle padding,
                                     py::handle threads, py::object progress) {
    const PhotoBakeOptions o =
        camera_proxy_options(photo_options(py::str("soft"), py::str("none"), occluded, colorspace));
    const AtlasOptions a = photo_atlas_options(uv, size, samples, padding);
    return atlas_from_photos(mesh, read_camera(camera, photo), o, a, threads, std::move(progress));
  });
}

// The layers file and the options of its bakes (--occluded, --cache-mb).
std::pair<LayersSpec, LayersBakeOptions> layers_args(py::handle layers, py::handle occluded,
                                                     py::handle cache_mb) {
  LayersBakeOptions o;
  occluded_arg(occluded, o.occluded, o.occluded_color);
  o.cache_mb = cache_mb_arg(cache_mb);
  const std::filesystem::path path = path_arg(layers, "layers");
  py::gil_scoped_release release;
  return {check(read_layers(path)), o};
}

void bind_layer_bakes(py::module_& m) {
  m.def("bake_vertex_from_layers",
        [](const LoadedMesh& mesh, py::handle layers, py::handle occluded, py::handle cache_mb,
           py::handle threads, py::object progress) {
          const auto [spec, o] = layers_args(layers, occluded, cache_mb);
          PyRun run(threads, std::move(progress));
          LayerColors baked = run_released<LayerColors>(run, [&](const RunOptions& r) {
            return bake_vertex_colors_from_layers(mesh.mesh, spec, o, r);
          });
          return py::make_tuple(
              colors_array(baked.colors),
              bake_stats(baked.stats, ReportSource::kLayers, /*atlas=*/false, baked.layers),
              layers_list(baked.layers));
        });
  m.def("bake_atlas_from_layers", [](const LoadedMesh& mesh, py::handle layers, py::handle occluded,
                                     py::handle uv, py::handle size, py::handle samples,
                                     py::handle padding, py::handle cache_mb, py::handle threads,
                                     py::object progress) {
    // size None: the base texture's size (base "mesh"), else the default (as the CLI
    // without --size); the other values are checked as given.
    const py::object checked_size = size.is_none() ? py::object(py::int_(AtlasOptions{}.bake.size))
                                                   : py::reinterpret_borrow<py::object>(size);
    AtlasOptions a = photo_atlas_options(uv, checked_size, samples, padding);
    if (size.is_none()) a.bake.size = 0;
    const auto [spec, o] = layers_args(layers, occluded, cache_mb);
    PyRun run(threads, std::move(progress));
    LayerAtlas baked = run_released<LayerAtlas>(run, [&](const RunOptions& r) {
      return bake_atlas_texture_from_layers(mesh.mesh, spec, o, a, r);
    });
    py::list per_layer = layers_list(baked.layers);
    return py::make_tuple(
        atlas_result(std::move(baked.atlas), ReportSource::kLayers, a.bake, nullptr, baked.layers),
        per_layer);
  });
}

py::list camera_checks(const LoadedMesh& mesh, py::handle cameras, py::handle images,
                       py::handle masks, py::handle threads) {
  const ReadPhotos photos = read_photos(cameras, images, masks);
  PyRun run(threads, py::none());
  const std::vector<CameraCheck> checks = run_released<std::vector<CameraCheck>>(
      run, [&](const RunOptions& r) { return check_cameras(mesh.mesh, photos.photos, r); });
  py::list out;
  for (const CameraCheck& c : checks) {
    py::dict d;
    d["image"] = c.name;
    d["in_front"] = c.in_front;
    d["inside"] = c.inside;
    d["masked"] = c.masked;
    d["has_mask"] = c.has_mask;
    d["visible"] = c.visible;
    d["warnings"] = c.warnings;
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_photos(py::module_& m) {
  bind_photo_bakes(m);
  bind_layer_bakes(m);
  m.def("check_cameras", &camera_checks);
}

}  // namespace texbake::python
