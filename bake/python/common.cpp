// The shared pieces of the Python module's C++ half (bake/python/common.h).
#include "bake/python/common.h"

#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdio>

namespace texbake::python {

// ---- Errors ---------------------------------------------------------------

namespace {

PyObject* g_cancelled = nullptr;  // texbake.Cancelled

void translate(const ApiError& e) {
  PyObject* type = PyExc_RuntimeError;
  switch (category(e.error)) {
    case ErrorCategory::kUsage:
      type = PyExc_ValueError;
      break;
    case ErrorCategory::kInput:
      type = PyExc_OSError;
      break;
    case ErrorCategory::kInternal:
      type = PyExc_RuntimeError;
      break;
    case ErrorCategory::kCancelled:
      type = g_cancelled;
      break;
  }
  PyErr_SetString(type, e.error.message.c_str());
}

}  // namespace

void register_errors(py::module_& m) {
  static py::exception<ApiError> cancelled(m, "Cancelled", PyExc_Exception);
  g_cancelled = cancelled.ptr();
  cancelled.attr("__doc__") = "Raised when a progress callback returned False.";
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const ApiError& e) {
      translate(e);
    }
  });
}

void raise(const Error& error) {
  throw ApiError{error};
}

void usage(const std::string& message) {
  raise(make_error(ErrorCode::kInvalidArgument, message));
}

// ---- Running --------------------------------------------------------------

PyRun::PyRun(const py::handle& threads, py::object progress) : callback(std::move(progress)) {
  const long long n = int_arg(threads, "--threads");
  check(check_range("--threads", n, 0, kMaxThreads));
  run.threads = static_cast<int>(n);
  if (callback.is_none()) return;
  run.progress = [this](std::string_view stage, double fraction) {
    py::gil_scoped_acquire gil;
    if (raised) return false;
    try {
      py::object r = callback(std::string(stage), fraction);
      return r.is_none() || r.cast<bool>();
    } catch (py::error_already_set& e) {
      raised.emplace(std::move(e));
      return false;
    }
  };
}

void PyRun::rethrow() {
  if (raised) {
    py::error_already_set e = std::move(*raised);
    raised.reset();
    throw e;
  }
}

// ---- Arrays ---------------------------------------------------------------

template <class T>
Array<T> rows(const py::handle& a, const char* name, py::ssize_t cols) {
  Array<T> arr;
  try {
    arr = Array<T>::ensure(a);
  } catch (py::error_already_set&) {
  }
  if (!arr) usage(std::string(name) + " must be a numeric array");
  if (arr.ndim() != 2 || (cols > 0 && arr.shape(1) != cols)) {
    std::string shape = "(";
    for (py::ssize_t i = 0; i < arr.ndim(); ++i)
      shape += (i ? ", " : "") + std::to_string(arr.shape(i));
    usage(std::string(name) + " must have shape (n, " + (cols > 0 ? std::to_string(cols) : "k") +
          "), got " + shape + (arr.ndim() == 1 ? ",)" : ")"));
  }
  return arr;
}
template Array<double> rows<double>(const py::handle&, const char*, py::ssize_t);
template Array<float> rows<float>(const py::handle&, const char*, py::ssize_t);
template Array<int64_t> rows<int64_t>(const py::handle&, const char*, py::ssize_t);

void check_float_rows(const Array<double>& a, const char* name) {
  const double* p = a.data();
  const py::ssize_t cols = a.ndim() == 2 ? a.shape(1) : 1;
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if (std::isfinite(p[i]) && std::fabs(p[i]) <= FLT_MAX) continue;
    char value[32];
    std::snprintf(value, sizeof value, "%g", p[i]);
    usage(std::string(name) + ": row " + std::to_string(i / cols) +
          (std::isfinite(p[i]) ? " is beyond float range (" : " is not finite (") + value + ")");
  }
}

py::array_t<int64_t> index_array(const std::vector<uint32_t>& v, py::ssize_t cols) {
  const auto n = static_cast<py::ssize_t>(v.size());
  std::vector<py::ssize_t> shape =
      cols > 0 ? std::vector<py::ssize_t>{n / cols, cols} : std::vector<py::ssize_t>{n};
  return owned(std::vector<int64_t>(v.begin(), v.end()), std::move(shape));
}

py::array_t<float> colors_array(const std::vector<Rgba>& colors) {
  std::vector<float> flat;
  flat.reserve(colors.size() * 4);
  for (const Rgba& c : colors) flat.insert(flat.end(), c.begin(), c.end());
  return owned(std::move(flat), {static_cast<py::ssize_t>(colors.size()), 4});
}

py::array_t<float> image_array(Image&& image) {
  const int h = image.height, w = image.width;
  return owned(std::move(image.pixels), {h, w, 4});
}

