// texbake.Mesh (from arrays or read_mesh) and read_image.
#include <cmath>

#include "bake/python/common.h"

namespace texbake::python {

namespace {

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

// A per-corner table (uvs + face_uvs, normals + face_normals) into `out`
// (Float2 or Float3 rows) and `corner`; `faces` gives the shape.
template <class Row>
void corner_table(const py::handle& table, const py::handle& index, const char* tname,
                  const char* iname, const Array<int64_t>& faces, std::vector<Row>& out,
                  std::vector<uint32_t>& corner) {
  if (table.is_none() && index.is_none()) return;
  if (table.is_none() || index.is_none()) {
    usage(std::string(tname) + " and " + iname + " go together");
  }
  constexpr py::ssize_t kCols = sizeof(Row) / sizeof(float);
  Array<double> t = rows<double>(table, tname, kCols);
  check_float_rows(t, tname);
  Array<int64_t> c = rows<int64_t>(index, iname, 0);
  if (c.shape(0) != faces.shape(0) || c.shape(1) != faces.shape(1)) {
    usage(std::string(iname) + " must have the shape of faces");
  }
  check_indices(c, iname, t.shape(0));
  out.resize(t.shape(0));
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    float* dst = reinterpret_cast<float*>(&out[i]);
    for (py::ssize_t k = 0; k < kCols; ++k) dst[k] = static_cast<float>(t.data()[kCols * i + k]);
  }
  corner.assign(c.data(), c.data() + c.size());
}

// colors (n, 3) or (n, 4), n the vertex count, finite.
void vertex_colors(const py::handle& colors, std::size_t n, MeshData& m) {
  if (colors.is_none()) return;
  Array<double> c = rows<double>(colors, "colors", 0);
  if (static_cast<std::size_t>(c.shape(0)) != n || (c.shape(1) != 3 && c.shape(1) != 4)) {
    usage("colors must have shape (n, 3) or (n, 4) with n = the vertex count");
  }
  check_float_rows(c, "colors");
  m.vertex_colors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = c.data() + c.shape(1) * i;
    m.vertex_colors[i] = {static_cast<float>(p[0]), static_cast<float>(p[1]),
                          static_cast<float>(p[2]),
                          c.shape(1) == 4 ? static_cast<float>(p[3]) : 1.0f};
  }
}

// A mesh from arrays (Mesh(vertices, faces, ...) in Python), not yet
// triangulated. Faces are (m, k) polygons of k >= 3 corners; every value
// finite and within float's range (ValueError naming the array and row).
MeshData mesh_from_arrays(const py::handle& vertices, const py::handle& faces,
                          const py::handle& uvs, const py::handle& face_uvs,
                          const py::handle& colors, const py::handle& normals,
                          const py::handle& face_normals) {
  MeshData m;
  Array<double> v = rows<double>(vertices, "vertices", 3);
  check_float_rows(v, "vertices");
  Array<int64_t> f = rows<int64_t>(faces, "faces", 0);
  if (f.shape(1) < 3)
    usage("faces must have at least 3 corners per row (got " + std::to_string(f.shape(1)) + ")");
  const std::size_t n = v.shape(0), k = f.shape(1), nf = f.shape(0);
  m.positions.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double* p = v.data() + 3 * i;
    m.positions[i] = {static_cast<float>(p[0]), static_cast<float>(p[1]), static_cast<float>(p[2])};
  }
  check_indices(f, "faces", n);
  m.face_offsets.resize(nf + 1);
  for (std::size_t i = 0; i <= nf; ++i) m.face_offsets[i] = static_cast<uint32_t>(i * k);
  m.face_vertices.assign(f.data(), f.data() + f.size());
  corner_table(uvs, face_uvs, "uvs", "face_uvs", f, m.uvs, m.corner_uv);
  corner_table(normals, face_normals, "normals", "face_normals", f, m.normals, m.corner_normal);
  vertex_colors(colors, n, m);
  return m;
}

// faces as (m, k) when every face has k corners, else None.
py::object faces_array(const LoadedMesh& l) {
  const MeshData& d = l.mesh;
  const std::size_t nf = d.face_count();
  std::size_t k = nf ? d.face_offsets[1] - d.face_offsets[0] : 3;
  for (std::size_t f = 0; f < nf; ++f) {
    if (d.face_offsets[f + 1] - d.face_offsets[f] != k) k = 0;
  }
  if (k == 0) return py::none();
  return index_array(d.face_vertices, static_cast<py::ssize_t>(k));
}

py::array_t<int64_t> triangles_array(const LoadedMesh& l) {
  std::vector<uint32_t> t;
  for (const auto& tri : l.mesh.triangles) t.insert(t.end(), tri.begin(), tri.end());
  return index_array(t, 3);
}

py::dict issues_dict(const LoadedMesh& l) {
  py::dict d;
  d["degenerate_triangles"] = l.issues.degenerate_triangles;
  d["unreferenced_vertices"] = l.issues.unreferenced_vertices;
  d["non_manifold_edges"] = l.issues.non_manifold_edges;
  return d;
}

void bind_mesh_class(py::module_& m) {
  using L = const LoadedMesh&;
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
      .def_property_readonly("vertices", [](L l) { return table_array<double>(l.mesh.positions); })
      .def_property_readonly("faces", &faces_array)
      .def_property_readonly("triangles", &triangles_array)
      .def_property_readonly("face_offsets", [](L l) { return index_array(l.mesh.face_offsets); })
      .def_property_readonly("face_vertices", [](L l) { return index_array(l.mesh.face_vertices); })
      .def_property_readonly("uvs",
                             [](L l) {
                               return present(l.mesh.has_uvs(),
                                              [&] { return table_array<double>(l.mesh.uvs); });
                             })
      .def_property_readonly("corner_uvs",
                             [](L l) {
                               return present(l.mesh.has_uvs(),
                                              [&] { return index_array(l.mesh.corner_uv); });
                             })
      .def_property_readonly("normals",
                             [](L l) {
                               return present(!l.mesh.corner_normal.empty(),
                                              [&] { return table_array<double>(l.mesh.normals); });
                             })
      .def_property_readonly("corner_normals",
                             [](L l) {
                               return present(!l.mesh.corner_normal.empty(),
                                              [&] { return index_array(l.mesh.corner_normal); });
                             })
      .def_property_readonly("colors",
                             [](L l) {
                               return present(l.mesh.has_vertex_colors(), [&] {
                                 return table_array<float>(l.mesh.vertex_colors);
                               });
                             })
      .def_property_readonly("texture_path",
                             [](L l) -> py::object {
                               if (l.mesh.texture_path.empty()) return py::none();
                               return py::str(l.mesh.texture_path);
                             })
      .def_property_readonly("issues", &issues_dict);
}

}  // namespace

void bind_mesh(py::module_& m) {
  bind_mesh_class(m);
  m.def("read_mesh", [](py::handle path) {
    const std::filesystem::path p = path_arg(path, "path");
    py::gil_scoped_release release;
    return check(read_mesh(p));
  });
  m.def("read_image", [](py::handle path, py::handle colorspace) {
    const std::filesystem::path p = path_arg(path, "path");
    ImageReadOptions options;
    options.color_space = choice_arg<TextureColorSpace>(colorspace, "--texture-colorspace");
    Image image;
    {
      py::gil_scoped_release release;
      image = check(read_image(p, options));
    }
    const char* space = image.color_space == ColorSpace::kLinear ? "linear" : "srgb";
    return py::make_tuple(image_array(std::move(image)), space);
  });
}

}  // namespace texbake::python
