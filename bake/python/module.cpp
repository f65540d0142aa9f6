// The C++ half of the Python module `texbake` (SPEC section 11): pybind11
// bindings of texbake/texbake.h, imported as texbake._texbake. The Python
// half (bake/python/texbake/__init__.py) gives the functions their keyword
// signatures, defaults (the job option table's, job_options(); render's and
// compare's from their option structs, render_defaults()) and docstrings; the bindings take the
// option values as the CLI spells them ("area", "first", ...) and check them with the library's
// checks (bake/python/common.h has the conventions).
//
// One file per concept: bind_mesh.cpp (Mesh, read_mesh, read_image),
// bind_proxy.cpp (Proxy, fit, map), bind_bake.cpp (the proxy bakes, Atlas), bind_photos.cpp
// (photos, camera proxies, layers, cameras check), bind_render.cpp (render, compare),
// bind_writers.cpp (writers), bind_jobs.cpp (the option table, run_job, run_batch).
#include "bake/python/common.h"

PYBIND11_MODULE(_texbake, m) {
  namespace tp = texbake::python;
  m.doc() = "texbake's C++ bindings; use the package `texbake`.";
  tp::register_errors(m);
  m.def("version", &texbake::version);
  tp::bind_mesh(m);
  tp::bind_proxy(m);
  tp::bind_bake(m);
  tp::bind_photos(m);
  tp::bind_render(m);
  tp::bind_writers(m);
  tp::bind_jobs(m);
}
