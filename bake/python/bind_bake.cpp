// The proxy bakes (bake_vertex, bake_atlas), texbake.Atlas, and the
// defaults of every call's options, read from the library's option structs.
#include "bake/python/common.h"

namespace texbake::python {

namespace {

// An occluded/outside rule as the CLI spells it: a keyword or (r, g, b, a).
py::object rule_name(bool is_color, const char* keyword, const Rgba& color) {
  if (is_color) return py::make_tuple(color[0], color[1], color[2], color[3]);
  return py::str(keyword);
}

py::tuple rgb(const Rgba& c) {
  return py::make_tuple(c[0], c[1], c[2]);
}

const char* occluded_keyword(OccludedMode mode) {
  return mode == OccludedMode::kProject ? "project" : "fill";
}

// Every option's default, by call group: what texbake/__init__.py puts in
// its signatures. Read from default-constructed option structs, so the
// defaults are written once, in the library.
py::dict defaults() {
  const VertexBakeOptions v;
  const AtlasOptions a;
  const PhotoBakeOptions p;
  const LayersBakeOptions l;
  const RenderOptions r;
  const CompareOptions c;
  py::dict vertex, atlas, photos, layers, render, compare;
  vertex["filter"] = choice_name(v.filter);
  vertex["samples"] = v.samples;
  vertex["visibility"] = choice_name(v.visibility);
  vertex["occluded"] =
      rule_name(v.occluded == OccludedMode::kColor, occluded_keyword(v.occluded), v.occluded_color);
  vertex["outside"] = rule_name(v.outside == OutsideMode::kColor, "clamp", v.outside_color);
  vertex["linear"] = v.linear;
  vertex["wrap"] = choice_name(v.plane_wrap);
  vertex["cache_mb"] = kDefaultCacheMb;
  atlas["uv"] = choice_name(a.uv);
  atlas["size"] = a.bake.size;
  atlas["samples"] = a.bake.samples;
  atlas["padding"] = py::none();  // kPaddingDefault
  photos["blend"] = choice_name(p.blend);
  photos["exposure"] = choice_name(p.exposure);
  photos["occluded"] =
      rule_name(p.occluded == OccludedMode::kColor, occluded_keyword(p.occluded), p.occluded_color);
  photos["colorspace"] = choice_name(p.color_space);
  layers["occluded"] =
      rule_name(l.occluded == OccludedMode::kColor, occluded_keyword(l.occluded), l.occluded_color);
  layers["cache_mb"] = l.cache_mb;
  render["size"] = py::make_tuple(r.width, r.height);
  render["view"] = py::make_tuple(r.azimuth_deg, r.elevation_deg);
  render["views"] = r.views;
  render["samples"] = kRenderSamples;
  render["shadows"] = r.shadows;
  render["flat"] = !r.smooth_normals;
  render["background"] = rgb(r.background);
  compare["background"] = rgb(c.background);
  py::dict out;
  out["vertex"] = vertex;
  out["atlas"] = atlas;
  out["photos"] = photos;
  out["layers"] = layers;
  out["render"] = render;
  out["compare"] = compare;
  return out;
}

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
  py::class_<Atlas>(m, "Atlas",
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
      .def_property_readonly("stats", [](const Atlas& a) { return stats_dict(a.stats); });
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
  return py::make_tuple(colors_array(baked.colors), stats_dict(baked.stats));
}

Atlas bake_atlas(const LoadedMesh& mesh, py::handle image, py::handle proxy, py::handle uv,
                 py::handle size, py::handle samples, py::handle padding, py::handle visibility,
                 py::handle occluded, py::handle outside, bool linear, py::handle wrap,
                 py::handle cache_mb, py::handle threads, py::object progress) {
  const PyProxy& p = proxy_arg(proxy);
  VertexBakeOptions shading = shading_options(py::str("bilinear"), py::int_(1), visibility,
                                              occluded, outside, linear, wrap);
  const AtlasOptions o = atlas_options(uv, size, samples, padding, shading);
  const std::size_t budget = cache_mb_arg(cache_mb);
  PyRun run(threads, std::move(progress));
  ImageArg img = bake_image_arg(image, budget, o.bake.shading);
  return run_released<Atlas>(run, [&](const RunOptions& r) {
    return bake_atlas_texture(mesh.mesh, img.view, p.proxy, o, r);
  });
}

}  // namespace

void bind_bake(py::module_& m) {
  m.def("defaults", &defaults);
  bind_atlas_class(m);
  m.def("bake_vertex", &bake_vertex);
  m.def("bake_atlas", &bake_atlas);
}

}  // namespace texbake::python
