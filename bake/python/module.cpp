// The C++ half of the Python module `texbake` (SPEC section 11, issue #15):
// pybind11 bindings of texbake/texbake.h, imported as texbake._texbake. The
// Python half (bake/python/texbake/__init__.py) gives the functions their
// keyword signatures and docstrings; everything here takes the option
// values already spelled as the CLI spells them ("area", "first", ...).
//
// Conventions of every binding here:
//  - Arrays in: numpy arrays of any numeric dtype convertible to the C++
//    type; a wrong shape raises ValueError naming the argument. An image
//    that is already (h, w, 4) float32 and C-contiguous is read in place
//    (no copy); any other image is converted once. Mesh arrays are always
//    converted (MeshData holds float32 positions and uint32 indices).
//  - Arrays out own their data through a capsule (no copy of images).
//  - Errors: every Expected of the API goes through check() (the one place
//    that maps ErrorCategory to a Python exception): kUsage -> ValueError,
//    kInput -> OSError, kInternal -> RuntimeError, kCancelled ->
//    texbake.Cancelled, with the API's message (the CLI's).
//  - Long calls release the GIL; the progress callback re-acquires it.
//    An exception raised by the callback cancels the call and is re-raised.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "texbake/texbake.h"

namespace py = pybind11;
using namespace texbake;

namespace {

// ---- Errors ---------------------------------------------------------------

struct ApiError {
  Error error;
};

PyObject* g_cancelled = nullptr;  // texbake.Cancelled

// The one mapping of ErrorCategory to Python exceptions (see the file comment).
[[noreturn]] void raise(const Error& error) {
  throw ApiError{error};
}

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

template <class T>
T check(Expected<T>&& result) {
  if (!result) raise(result.error());
  return std::move(*result);
}

[[noreturn]] void usage(const std::string& message) {
  raise(make_error(ErrorCode::kInvalidArgument, message));
}

// ---- Progress -------------------------------------------------------------

// RunOptions whose progress calls the Python callable (with the GIL) and
// keeps an exception it raises for rethrow() after the call.
struct PyRun {
  RunOptions run;
  py::object callback;
  std::optional<py::error_already_set> raised;

