// The proxy bakes (bake_vertex, bake_atlas) and texbake.Atlas. Their
// options' defaults are the job option table's (texbake/__init__.py).
#include "bake/python/common.h"

namespace texbake::python {

namespace {

py::dict uv_layout_dict(const Atlas& a) {
  py::dict d;
  d["used"] = to_string(a.uv.used);
  d["corners_outside"] = a.uv.corners_outside;
  d["overlap_texels"] = a.uv.overlap_texels;
  d["cut_triangles"] = a.uv.cut_triangles;
  d["charts"] = a.uv.charts;
  d["utilisation"] = a.uv.utilisation;
  d["stretch_l2"] = a.uv.stretch_l2;
  return d;
}

void bind_atlas_class(py::module_& m) {
  py::class_<Atlas>(m, "Atlas", py::dynamic_attr(),
                    "An atlas bake (texbake.bake_atlas and the other atlas bakes): image (N, N, "
                    "4) float32, mesh (with the per-corner UVs baked against), uvs, face_uvs, "
                    "stats, uv_layout, repeat_u, blend. Unpacks as image, uvs, face_uvs, stats; "
                    "texbake.write_atlas writes it.")
      .def_property_readonly("image",
                             [](const Atlas& a) {
                               // A copy: the Atlas keeps its image for write_atlas.
                               Image copy = a.image;
                               return image_array(std::move(copy));
                             })
      .def_property_readonly("mesh",
                             [](const Atlas& a) {
                               return LoadedMesh{a.mesh, {}};
                             })
      .def_readonly("repeat_u", &Atlas::repeat_u)
      .def_readonly("blend", &Atlas::blend)
      .def_property_readonly("uv_layout", &uv_layout_dict)
      .def_property_readonly("stats", [](const py::object& self) {
        // A bake's: the report's counts (and photos_skipped), atlas_result's.
        py::dict d = stats_dict(self.cast<const Atlas&>().stats);
        const py::object report = py::getattr(self, "_report", py::none());
        if (!report.is_none()) {
          for (const auto& [key, value] : report.cast<py::dict>()) d[key] = value;
        }
        return d;
      });
}

py::tuple bake_vertex(const LoadedMesh& mesh, py::handle image, py::handle proxy, py::handle filter,
                      py::handle samples, py::handle visibility, py::handle occluded,
                      py::handle outside, bool linear, py::handle wrap, py::handle cache_mb,
                      py::handle threads, py::object progress) {
  const PyProxy& p = proxy_arg(proxy);
  const VertexBakeOptions o =
      shading_options(filter, samples, visibility, occluded, outside, linear, wrap);
  check(validate_options(o));
  const std::size_t budget = cache_mb_arg(cache_mb);
  PyRun run(threads, std::move(progress));
  ImageArg img = bake_image_arg(image, budget, o);
  VertexColors baked = run_released<VertexColors>(run, [&](const RunOptions& r) {
    return bake_vertex_colors(mesh.mesh, img.view, p.proxy, o, r);
  });
  return py::make_tuple(colors_array(baked.colors),
                        bake_stats(baked.stats, ReportSource::kProxy, /*atlas=*/false));
}

// The atlas's --filter: bilinear or ewa (each supersample filtered by its footprint).
void check_atlas_filter(const VertexBakeOptions& shading) {
  if (shading.filter == VertexFilter::kArea) {
    usage("--filter area applies to --target vertex only (the atlas takes bilinear or ewa)");
  }
}

py::object bake_atlas(const LoadedMesh& mesh, py::handle image, py::handle proxy, py::handle uv,
                      py::handle size, py::handle samples, py::handle padding, py::handle filter,
                      py::handle visibility, py::handle occluded, py::handle outside, bool linear,
                      py::handle wrap, py::handle cache_mb, py::handle threads,
                      py::object progress) {
  const PyProxy& p = proxy_arg(proxy);
  const VertexBakeOptions shading =
      shading_options(filter, py::int_(1), visibility, occluded, outside, linear, wrap);
  check_atlas_filter(shading);
  const AtlasOptions o = atlas_options(uv, size, samples, padding, shading);
  const std::size_t budget = cache_mb_arg(cache_mb);
  PyRun run(threads, std::move(progress));
  ImageArg img = bake_image_arg(image, budget, o.bake.shading);
  Atlas baked = run_released<Atlas>(run, [&](const RunOptions& r) {
    return bake_atlas_texture(mesh.mesh, img.view, p.proxy, o, r);
  });
  return atlas_result(std::move(baked), ReportSource::kProxy, o.bake);
}

}  // namespace

void bind_bake(py::module_& m) {
  bind_atlas_class(m);
  m.def("bake_vertex", &bake_vertex);
  m.def("bake_atlas", &bake_atlas);
}

}  // namespace texbake::python