// ---- Images in ------------------------------------------------------------

namespace {

// The CLI's warning for NaN or infinite texels (bake/cli/file_checks.h
// warn_nonfinite), as a RuntimeWarning.
void warn_nonfinite(std::size_t count, const std::string& name) {
  if (count == 0) return;
  const std::string message =
      name + ": " + std::to_string(count) + " NaN or infinite values read as 0";
  if (PyErr_WarnEx(PyExc_RuntimeWarning, message.c_str(), 2) != 0) throw py::error_already_set();
}

std::size_t count_nonfinite(const float* p, std::size_t n) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < n; ++i) count += !std::isfinite(p[i]);
  return count;
}

// `a` (h, w, c) as float RGBA in out.converted; integer types scaled as OIIO
// scales them on reading (value * (1.0f / max), in float); NaN and
// infinities read as 0.
void convert_image(const py::array& a, const char* name, int h, int w, int c, ImageArg& out) {
  float scale = 1;
  if (a.dtype().is(py::dtype::of<uint8_t>())) scale = 1.0f / 255;
  if (a.dtype().is(py::dtype::of<uint16_t>())) scale = 1.0f / 65535;
  Array<float> f = Array<float>::ensure(a);
  if (!f) usage(std::string(name) + " must be a numeric array");
  out.converted.width = w;
  out.converted.height = h;
  out.converted.pixels.resize(static_cast<std::size_t>(w) * h * 4);
  const float* src = f.data();
  float* dst = out.converted.pixels.data();
  std::size_t nonfinite = 0;
  for (std::size_t i = 0; i < static_cast<std::size_t>(w) * h; ++i, src += c, dst += 4) {
    float px[4] = {0, 0, 0, 1};
    for (int k = 0; k < c; ++k) {
      px[k] = src[k] * scale;
      if (!std::isfinite(px[k])) {
        px[k] = 0;
        ++nonfinite;
      }
    }
    if (c <= 2) {  // gray (+ alpha)
      px[3] = c == 2 ? px[1] : 1.0f;
      px[1] = px[2] = px[0];
    }
    for (int k = 0; k < 4; ++k) dst[k] = px[k];
  }
  warn_nonfinite(nonfinite, name);
  out.view = out.converted.view();
}

ImageArg image_arg_values(const py::handle& obj, const char* name) {
  ImageArg out;
  py::array a;
  try {
    a = py::array::ensure(obj);
  } catch (py::error_already_set&) {
  }
  if (!a || a.ndim() < 2 || a.ndim() > 3 || (a.ndim() == 3 && (a.shape(2) < 1 || a.shape(2) > 4))) {
    usage(std::string(name) + " must be an image array of shape (h, w) or (h, w, c), c in 1..4");
  }
  const int h = static_cast<int>(a.shape(0)), w = static_cast<int>(a.shape(1));
  const int c = a.ndim() == 3 ? static_cast<int>(a.shape(2)) : 1;
  if (h == 0 || w == 0) usage(std::string(name) + ": the image has no pixels");
  if (c == 4 && a.dtype().is(py::dtype::of<float>()) && (a.flags() & py::array::c_style)) {
    Array<float> keep = Array<float>::ensure(a);
    if (count_nonfinite(keep.data(), static_cast<std::size_t>(keep.size())) == 0) {
      out.keep = std::move(keep);
      out.view = {w, h, out.keep.data()};
      return out;
    }
  }
  convert_image(a, name, h, w, c, out);
  return out;
}

// The colour space of an image argument: its `colorspace` attribute
// (texbake.ImageArray: read_image's detection, or texbake.image(array,
// colorspace)), "srgb" for a plain array.
ColorSpace colorspace_arg(const py::handle& obj, const char* name) {
  const std::string cs = py::str(py::getattr(obj, "colorspace", py::str("srgb")));
  if (cs == "srgb") return ColorSpace::kSrgb;
  if (cs == "linear") return ColorSpace::kLinear;
  usage(std::string(name) + ".colorspace must be 'srgb' or 'linear', not '" + cs + "'");
}

}  // namespace

ImageArg image_arg(const py::handle& obj, const char* name) {
  ImageArg out = image_arg_values(obj, name);
  out.view.color_space = colorspace_arg(obj, name);
  return out;
}

bool is_path(const py::handle& obj) {
  return py::isinstance<py::str>(obj) || py::hasattr(obj, "__fspath__");
}

