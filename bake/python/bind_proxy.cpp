// texbake.Proxy's native half: make_proxy, proxy_from_json, read_proxy_file,
// fit and map.
#include "bake/python/common.h"

namespace texbake::python {

namespace {

// One given value of `field` (kind `kind`) into spec.values.
void spec_value(ProxySpec& spec, const ParamField& field, const std::string& key,
                const py::handle& value) {
  const std::string kind = to_string(spec.kind);
  switch (field.type) {
    case ParamType::kNumber:
      try {
        spec.values[key] = value.cast<double>();
      } catch (const py::cast_error&) {
        usage(kind + ": " + key + " must be a number");
      }
      break;
    case ParamType::kVec3:
      spec.values[key] = vec3_arg(value, kind + ": " + key);
      break;
    case ParamType::kCorners: {
      if (!py::isinstance<py::sequence>(value) || py::len(value) != 4) {
        usage(kind + ": corners must be 4 points");
      }
      std::array<Vec3, 4> corners;
      const py::sequence seq = value.cast<py::sequence>();
      for (int i = 0; i < 4; ++i) corners[i] = vec3_arg(seq[i], kind + ": corners");
      spec.values[key] = corners;
      break;
    }
  }
}

// A ProxySpec from a kind and a dict of given values by JSON key.
ProxySpec spec_from_dict(const std::string& kind_name, const py::dict& values,
                         const py::object& up) {
  std::optional<ProxyKind> kind = parse_proxy_kind(kind_name);
  if (!kind) {
    usage("unknown proxy kind '" + kind_name +
          "' (expected sphere, cylinder, cone, disk, quad or plane)");
  }
  ProxySpec spec{*kind, {}, std::nullopt};
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
    spec_value(spec, *field, key, value);
  }
  if (!up.is_none()) spec.up = vec3_arg(up, "up");
  return spec;
}

py::tuple map_points(const PyProxy& proxy, py::handle points) {
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
}

}  // namespace

void bind_proxy(py::module_& m) {
  py::class_<PyProxy>(m, "Proxy")
      .def_property_readonly("kind", [](const PyProxy& p) { return to_string(kind_of(p.proxy)); })
      .def_property_readonly("fitted", [](const PyProxy& p) { return p.fitted; })
      .def("to_json", [](const PyProxy& p) { return proxy_to_json(p.proxy); })
      .def("write", [](const PyProxy& p, py::handle path) {
        check(write_proxy_file(path_arg(path, "path"), p.proxy));
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
  m.def("read_proxy_file", [](py::handle path) {
    return PyProxy{check(read_proxy_file(path_arg(path, "path"))), {}};
  });
  m.def("fit", [](const LoadedMesh& mesh, const std::string& kind, const py::dict& given,
                  const py::object& up, py::handle threads) {
    const ProxySpec spec = spec_from_dict(kind, given, up);
    check(check_triangles(mesh.mesh));
    PyRun run(threads, py::none());
    CompletedProxy c = run_released<CompletedProxy>(
        run, [&](const RunOptions& r) { return complete_proxy(spec, mesh.mesh, r); });
    return PyProxy{std::move(c.proxy), std::move(c.fitted)};
  });
  m.def("map",
        [](py::handle proxy, py::handle points) { return map_points(proxy_arg(proxy), points); });
}

}  // namespace texbake::python
