// render and compare (texbake render, texbake compare), with the CLI's
// checks (validate_options of RenderOptions and CompareOptions).
#include "bake/python/common.h"

namespace texbake::python {

namespace {

// Two numbers (w, h) or (azimuth, elevation); ValueError naming `flag`.
std::vector<py::handle> pair_arg(const py::handle& obj, const char* flag, const char* what) {
  if (py::isinstance<py::str>(obj) || !py::isinstance<py::sequence>(obj) || py::len(obj) != 2) {
    usage(std::string(flag) + ": expected " + what + ", got " + std::string(py::repr(obj)));
  }
  const py::sequence s = py::reinterpret_borrow<py::sequence>(obj);
  return {s[0], s[1]};
}

double number_arg(const py::handle& obj, const char* flag) {
  try {
    if (!py::isinstance<py::str>(obj)) return obj.cast<double>();
  } catch (const py::cast_error&) {
  }
  usage(std::string(flag) + ": '" + std::string(py::str(obj)) + "' is not a number");
}

RenderOptions render_options(py::handle size, py::handle view, py::handle views, bool shadows,
                             py::handle samples, py::handle up, bool flat, py::handle background) {
  RenderOptions o;
  const std::vector<py::handle> wh = pair_arg(size, "--size", "(width, height)");
  o.width = static_cast<int>(int_arg(wh[0], "--size"));
  o.height = static_cast<int>(int_arg(wh[1], "--size"));
  const std::vector<py::handle> ae = pair_arg(view, "--view", "(azimuth, elevation)");
  o.azimuth_deg = number_arg(ae[0], "--view");
  o.elevation_deg = number_arg(ae[1], "--view");
  o.views = static_cast<int>(int_arg(views, "--views"));
  o.shadows = shadows;
  o.samples_per_pixel = static_cast<int>(int_arg(samples, "--samples"));
  o.up = vec3_arg(up, "up");
  o.smooth_normals = !flat;
  if (!background.is_none()) {
    const Rgba b = color_arg(background, "--background", /*alpha=*/false);
    for (int c = 0; c < 3; ++c) o.background[c] = b[c];
  }
  check(validate_options(o));
  return o;
}

// The colour source: texture + proxy (the direct projection), else the
// atlas image or the vertex colours (`colors`), else grey. `img` keeps the
// image the source views.
ColorSource color_source(const LoadedMesh& mesh, py::handle colors, py::handle texture,
                         py::handle proxy, py::handle atlas_image, py::handle outside,
                         py::handle wrap, bool linear, ImageArg& img) {
  const std::string choice = py::isinstance<py::str>(colors) ? std::string(py::str(colors)) : "";
  if (!texture.is_none()) {
    if (proxy.is_none()) usage("--texture needs --proxy KIND or --proxy-file F");
    ProjectionSource p{
        proxy_arg(proxy).proxy, {}, std::nullopt, choice_arg<WrapMode>(wrap, "--wrap"), linear};
    Rgba color;
    if (keyword_or_color(outside, "--outside", {"clamp"}, color).empty()) p.outside = color;
    img = image_arg(texture, "texture");
    p.texture = img.view;
    return p;
  }
  if (!proxy.is_none()) usage("--proxy/--proxy-file needs --texture IMG");
  if (choice == "atlas" || (choice == "auto" && !atlas_image.is_none())) {
    if (atlas_image.is_none()) usage("colors='atlas' needs atlas_image");
    img = image_arg(atlas_image, "atlas_image");
    return AtlasSource{img.view};
  }
  if (choice == "vertex" || (choice == "auto" && mesh.mesh.has_vertex_colors())) {
    return VertexColorSource{};
  }
  if (choice != "auto" && choice != "none") {
    usage("--colors: unknown value '" + std::string(py::str(colors)) +
          "' (expected auto, vertex, atlas or none)");
  }
  return GreySource{};
}

// The defaults of render's and compare's options (commands of their own,
// outside the bake job's option table): their option structs'.
py::dict render_defaults() {
  const RenderOptions r;
  const CompareOptions c;
  const auto rgb = [](const Rgba& v) { return py::make_tuple(v[0], v[1], v[2]); };
  py::dict render, compare;
  render["size"] = py::make_tuple(r.width, r.height);
  render["view"] = py::make_tuple(r.azimuth_deg, r.elevation_deg);
  render["views"] = r.views;
  render["samples"] = kRenderSamples;
  render["shadows"] = r.shadows;
  render["flat"] = !r.smooth_normals;
  render["background"] = rgb(r.background);
  compare["background"] = rgb(c.background);
  py::dict out;
  out["render"] = render;
  out["compare"] = compare;
  return out;
}

py::tuple render(const LoadedMesh& mesh, py::handle colors, py::handle texture, py::handle proxy,
                 py::handle atlas_image, py::handle outside, py::handle wrap, bool linear,
                 py::handle size, py::handle view, py::handle views, bool shadows,
                 py::handle samples, py::handle up, bool flat, py::handle background,
                 py::handle threads, py::object progress) {
  const RenderOptions o = render_options(size, view, views, shadows, samples, up, flat, background);
  ImageArg img;
  const ColorSource source =
      color_source(mesh, colors, texture, proxy, atlas_image, outside, wrap, linear, img);
  PyRun run(threads, std::move(progress));
  Rendered r = run_released<Rendered>(
      run, [&](const RunOptions& ro) { return render_mesh(mesh.mesh, source, o, ro); });
  const int h = r.image.height, w = r.image.width;
  return py::make_tuple(owned(std::move(r.image.pixels), {h, w, 4}), stats_dict(r.stats));
}

py::dict compare(py::handle a, py::handle b, bool mask_background, py::handle background) {
  CompareOptions o;
  o.mask_background = mask_background;
  if (!background.is_none()) {
    const Rgba c = color_arg(background, "--background", /*alpha=*/false);
    for (int k = 0; k < 3; ++k) o.background[k] = c[k];
  }
  check(validate_options(o));
  CompareResult r;
  if (is_path(a) || is_path(b)) {
    const std::filesystem::path pa = path_arg(a, "a"), pb = path_arg(b, "b");
    py::gil_scoped_release release;
    r = check(compare_image_files(pa, pb, o));
  } else {
    ImageArg ia = image_arg(a, "a"), ib = image_arg(b, "b");
    r = check(compare_images(ia.view, ib.view, o));
  }
  py::dict d;
  d["width"] = r.width;
  d["height"] = r.height;
  d["channels"] = r.channels;
  d["compared_pixels"] = r.compared_pixels;
  d["rms"] = r.rms;
  d["psnr"] = r.psnr;
  d["max_difference"] = r.max_difference;
  d["max_x"] = r.max_x;
  d["max_y"] = r.max_y;
  d["max_channel"] = r.max_channel;
  return d;
}

}  // namespace

void bind_render(py::module_& m) {
  m.def("render_defaults", &render_defaults);
  m.def("render", &render);
  m.def("compare", &compare);
}

}  // namespace texbake::python