  PyRun(int threads, py::object progress) : callback(std::move(progress)) {
    if (threads < 0 || threads > 4096)
      usage("threads must be in 0..4096 (got " + std::to_string(threads) + ")");
    run.threads = threads;
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
  // Re-raises the callback's exception, if any (call with the GIL held).
  void rethrow() {
    if (raised) {
      py::error_already_set e = std::move(*raised);
      raised.reset();
      throw e;
    }
  }
};

// Runs work() without the GIL, then re-raises the callback's exception or
// the work's error.
template <class T, class Work>
T run_released(PyRun& run, Work&& work) {
  std::optional<Expected<T>> out;
  {
    py::gil_scoped_release release;
    out.emplace(work(run.run));
  }
  run.rethrow();
  return check(std::move(*out));
}

// ---- Arrays ---------------------------------------------------------------

template <class T>
using Array = py::array_t<T, py::array::c_style | py::array::forcecast>;

// `a` as a C-contiguous array of T with shape (n, cols) (cols 0: any).
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

// An owning numpy array over `data` (moved into a capsule), shape `shape`.
template <class T>
py::array_t<T> owned(std::vector<T>&& data, std::vector<py::ssize_t> shape) {
  auto* held = new std::vector<T>(std::move(data));
  py::capsule free(held, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, held->data(), free);
}

// A table of C floats per row (Float2, Float3, Rgba) as an (n, C) array of Out.
template <class Out, class T>
py::array_t<Out> table_array(const std::vector<T>& rows) {
  constexpr std::size_t kCols = sizeof(T) / sizeof(float);
  static_assert(sizeof(T) == kCols * sizeof(float));
  const float* f = reinterpret_cast<const float*>(rows.data());
  return owned(std::vector<Out>(f, f + rows.size() * kCols),
               {static_cast<py::ssize_t>(rows.size()), static_cast<py::ssize_t>(kCols)});
}

// Indices as int64: (n,) or, with cols > 0, (n / cols, cols).
py::array_t<int64_t> index_array(const std::vector<uint32_t>& v, py::ssize_t cols = 0) {
  const auto n = static_cast<py::ssize_t>(v.size());
  std::vector<py::ssize_t> shape =
      cols > 0 ? std::vector<py::ssize_t>{n / cols, cols} : std::vector<py::ssize_t>{n};
  return owned(std::vector<int64_t>(v.begin(), v.end()), std::move(shape));
}

// make() when the attribute is present, else None.
template <class Make>
py::object present(bool is_present, Make&& make) {
  return is_present ? py::object(make()) : py::object(py::none());
}

// Per-corner indices of equal-size polygons (m, k), checked against `limit`.
void check_indices(const Array<int64_t>& a, const char* name, std::size_t limit) {
  const int64_t* p = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if (p[i] < 0 || static_cast<uint64_t>(p[i]) >= limit) {
      usage(std::string(name) + ": index " + std::to_string(p[i]) + " at row " +
            std::to_string(i / a.shape(1)) + " is outside 0.." + std::to_string(limit) + "-1");
    }
  }
}

// A mesh from arrays (Mesh(vertices, faces, ...) in Python), not yet
// triangulated. Faces are (m, k) polygons of k >= 3 corners.
MeshData mesh_from_arrays(const py::handle& vertices, const py::handle& faces,
                          const py::handle& uvs, const py::handle& face_uvs,
                          const py::handle& colors, const py::handle& normals,
                          const py::handle& face_normals) {
  MeshData m;
  Array<double> v = rows<double>(vertices, "vertices", 3);
  Array<int64_t> f = rows<int64_t>(faces, "faces", 0);
  if (f.shape(1) < 3)
    usage("faces must have at least 3 corners per row (got " + std::to_string(f.shape(1)) + ")");
  const std::size_t n = v.shape(0), k = f.shape(1), nf = f.shape(0);
  m.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = v.data() + 3 * i;
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) {
      usage("vertices: row " + std::to_string(i) + " is not finite");
    }
    m.positions[i] = {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
  }
  check_indices(f, "faces", n);
  m.face_offsets.resize(nf + 1);
  for (std::size_t i = 0; i <= nf; ++i) m.face_offsets[i] = static_cast<uint32_t>(i * k);
  m.face_vertices.assign(f.data(), f.data() + f.size());
  // A per-corner table (uvs + face_uvs, normals + face_normals).
  auto corner_table = [&](const py::handle& table, const py::handle& index, const char* tname,
                          const char* iname, py::ssize_t cols, auto& out,
                          std::vector<uint32_t>& corner) {
    if (table.is_none() && index.is_none()) return;
    if (table.is_none() || index.is_none())
      usage(std::string(tname) + " and " + iname + " go together");
    Array<double> t = rows<double>(table, tname, cols);
    Array<int64_t> c = rows<int64_t>(index, iname, 0);
    if (c.shape(0) != f.shape(0) || c.shape(1) != f.shape(1)) {
      usage(std::string(iname) + " must have the shape of faces");
    }
    check_indices(c, iname, t.shape(0));
    out.resize(t.shape(0));
    for (py::ssize_t i = 0; i < t.shape(0); ++i) {
      const double* p = t.data() + cols * i;
      if constexpr (std::is_same_v<std::decay_t<decltype(out[0])>, Float2>) {
        out[i] = {static_cast<float>(p[0]), static_cast<float>(p[1])};
      } else {
        out[i] = {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
      }
    }
    corner.assign(c.data(), c.data() + c.size());
  };
  corner_table(uvs, face_uvs, "uvs", "face_uvs", 2, m.uvs, m.corner_uv);
  corner_table(normals, face_normals, "normals", "face_normals", 3, m.normals, m.corner_normal);
  if (!colors.is_none()) {
    Array<float> c = rows<float>(colors, "colors", 0);
    if (static_cast<std::size_t>(c.shape(0)) != n || (c.shape(1) != 3 && c.shape(1) != 4)) {
      usage("colors must have shape (n, 3) or (n, 4) with n = the vertex count");
    }
    m.vertex_colors.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      const float* p = c.data() + c.shape(1) * i;
      m.vertex_colors[i] = {p[0], p[1], p[2], c.shape(1) == 4 ? p[3] : 1.0f};
    }
  }
  return m;
}

// The image argument: (h, w), (h, w, 1..4) numbers; uint8 / uint16 are
// scaled to [0, 1] as read_image does. Keeps `keep` alive for the view.
struct ImageArg {
  ImageView view;
  Array<float> keep;  // the array viewed (float32 RGBA) ...
  Image converted;    // ... or the conversion
};

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
    out.keep = Array<float>::ensure(a);
    out.view = {w, h, out.keep.data()};
    return out;
  }
  // As OIIO converts on reading: value * (1.0f / max), in float.
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
  for (std::size_t i = 0; i < static_cast<std::size_t>(w) * h; ++i, src += c, dst += 4) {
    float px[4] = {0, 0, 0, 1};
    for (int k = 0; k < c; ++k) px[k] = src[k] * scale;
    if (c <= 2) {  // gray (+ alpha)
      px[3] = c == 2 ? px[1] : 1.0f;
      px[1] = px[2] = px[0];
    }
    for (int k = 0; k < 4; ++k) dst[k] = px[k];
  }
  out.view = out.converted.view();
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