std::filesystem::path path_arg(const py::handle& obj, const char* name) {
  if (!is_path(obj)) {
    usage(std::string(name) + " must be a file path (str or os.PathLike), not " +
          std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
  }
  return py::module_::import("os").attr("fspath")(obj).cast<std::string>();
}

ImageArg bake_image_arg(const py::handle& obj, std::size_t cache_mb, const VertexBakeOptions& o) {
  if (!is_path(obj)) return image_arg(obj, "image");
  const std::filesystem::path path = path_arg(obj, "image");
  const bool ewa = o.filter == VertexFilter::kEwa;
  ImageArg out;
  {
    py::gil_scoped_release release;
    out.converted = check(
        read_image(path, texture_read_options(TextureColorSpace::kAuto, cache_mb, o.linear, ewa)));
  }
  if (ewa) check(check_ewa_budget(out.converted, cache_mb, o.linear));
  warn_nonfinite(out.converted.nonfinite_values, path.string());
  out.view = out.converted.view();
  return out;
}

// ---- Option values ----------------------------------------------------------

long long int_arg(const py::handle& obj, const char* flag) {
  const bool integer = py::isinstance<py::int_>(obj) ||
                       (py::hasattr(obj, "dtype") && py::hasattr(obj, "__index__") &&
                        !py::isinstance<py::float_>(obj));
  if (integer) {
    int overflow = 0;
    const py::int_ value = py::reinterpret_borrow<py::object>(obj);
    const long long v = PyLong_AsLongLongAndOverflow(value.ptr(), &overflow);
    if (!overflow && v >= INT_MIN && v <= INT_MAX) return v;
  }
  usage(std::string(flag) + ": '" + std::string(py::str(obj)) + "' is not an integer" +
        (integer ? " of int's range" : ""));
}

std::string keyword_or_color(const py::handle& obj, const char* flag,
                             std::initializer_list<const char*> keywords, Rgba& color) {
  if (py::isinstance<py::str>(obj)) {
    const std::string text = py::str(obj);
    for (const char* k : keywords) {
      if (text == k) return k;
    }
  }
  color = color_arg(obj, flag);
  return "";
}

Rgba color_arg(const py::handle& obj, const char* flag, bool alpha) {
  std::vector<double> c;
  bool numbers = !py::isinstance<py::str>(obj);
  if (numbers) {
    try {
      c = obj.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
      numbers = false;
    }
  }
  // Not numbers: the CLI's message for the text.
  if (!numbers) return check(parse_color(std::string(py::str(obj)), flag, alpha));
  return check(color_from_components(c, flag, alpha));
}

Vec3 vec3_arg(const py::handle& h, const std::string& name) {
  std::vector<double> v;
  try {
    v = h.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
  }
  if (v.size() != 3) usage(name + " must be 3 numbers (x, y, z)");
  return Vec3{v[0], v[1], v[2]};
}

int padding_arg(const py::handle& obj) {
  if (obj.is_none()) return kPaddingDefault;
  if (py::isinstance<py::str>(obj)) return check(parse_padding(std::string(py::str(obj))));
  const bool integer = py::isinstance<py::int_>(obj) && !py::isinstance<py::bool_>(obj);
  return check(parse_padding(integer ? std::string(py::str(obj)) : std::string(py::repr(obj))));
}

std::size_t cache_mb_arg(const py::handle& obj) {
  const long long mb = int_arg(obj, "--cache-mb");
  check(check_cache_mb(mb));
  return static_cast<std::size_t>(mb);
}

VertexBakeOptions shading_options(const py::handle& filter, const py::handle& samples,
                                  const py::handle& visibility, const py::handle& occluded,
                                  const py::handle& outside, bool linear, const py::handle& wrap) {
  VertexBakeOptions o;
  o.filter = choice_arg<VertexFilter>(filter, "--filter");
  o.samples = static_cast<int>(int_arg(samples, "--samples"));
  o.visibility = choice_arg<Visibility>(visibility, "--visibility");
  const std::string occ =
      keyword_or_color(occluded, "--occluded", {"fill", "project"}, o.occluded_color);
  o.occluded = occ == "fill"      ? OccludedMode::kFill
               : occ == "project" ? OccludedMode::kProject
                                  : OccludedMode::kColor;
  const std::string out = keyword_or_color(outside, "--outside", {"clamp"}, o.outside_color);
  o.outside = out == "clamp" ? OutsideMode::kClamp : OutsideMode::kColor;
  o.linear = linear;
  o.plane_wrap = choice_arg<WrapMode>(wrap, "--wrap");
  return o;
}

AtlasOptions atlas_options(const py::handle& uv, const py::handle& size, const py::handle& samples,
                           const py::handle& padding, const VertexBakeOptions& shading) {
  AtlasOptions o;
  o.uv = choice_arg<UvLayout>(uv, "--uv");
  o.bake.size = static_cast<int>(int_arg(size, "--size"));
  o.bake.samples = static_cast<int>(int_arg(samples, "--samples"));
  o.bake.shading = shading;
  check(validate_options(o));  // the CLI's order: size and samples, then padding
  o.bake.padding = padding_arg(padding);
  return o;
}

// ---- Results --------------------------------------------------------------

py::dict stats_dict(const Stats& s) {
  const Counts& c = s.counts;
  const Timings& t = s.timings;
  py::dict counts;
  counts["vertices"] = c.vertices;
  counts["triangles"] = c.triangles;
  counts["degenerate_triangles"] = c.degenerate_triangles;
  counts["unreferenced_vertices"] = c.unreferenced_vertices;
  counts["samples"] = c.samples;
  counts["occluded"] = c.occluded;
  counts["undefined"] = c.undefined;
  counts["outside"] = c.outside;
  counts["filled"] = c.filled;
  counts["unfilled"] = c.unfilled;
  counts["texels"] = c.texels;
  counts["border_samples"] = c.border_samples;
  counts["padded"] = c.padded;
  py::dict timings;
  timings["fit"] = t.fit;
  timings["uv_layout"] = t.uv_layout;
  timings["rasterize"] = t.rasterize;
  timings["scene_build"] = t.scene_build;
  timings["bake"] = t.bake;
  timings["fill"] = t.fill;
  timings["pad"] = t.pad;
  timings["render"] = t.render;
  timings["total"] = t.total;
  py::dict out;
  out["counts"] = counts;
  out["timings"] = timings;
  out["warnings"] = s.warnings;
  out["notes"] = s.notes;
  return out;
}

namespace {

// A report's JSON value as Python's (json.loads of its text).
py::object from_json(const nlohmann::ordered_json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

}  // namespace

py::dict bake_stats(const Stats& s, ReportSource source, bool atlas,
                    const std::vector<LayerStats>& layers) {
  py::dict out = stats_dict(s);
  out["counts"] = from_json(counts_json(source, atlas, s.counts));
  nlohmann::ordered_json timings = stage_timings_json(source, atlas, s.timings, layers);
  timings["total"] = s.timings.total;
  out["timings"] = from_json(timings);
  return out;
}

py::object atlas_result(Atlas&& atlas, ReportSource source, const AtlasBakeOptions& options,
                        const std::vector<SkippedPhoto>* skipped,
                        const std::vector<LayerStats>& layers) {
  py::dict report = bake_stats(atlas.stats, source, /*atlas=*/true, layers);
  AtlasBakeOptions reported = options;
  reported.size = atlas.image.width;  // a layers bake's size 0: the base texture's
  nlohmann::ordered_json object = atlas_json(AtlasReport{reported, atlas.uv}, atlas.stats, 0);
  object.erase("timings");
  report["atlas"] = from_json(object);
  if (skipped) report["photos_skipped"] = skipped_list(*skipped);
  py::object out = py::cast(std::move(atlas));
  out.attr("_report") = report;  // read by Atlas.stats (bind_bake.cpp)
  return out;
}

py::list skipped_list(const std::vector<SkippedPhoto>& skipped) {
  py::list out;
  for (const SkippedPhoto& k : skipped) {
    py::dict d;
    d["image"] = k.name;
    d["path"] = k.path.string();
    d["reason"] = k.reason;
    out.append(d);
  }
  return out;
}

py::list cameras_list(const std::vector<PhotoCameraStats>& cameras) {
  py::list out;
  for (const PhotoCameraStats& c : cameras) {
    py::dict d;
    d["image"] = c.name;
    d["photo"] = py::make_tuple(c.photo_width, c.photo_height);
    d["masked"] = c.masked_share;
    d["in_view"] = c.in_view;
    d["visible"] = c.visible;
    d["weight_share"] = c.weight_share;
    d["gain"] = py::make_tuple(c.gain[0], c.gain[1], c.gain[2]);
    d["shared"] = c.shared;
    d["deviation"] = c.deviation;
    out.append(d);
  }
  return out;
}

py::list layers_list(const std::vector<LayerStats>& layers) {
  py::list out;
  for (const LayerStats& l : layers) {
    py::dict d;
    d[l.photos ? "cameras" : "texture"] = l.name;
    d["in_domain"] = l.in_domain;
    d["visible"] = l.visible;
    d["blended"] = l.blended;
    d["mean_alpha"] = l.mean_alpha;
    d["seconds"] = l.seconds;
    if (l.photos) d["photos_skipped"] = skipped_list(l.skipped);
    out.append(d);
  }
  return out;
}

const PyProxy& proxy_arg(const py::handle& obj, const char* name) {
  const py::object native = py::getattr(obj, "_native", py::none());
  const py::handle h = native.is_none() ? obj : native;
  if (!py::isinstance<PyProxy>(h)) {
    usage(std::string(name) + " must be a texbake.Proxy, not " +
          std::string(py::str(py::type::handle_of(obj).attr("__name__"))));
  }
  return h.cast<const PyProxy&>();
}

}  // namespace texbake::python
