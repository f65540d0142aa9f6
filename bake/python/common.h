// What every file of the Python module's C++ half shares (SPEC section 11):
// the error mapping, running without the GIL, numpy arrays in and out, and
// the option arguments checked by the library's own checks (texbake.h,
// "Option values"), so a bad argument raises ValueError with the message
// the command line prints for the same flag.
//
// Conventions of every binding (bind_*.cpp):
//  - Arrays in: numpy arrays of any numeric dtype convertible to the C++
//    type; a wrong shape raises ValueError naming the argument. An image
//    that is already (h, w, 4) float32 and C-contiguous is read in place
//    (no copy); any other image is converted once. Mesh arrays are always
//    converted (MeshData holds float32 positions and uint32 indices).
//  - Arrays out own their data through a capsule (no copy of images).
//  - Errors: every Expected of the API goes through check() (the one place
//    that maps ErrorCategory to a Python exception): kUsage -> ValueError,
//    kInput -> OSError, kInternal -> RuntimeError, kCancelled ->
//    texbake.Cancelled, with the API's message (the CLI's). Arguments of a
//    wrong type or value raise ValueError too (never TypeError or a cast
//    error), naming the CLI flag.
//  - Long calls release the GIL; the progress callback re-acquires it.
//    An exception raised by the callback cancels the call and is re-raised.
#pragma once

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "texbake/report.h"
#include "texbake/texbake.h"

namespace texbake::python {

namespace py = pybind11;

// ---- Errors ---------------------------------------------------------------

struct ApiError {
  Error error;
};

// Registers the translation of ApiError (see the file comment) and
// texbake.Cancelled on `m`.
void register_errors(py::module_& m);

[[noreturn]] void raise(const Error& error);
[[noreturn]] void usage(const std::string& message);

template <class T>
T check(Expected<T>&& result) {
  if (!result) raise(result.error());
  return std::move(*result);
}
inline void check(const Status& status) {
  if (!status) raise(status.error());
}

// ---- Running without the GIL ----------------------------------------------

// RunOptions whose progress calls the Python callable (with the GIL) and
// keeps an exception it raises for rethrow() after the call. `threads`:
// 0 (all cores) .. kMaxThreads.
struct PyRun {
  RunOptions run;
  py::object callback;
  std::optional<py::error_already_set> raised;