// An image argument's values and colour space.
ImageArg image_arg(const py::handle& obj, const char* name) {
  ImageArg out = image_arg_values(obj, name);
  out.view.color_space = colorspace_arg(obj, name);
  return out;
}

// The image of a bake: an image array (image_arg), or a file path (str or
// os.PathLike) read as `texbake bake --texture` reads it, with the memory
// budget `cache_mb` (past it the texels are read in tiles through
// OpenImageIO's ImageCache; ValueError for --filter ewa whose MIP levels do
// not fit it).
ImageArg bake_image_arg(const py::handle& obj, std::size_t cache_mb, const VertexBakeOptions& o) {
  if (!py::isinstance<py::str>(obj) && !py::hasattr(obj, "__fspath__")) {
    return image_arg(obj, "image");
  }
  const std::filesystem::path path =
      py::module_::import("os").attr("fspath")(obj).cast<std::string>();
  const bool ewa = o.filter == VertexFilter::kEwa;
  ImageArg out;
  {
    py::gil_scoped_release release;
    out.converted = check(
        read_image(path, texture_read_options(TextureColorSpace::kAuto, cache_mb, o.linear, ewa)));
  }
  if (ewa) check(check_ewa_budget(out.converted, cache_mb, o.linear));
  out.view = out.converted.view();
  return out;
}

py::array_t<float> image_array(Image&& image) {
  const int h = image.height, w = image.width;
  return owned(std::move(image.pixels), {h, w, 4});
}

// 3 numbers (any sequence); ValueError naming `name` otherwise.
Vec3 vec3_arg(const py::handle& h, const std::string& name) {
  std::vector<double> v;
  try {
    v = h.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
  }
  if (v.size() != 3) usage(name + " must be 3 numbers (x, y, z)");
  return Vec3{v[0], v[1], v[2]};
}

// ---- Options from the CLI's names -----------------------------------------

template <class T>
T choice(const std::string& value, const char* name,
         std::initializer_list<std::pair<const char*, T>> names) {
  std::string expected;
  std::size_t i = 0;
  for (const auto& [n, v] : names) {
    if (value == n) return v;
    expected += std::string(i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + n;
    ++i;
  }
  usage(std::string(name) + ": unknown value '" + value + "' (expected " + expected + ")");
}

// "fill" | "project" | colour (a sequence of 3 or 4 numbers).
Rgba color_arg(const py::handle& obj, const char* name) {
  std::vector<float> c;
  try {
    c = obj.cast<std::vector<float>>();
  } catch (const py::cast_error&) {
  }
  if (c.size() != 3 && c.size() != 4)
    usage(std::string(name) + " must be a keyword or a colour (r, g, b[, a])");
  return {c[0], c[1], c[2], c.size() == 4 ? c[3] : 1.0f};
}

// occluded= for the photo and layers bakes: "fill" or a colour.
void occluded_arg(const py::object& occluded, OccludedMode& mode, Rgba& color) {
  if (py::isinstance<py::str>(occluded)) {
    mode = choice<OccludedMode>(occluded.cast<std::string>(), "occluded",
                                {{"fill", OccludedMode::kFill}});
  } else {
    mode = OccludedMode::kColor;
    color = color_arg(occluded, "occluded");
  }
}

// Per-vertex colours as an (n, 4) float32 array.
py::array_t<float> colors_array(const std::vector<Rgba>& colors) {
  std::vector<float> flat;
  flat.reserve(colors.size() * 4);
  for (const Rgba& c : colors) flat.insert(flat.end(), c.begin(), c.end());
  return owned(std::move(flat), {static_cast<py::ssize_t>(colors.size()), 4});
}

VertexBakeOptions shading_options(const std::string& filter, int samples,
                                  const std::string& visibility, const py::object& occluded,
                                  const py::object& outside, bool linear, const std::string& wrap) {
  VertexBakeOptions o;
  o.filter = choice<VertexFilter>(filter, "filter",
                                  {{"bilinear", VertexFilter::kBilinear},
                                   {"area", VertexFilter::kArea},
                                   {"ewa", VertexFilter::kEwa}});
  o.samples = samples;
  o.visibility = choice<Visibility>(visibility, "visibility",
                                    {{"first", Visibility::kFirst}, {"all", Visibility::kAll}});
  if (py::isinstance<py::str>(occluded)) {
    o.occluded =
        choice<OccludedMode>(occluded.cast<std::string>(), "occluded",
                             {{"fill", OccludedMode::kFill}, {"project", OccludedMode::kProject}});
  } else {
    o.occluded = OccludedMode::kColor;
    o.occluded_color = color_arg(occluded, "occluded");
  }
  if (py::isinstance<py::str>(outside)) {
    o.outside = choice<OutsideMode>(outside.cast<std::string>(), "outside",
                                    {{"clamp", OutsideMode::kClamp}});
  } else {
    o.outside = OutsideMode::kColor;
    o.outside_color = color_arg(outside, "outside");
  }
  o.linear = linear;
  o.plane_wrap =
      choice<WrapMode>(wrap, "wrap", {{"clamp", WrapMode::kClamp}, {"repeat", WrapMode::kRepeat}});
  return o;
}

// ---- Stats ----------------------------------------------------------------

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
  return out;
}