  PyRun(const py::handle& threads, py::object progress);
  // Re-raises the callback's exception, if any (call with the GIL held).
  void rethrow();
};

// Runs work(RunOptions) without the GIL, then re-raises the callback's
// exception or the work's error.
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
Array<T> rows(const py::handle& a, const char* name, py::ssize_t cols);
extern template Array<double> rows<double>(const py::handle&, const char*, py::ssize_t);
extern template Array<float> rows<float>(const py::handle&, const char*, py::ssize_t);
extern template Array<int64_t> rows<int64_t>(const py::handle&, const char*, py::ssize_t);

// Every value of `a` (n rows of a.shape(1)) finite and within float's
// range: ValueError "NAME: row I is not finite (VALUE)" / "... is beyond
// float range (VALUE)" for the first that is not.
void check_float_rows(const Array<double>& a, const char* name);

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
py::array_t<int64_t> index_array(const std::vector<uint32_t>& v, py::ssize_t cols = 0);

// Per-vertex colours as an (n, 4) float32 array.
py::array_t<float> colors_array(const std::vector<Rgba>& colors);

// An image as an (h, w, 4) float32 array owning its pixels.
py::array_t<float> image_array(Image&& image);

// ---- Images in ------------------------------------------------------------

// An image argument: (h, w), (h, w, 1..4) numbers; uint8 / uint16 are
// scaled to [0, 1] as read_image does; NaN and infinite values are read as
// 0 with a RuntimeWarning naming the argument and the count (the CLI's
// warning for a texture file). Keeps `keep` alive for the view.
struct ImageArg {
  ImageView view;
  Array<float> keep;  // the array viewed (float32 RGBA) ...
  Image converted;    // ... or the conversion
};

// An image array with its colour space (its `colorspace` attribute:
// texbake.ImageArray; "srgb" for a plain array).
ImageArg image_arg(const py::handle& obj, const char* name);

// The image of a bake: image_arg, or a file path (str or os.PathLike) read
// as `texbake bake --texture` reads it (texture_read_options with
// `cache_mb`; ValueError for --filter ewa past the budget).
ImageArg bake_image_arg(const py::handle& obj, std::size_t cache_mb, const VertexBakeOptions& o);

// A path argument (str or os.PathLike); ValueError naming `name` otherwise.
std::filesystem::path path_arg(const py::handle& obj, const char* name);
bool is_path(const py::handle& obj);

// ---- Option values (the CLI's checks and messages) -------------------------

// An integer (Python int or numpy integer); ValueError "FLAG: 'X' is not an
// integer" otherwise, or out of int's range.
long long int_arg(const py::handle& obj, const char* flag);

// An enum option by its CLI name (texbake::parse_choice).
template <class E>
E choice_arg(const py::handle& obj, const char* flag) {
  // Not a str: its repr, which names no value ("5", "None").
  const std::string text = py::isinstance<py::str>(obj) ? py::str(obj) : py::repr(obj);
  return check(parse_choice<E>(text, flag));
}

// A keyword among `keywords` (returned) or a colour (3 or 4 numbers in
// [0, 1], into `color`; returns ""). ValueError with the CLI's messages.
std::string keyword_or_color(const py::handle& obj, const char* flag,
                             std::initializer_list<const char*> keywords, Rgba& color);

// A colour (3 numbers; 4 with `alpha`) in [0, 1]: color_from_components.
Rgba color_arg(const py::handle& obj, const char* flag, bool alpha = true);

// 3 numbers (any sequence); ValueError naming `name` otherwise.
Vec3 vec3_arg(const py::handle& h, const std::string& name);

// --padding: None (the default), "inf" or a texel count (parse_padding).
int padding_arg(const py::handle& obj);

// --cache-mb: check_cache_mb.
std::size_t cache_mb_arg(const py::handle& obj);

// The shading options of the proxy bakes (--filter ... --wrap).
VertexBakeOptions shading_options(const py::handle& filter, const py::handle& samples,
                                  const py::handle& visibility, const py::handle& occluded,
                                  const py::handle& outside, bool linear, const py::handle& wrap);

// The atlas options (--uv, --size, --samples, --padding) over `shading`.
AtlasOptions atlas_options(const py::handle& uv, const py::handle& size, const py::handle& samples,
                           const py::handle& padding, const VertexBakeOptions& shading);

// ---- Results --------------------------------------------------------------

// counts (every counter by its Stats name), timings, warnings: render's.
py::dict stats_dict(const Stats& s);
// A bake's stats: stats_dict with the report's "counts" and "timings" (the
// names `texbake bake --report` gives the figures: texbake/report.h
// counts_json, stage_timings_json of `layers`, and the call's "total").
py::dict bake_stats(const Stats& s, ReportSource source, bool atlas,
                    const std::vector<LayerStats>& layers = {});
// An atlas bake's result: the Atlas, whose `stats` are bake_stats, with
// "atlas" the report's atlas object (its size, samples_per_texel, padding,
// counts, uv, uv_check or charts ...: atlas_json for `options` at the
// image's size; its timings are the stats') and "photos_skipped" when
// `skipped` is given.
py::object atlas_result(Atlas&& atlas, ReportSource source, const AtlasBakeOptions& options,
                        const std::vector<SkippedPhoto>* skipped = nullptr,
                        const std::vector<LayerStats>& layers = {});
py::list cameras_list(const std::vector<PhotoCameraStats>& cameras);
// The photos a bake left out (cannot be read): image, path, reason.
py::list skipped_list(const std::vector<SkippedPhoto>& skipped);
// Per layer: texture or cameras, in_domain, visible, blended, mean_alpha,
// seconds, and for a cameras layer photos_skipped (the report's layers).
py::list layers_list(const std::vector<LayerStats>& layers);

// ---- Shared types -----------------------------------------------------------

struct PyProxy {
  Proxy proxy;
  std::vector<std::string> fitted;  // keys filled by fit()
};

// The proxy argument: a texbake.Proxy's native object; ValueError otherwise.
const PyProxy& proxy_arg(const py::handle& obj, const char* name = "proxy");

// ---- The module's parts -------------------------------------------------------

void bind_mesh(py::module_& m);     // Mesh, read_mesh, read_image
void bind_proxy(py::module_& m);    // Proxy, make_proxy, fit, map
void bind_bake(py::module_& m);     // Atlas, bake_vertex, bake_atlas
void bind_photos(py::module_& m);   // photo, camera and layers bakes, check_cameras
void bind_render(py::module_& m);   // render, compare, render_defaults
void bind_writers(py::module_& m);  // write_vertex_colors, write_atlas, write_image
void bind_jobs(py::module_& m);     // job_options, run_job, run_batch

}  // namespace texbake::python