// ---- Proxies --------------------------------------------------------------

// A ProxySpec from a kind and a dict of given values by JSON key.
ProxySpec spec_from_dict(const std::string& kind_name, const py::dict& values,
                         const py::object& up) {
  std::optional<ProxyKind> kind = parse_proxy_kind(kind_name);
  if (!kind) {
    usage("unknown proxy kind '" + kind_name +
          "' (expected sphere, cylinder, cone, disk, quad or plane)");
  }
  ProxySpec spec{*kind, {}, std::nullopt};
  const auto& vec3 = vec3_arg;
  for (const auto& [k, value] : values) {
    if (value.is_none()) continue;
    const std::string key = py::str(k);
    const ParamField* field = find_field(*kind, key);
    if (!field) {
      std::string keys;
      for (const ParamField& f : proxy_fields(*kind))
        keys += (keys.empty() ? "" : ", ") + std::string(f.key);
      usage(std::string(to_string(*kind)) + ": unknown key '" + key + "' (expected " + keys + ")");
    }
    switch (field->type) {
      case ParamType::kNumber:
        try {
          spec.values[key] = value.cast<double>();
        } catch (const py::cast_error&) {
          usage(std::string(to_string(*kind)) + ": " + key + " must be a number");
        }
        break;
      case ParamType::kVec3:
        spec.values[key] = vec3(value, std::string(to_string(*kind)) + ": " + key);
        break;
      case ParamType::kCorners: {
        std::array<Vec3, 4> corners;
        py::sequence seq;
        if (!py::isinstance<py::sequence>(value) || py::len(value) != 4) {
          usage(std::string(to_string(*kind)) + ": corners must be 4 points");
        }
        seq = value.cast<py::sequence>();
        for (int i = 0; i < 4; ++i)
          corners[i] = vec3(seq[i], std::string(to_string(*kind)) + ": corners");
        spec.values[key] = corners;
        break;
      }
    }
  }
  if (!up.is_none()) spec.up = vec3(up, "up");
  return spec;
}

struct PyProxy {
  Proxy proxy;
  std::vector<std::string> fitted;  // keys filled by fit()
};

}  // namespace

PYBIND11_MODULE(_texbake, m) {
  m.doc() = "texbake's C++ bindings; use the package `texbake`.";
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
  m.def("version", &texbake::version);

  // ---- Mesh ----
  py::class_<LoadedMesh>(
      m, "Mesh",
      "A mesh: Mesh(vertices (n, 3), faces (m, k), uvs=None, face_uvs=None, "
      "colors=None, normals=None, face_normals=None) or texbake.read_mesh(path). "
      "Properties (numpy copies): vertices, faces (None for mixed polygons), "
      "triangles, face_offsets, face_vertices, uvs, corner_uvs, normals, "
      "corner_normals, colors, texture_path, issues.")
      .def(py::init([](py::handle vertices, py::handle faces, py::handle uvs, py::handle face_uvs,
                       py::handle colors, py::handle normals, py::handle face_normals) {
             LoadedMesh out;
             out.mesh =
                 mesh_from_arrays(vertices, faces, uvs, face_uvs, colors, normals, face_normals);
             out.issues = triangulate_faces(out.mesh);
             return out;
           }),
           py::arg("vertices"), py::arg("faces"), py::arg("uvs") = py::none(),
           py::arg("face_uvs") = py::none(), py::arg("colors") = py::none(),
           py::arg("normals") = py::none(), py::arg("face_normals") = py::none())
      .def_property_readonly(
          "vertices", [](const LoadedMesh& l) { return table_array<double>(l.mesh.positions); })
      .def_property_readonly("faces",
                             [](const LoadedMesh& l) -> py::object {
                               const MeshData& d = l.mesh;
                               const std::size_t nf = d.face_count();
                               std::size_t k = nf ? d.face_offsets[1] - d.face_offsets[0] : 3;
                               for (std::size_t f = 0; f < nf; ++f) {
                                 if (d.face_offsets[f + 1] - d.face_offsets[f] != k) k = 0;
                               }
                               if (k == 0) return py::none();
                               return index_array(d.face_vertices, static_cast<py::ssize_t>(k));
                             })
      .def_property_readonly("triangles",
                             [](const LoadedMesh& l) {
                               std::vector<uint32_t> t;
                               for (const auto& tri : l.mesh.triangles)
                                 t.insert(t.end(), tri.begin(), tri.end());
                               return index_array(t, 3);
                             })
      .def_property_readonly("face_offsets",
                             [](const LoadedMesh& l) { return index_array(l.mesh.face_offsets); })
      .def_property_readonly("face_vertices",
                             [](const LoadedMesh& l) { return index_array(l.mesh.face_vertices); })
      .def_property_readonly("uvs",
                             [](const LoadedMesh& l) {
                               return present(l.mesh.has_uvs(),
                                              [&] { return table_array<double>(l.mesh.uvs); });
                             })
      .def_property_readonly("corner_uvs",
                             [](const LoadedMesh& l) {
                               return present(l.mesh.has_uvs(),
                                              [&] { return index_array(l.mesh.corner_uv); });
                             })
      .def_property_readonly("normals",
                             [](const LoadedMesh& l) {
                               return present(!l.mesh.corner_normal.empty(),
                                              [&] { return table_array<double>(l.mesh.normals); });
                             })
      .def_property_readonly("corner_normals",
                             [](const LoadedMesh& l) {
                               return present(!l.mesh.corner_normal.empty(),
                                              [&] { return index_array(l.mesh.corner_normal); });
                             })
      .def_property_readonly("colors",
                             [](const LoadedMesh& l) {
                               return present(l.mesh.has_vertex_colors(), [&] {
                                 return table_array<float>(l.mesh.vertex_colors);
                               });
                             })
      .def_property_readonly("texture_path",
                             [](const LoadedMesh& l) -> py::object {
                               if (l.mesh.texture_path.empty()) return py::none();
                               return py::str(l.mesh.texture_path);
                             })
      .def_property_readonly("issues", [](const LoadedMesh& l) {
        py::dict d;
        d["degenerate_triangles"] = l.issues.degenerate_triangles;
        d["unreferenced_vertices"] = l.issues.unreferenced_vertices;
        d["non_manifold_edges"] = l.issues.non_manifold_edges;
        return d;
      });

  m.def("read_mesh", [](const std::filesystem::path& path) {
    py::gil_scoped_release release;
    return check(read_mesh(path));
  });
  m.def("read_image", [](const std::filesystem::path& path, const std::string& colorspace) {
    ImageReadOptions options;
    if (colorspace == "srgb") {
      options.color_space = TextureColorSpace::kSrgb;
    } else if (colorspace == "linear") {
      options.color_space = TextureColorSpace::kLinear;
    } else if (colorspace != "auto") {
      usage("colorspace must be 'auto', 'srgb' or 'linear', not '" + colorspace + "'");
    }
    Image image;
    {
      py::gil_scoped_release release;
      image = check(read_image(path, options));
    }
    const char* space = image.color_space == ColorSpace::kLinear ? "linear" : "srgb";
    return py::make_tuple(image_array(std::move(image)), space);
  });

  // ---- Proxy ----
  py::class_<PyProxy>(m, "Proxy")
      .def_property_readonly("kind", [](const PyProxy& p) { return to_string(kind_of(p.proxy)); })
      .def_property_readonly("fitted", [](const PyProxy& p) { return p.fitted; })
      .def("to_json", [](const PyProxy& p) { return proxy_to_json(p.proxy); })
      .def("write", [](const PyProxy& p, const std::filesystem::path& path) {
        check(write_proxy_file(path, p.proxy));
      });
  m.def("make_proxy", [](const std::string& kind, const py::dict& values, const py::object& up) {
    const ProxySpec spec = spec_from_dict(kind, values, up);
    check(check_given_values(spec));
    ProxyParams params = check(params_from_spec(spec));
    return PyProxy{check(make_proxy(params)), {}};
  });
  m.def("proxy_from_json", [](const std::string& text, const std::string& source) {
    return PyProxy{check(proxy_from_json(text, source)), {}};
  });
  m.def("read_proxy_file", [](const std::filesystem::path& path) {
    return PyProxy{check(read_proxy_file(path)), {}};
  });
  m.def("fit", [](const LoadedMesh& mesh, const std::string& kind, const py::dict& given,
                  const py::object& up, int threads) {
    const ProxySpec spec = spec_from_dict(kind, given, up);
    check(check_triangles(mesh.mesh));
    PyRun run(threads, py::none());
    CompletedProxy c = run_released<CompletedProxy>(
        run, [&](const RunOptions& r) { return complete_proxy(spec, mesh.mesh, r); });
    return PyProxy{std::move(c.proxy), std::move(c.fitted)};
  });
  m.def("map", [](const PyProxy& proxy, py::handle points) {
    Array<double> p = rows<double>(points, "points", 3);
    const std::size_t n = p.shape(0);
    std::vector<double> uv(2 * n), dir(3 * n);
    std::vector<int8_t> status(n);
    {
      py::gil_scoped_release release;
      for (std::size_t i = 0; i < n; ++i) {
        const double* q = p.data() + 3 * i;
        const MapResult r = inverse_map(proxy.proxy, Vec3{q[0], q[1], q[2]});
        uv[2 * i] = r.uv.u;
        uv[2 * i + 1] = r.uv.v;
        dir[3 * i] = r.to_projector.x;
        dir[3 * i + 1] = r.to_projector.y;
        dir[3 * i + 2] = r.to_projector.z;
        status[i] = static_cast<int8_t>(r.status);
      }
    }
    const auto sn = static_cast<py::ssize_t>(n);
    return py::make_tuple(owned(std::move(uv), {sn, 2}), owned(std::move(status), {sn}),
                          owned(std::move(dir), {sn, 3}));
  });

  // ---- Bakes ----
  m.def("bake_vertex",
        [](const LoadedMesh& mesh, py::handle image, const PyProxy& proxy,
           const std::string& filter, int samples, const std::string& visibility,
           py::object occluded, py::object outside, bool linear, const std::string& wrap,
           std::size_t cache_mb, int threads, py::object progress) {
          const VertexBakeOptions o =
              shading_options(filter, samples, visibility, occluded, outside, linear, wrap);
          check(validate_options(o));
          ImageArg img = bake_image_arg(image, cache_mb, o);
          PyRun run(threads, std::move(progress));
          VertexColors baked = run_released<VertexColors>(run, [&](const RunOptions& r) {
            return bake_vertex_colors(mesh.mesh, img.view, proxy.proxy, o, r);
          });
          return py::make_tuple(colors_array(baked.colors), stats_dict(baked.stats));
        });

  m.def("bake_vertex_from_photos", [](const LoadedMesh& mesh, const std::filesystem::path& cameras,
                                      const std::filesystem::path& images, const std::string& blend,
                                      const std::string& exposure, py::object occluded,
                                      const std::string& colorspace, bool strict_photos,
                                      int threads, py::object progress) {
    PhotoBakeOptions o;
    o.strict_photos = strict_photos;
    o.blend = choice<PhotoBlend>(
        blend, "blend",
        {{"soft", PhotoBlend::kSoft}, {"best", PhotoBlend::kBest}, {"mean", PhotoBlend::kMean}});
    o.exposure = choice<ExposureMode>(
        exposure, "exposure", {{"gain", ExposureMode::kGain}, {"none", ExposureMode::kNone}});
    occluded_arg(occluded, o.occluded, o.occluded_color);
    o.color_space = choice<TextureColorSpace>(colorspace, "colorspace",
                                              {{"auto", TextureColorSpace::kAuto},
                                               {"srgb", TextureColorSpace::kSrgb},
                                               {"linear", TextureColorSpace::kLinear}});
    const std::vector<Photo> photos = check(read_cameras(cameras, images));
    PyRun run(threads, std::move(progress));
    PhotoColors baked = run_released<PhotoColors>(run, [&](const RunOptions& r) {
      return bake_vertex_colors_from_photos(mesh.mesh, photos, o, r);
    });
    py::list per_camera;
    for (const PhotoCameraStats& c : baked.cameras) {
      py::dict d;
      d["image"] = c.name;
      d["photo"] = py::make_tuple(c.photo_width, c.photo_height);
      d["in_view"] = c.in_view;
      d["visible"] = c.visible;
      d["weight_share"] = c.weight_share;
      d["gain"] = py::make_tuple(c.gain[0], c.gain[1], c.gain[2]);
      per_camera.append(d);
    }
    py::dict stats = stats_dict(baked.stats);
    py::list skipped;
    for (const SkippedPhoto& k : baked.skipped) {
      py::dict d;
      d["image"] = k.name;
      d["path"] = k.path.string();
      d["reason"] = k.reason;
      skipped.append(d);
    }
    stats["photos_skipped"] = skipped;
    return py::make_tuple(colors_array(baked.colors), stats, per_camera);
  });

  m.def("bake_vertex_from_layers", [](const LoadedMesh& mesh, const std::filesystem::path& layers,
                                      py::object occluded, int threads, py::object progress) {
    LayersBakeOptions o;
    occluded_arg(occluded, o.occluded, o.occluded_color);
    const LayersSpec spec = check(read_layers(layers));
    PyRun run(threads, std::move(progress));
    LayerColors baked = run_released<LayerColors>(run, [&](const RunOptions& r) {
      return bake_vertex_colors_from_layers(mesh.mesh, spec, o, r);
    });
    py::list per_layer;
    for (const LayerStats& l : baked.layers) {
      py::dict d;
      d[l.photos ? "cameras" : "texture"] = l.name;
      d["in_domain"] = l.in_domain;
      d["visible"] = l.visible;
      d["blended"] = l.blended;
      d["mean_alpha"] = l.mean_alpha;
      d["seconds"] = l.seconds;
      per_layer.append(d);
    }
    return py::make_tuple(colors_array(baked.colors), stats_dict(baked.stats), per_layer);
  });

  py::class_<Atlas>(m, "Atlas",
                    "An atlas bake (texbake.bake_atlas): image (N, N, 4) float32, mesh (with "
                    "the per-corner UVs baked against), uvs, face_uvs, stats, uv_layout, "
                    "repeat_u. Unpacks as image, uvs, face_uvs, stats; texbake.write_atlas "
                    "writes it.")
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
      .def_property_readonly("uv_layout",
                             [](const Atlas& a) {
                               py::dict d;
                               d["used"] = to_string(a.uv.used);
                               d["corners_outside"] = a.uv.corners_outside;
                               d["overlap_texels"] = a.uv.overlap_texels;
                               d["cut_triangles"] = a.uv.cut_triangles;
                               d["charts"] = a.uv.charts;
                               d["utilisation"] = a.uv.utilisation;
                               d["stretch_l2"] = a.uv.stretch_l2;
                               return d;
                             })
      .def_property_readonly("stats", [](const Atlas& a) { return stats_dict(a.stats); });

  m.def("bake_atlas",
        [](const LoadedMesh& mesh, py::handle image, const PyProxy& proxy, const std::string& uv,
           int size, int samples, py::object padding, const std::string& visibility,
           py::object occluded, py::object outside, bool linear, const std::string& wrap,
           std::size_t cache_mb, int threads, py::object progress) {
          AtlasOptions o;
          o.uv = choice<UvLayout>(uv, "uv",
                                  {{"auto", UvLayout::kAuto},
                                   {"mesh", UvLayout::kMesh},
                                   {"generate", UvLayout::kGenerate},
                                   {"proxy", UvLayout::kProxy}});
          o.bake.size = size;
          o.bake.samples = samples;
          if (padding.is_none()) {
            o.bake.padding = kPaddingDefault;
          } else if (py::isinstance<py::str>(padding)) {
            if (padding.cast<std::string>() != "inf")
              usage("padding must be a count >= 0, 'inf' or None");
            o.bake.padding = kPaddingInfinite;
          } else {
            const int p = padding.cast<int>();
            if (p < 0)
              usage("padding must be a count >= 0, 'inf' or None (got " + std::to_string(p) + ")");
            o.bake.padding = p;
          }
          o.bake.shading = shading_options("area", 16, visibility, occluded, outside, linear, wrap);
          check(validate_options(o));
          ImageArg img = bake_image_arg(image, cache_mb, o.bake.shading);
          PyRun run(threads, std::move(progress));
          return run_released<Atlas>(run, [&](const RunOptions& r) {
            return bake_atlas_texture(mesh.mesh, img.view, proxy.proxy, o, r);
          });
        });

  m.def("render", [](const LoadedMesh& mesh, const std::string& colors, py::object texture,
                     py::object proxy, py::object atlas_image, py::object outside,
                     const std::string& wrap, bool linear, int width, int height, double azimuth,
                     double elevation, int views, bool shadows, int samples, py::object up,
                     bool flat, py::object background, int threads, py::object progress) {
    RenderOptions o;
    o.width = width;
    o.height = height;
    o.azimuth_deg = azimuth;
    o.elevation_deg = elevation;
    o.views = views;
    o.shadows = shadows;
    o.samples_per_pixel = samples;
    o.up = vec3_arg(up, "up");
    o.smooth_normals = !flat;
    if (!background.is_none()) {
      const Rgba b = color_arg(background, "background");
      for (int c = 0; c < 3; ++c) o.background[c] = b[c];
    }
    ImageArg img;
    ColorSource source = GreySource{};
    if (!texture.is_none()) {
      if (proxy.is_none()) usage("texture needs a proxy");
      img = image_arg(texture, "texture");
      ProjectionSource p{
          proxy.cast<const PyProxy&>().proxy, img.view, std::nullopt,
          choice<WrapMode>(wrap, "wrap",
                           {{"clamp", WrapMode::kClamp}, {"repeat", WrapMode::kRepeat}}),
          linear};
      if (!py::isinstance<py::str>(outside)) p.outside = color_arg(outside, "outside");
      source = p;
    } else if (colors == "atlas" || (colors == "auto" && !atlas_image.is_none())) {
      if (atlas_image.is_none()) usage("colors='atlas' needs atlas_image");
      img = image_arg(atlas_image, "atlas_image");
      source = AtlasSource{img.view};
    } else if (colors == "vertex" || (colors == "auto" && mesh.mesh.has_vertex_colors())) {
      source = VertexColorSource{};
    } else if (colors != "auto" && colors != "none") {
      usage("colors: unknown value '" + colors + "' (expected auto, vertex, atlas or none)");
    }
    PyRun run(threads, std::move(progress));
    Rendered r = run_released<Rendered>(
        run, [&](const RunOptions& ro) { return render_mesh(mesh.mesh, source, o, ro); });
    const int h = r.image.height, w = r.image.width;
    return py::make_tuple(owned(std::move(r.image.pixels), {h, w, 4}), stats_dict(r.stats));
  });

  m.def("compare", [](py::handle a, py::handle b, bool mask_background, py::object background) {
    CompareOptions o;
    o.mask_background = mask_background;
    if (!background.is_none()) {
      const Rgba c = color_arg(background, "background");
      for (int k = 0; k < 3; ++k) o.background[k] = c[k];
    }
    CompareResult r;
    if (py::isinstance<py::str>(a) ||
        py::isinstance(a, py::module_::import("pathlib").attr("Path"))) {
      const auto pa = a.cast<std::filesystem::path>(), pb = b.cast<std::filesystem::path>();
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
  });

  // ---- Writers ----
  m.def("write_vertex_colors", [](const std::filesystem::path& path, const LoadedMesh& mesh,
                                  py::handle colors, bool ascii, py::handle up) {
    Array<float> c = rows<float>(colors, "colors", 0);
    if (c.shape(1) != 3 && c.shape(1) != 4) usage("colors must have shape (n, 3) or (n, 4)");
    std::vector<Rgba> rgba(c.shape(0));
    for (py::ssize_t i = 0; i < c.shape(0); ++i) {
      const float* p = c.data() + c.shape(1) * i;
      rgba[i] = {p[0], p[1], p[2], c.shape(1) == 4 ? p[3] : 1.0f};
    }
    WriteOptions o;
    o.ascii = ascii;
    o.up = vec3_arg(up, "up");
    py::gil_scoped_release release;
    check(write_vertex_colors(path, mesh.mesh, rgba, o));
  });
  m.def("write_atlas", [](const std::filesystem::path& path, const Atlas& atlas,
                          const std::string& format, py::handle up) {
    WriteOptions o;
    o.up = vec3_arg(up, "up");
    o.format = choice<AtlasFormat>(
        format, "format",
        {{"png8", AtlasFormat::kPng8}, {"png16", AtlasFormat::kPng16}, {"exr", AtlasFormat::kExr}});
    check(validate_write(path, o, /*atlas=*/true));
    py::gil_scoped_release release;
    check(write_atlas(path, atlas, o));
  });
  m.def("atlas_files", [](const std::filesystem::path& path, const std::string& format) {
    WriteOptions o;
    o.format = format == "exr" ? AtlasFormat::kExr : AtlasFormat::kPng8;
    std::vector<std::string> out;
    for (const auto& p : atlas_files(path, o)) out.push_back(p.string());
    return out;
  });
  m.def("write_image", [](const std::filesystem::path& path, py::handle image, int bits,
                          int compression) {
    ImageWriteOptions o;
    if (compression < 0 || compression > 9) usage("compression must be in 0..9");
    o.png_compression = compression;
    o.bit_depth = choice<ImageBitDepth>(
        std::to_string(bits), "bits",
        {{"8", ImageBitDepth::k8}, {"16", ImageBitDepth::k16}, {"32", ImageBitDepth::kFloat}});
    ImageArg img = image_arg(image, "image");
    py::gil_scoped_release release;
    check(write_image(path, img.view, o));
  });
}
