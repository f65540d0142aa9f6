// texbake info MESH [--json]: counts, bounds, attributes present and problems
// found (SPEC section 5). A file that cannot be read is exit 1 with
// "texbake: error: ..." naming it.
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>

#include "bake/cli/commands.h"
#include "mesh_io/mesh_texture.h"
#include "texbake/texbake.h"

namespace texbake::cli {

namespace {

struct InfoOptions {
  std::string mesh;
  bool json = false;
};

int run_info(const InfoOptions& opt) {
  Expected<LoadedMesh> loaded = read_mesh(opt.mesh);
  if (!loaded) return report_error(loaded.error());
  const MeshData& m = loaded->mesh;
  const MeshIssues& is = loaded->issues;
  std::array<double, 3> lo{}, hi{};
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const Float3& p : m.positions) {
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], c[k]);
      hi[k] = std::max(hi[k], c[k]);
    }
  }
  const bool normals = !m.corner_normal.empty();
  if (opt.json) {
    nlohmann::json j;
    j["file"] = opt.mesh;
    j["vertices"] = m.vertex_count();
    j["faces"] = m.face_count();
    j["triangles"] = m.triangles.size();
    j["bounds"] = {{"min", lo}, {"max", hi}};
    j["attributes"] = {{"uv", m.has_uvs()},
                       {"normals", normals},
                       {"vertex_colors", m.has_vertex_colors()},
                       {"texture", m.has_texture() ? nlohmann::json(mesh_texture_label(m))
                                                   : nlohmann::json(nullptr)}};
    if (m.base_color_factor) j["attributes"]["base_color_factor"] = *m.base_color_factor;
    j["problems"] = {{"degenerate_triangles", is.degenerate_triangles},
                     {"unreferenced_vertices", is.unreferenced_vertices},
                     {"non_manifold_edges", is.non_manifold_edges},
                     {"other_material_primitives", is.other_material_primitives}};
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  auto yes_no = [](bool b) { return b ? "yes" : "no"; };
  std::printf("file: %s\n", opt.mesh.c_str());
  std::printf("vertices: %zu\nfaces: %zu\ntriangles: %zu\n", m.vertex_count(), m.face_count(),
              m.triangles.size());
  std::printf("bounds: min %.9g %.9g %.9g  max %.9g %.9g %.9g\n", lo[0], lo[1], lo[2], hi[0], hi[1],
              hi[2]);
  std::printf("uv: %s\nnormals: %s\nvertex colors: %s\ntexture: %s\n", yes_no(m.has_uvs()),
              yes_no(normals), yes_no(m.has_vertex_colors()), mesh_texture_label(m).c_str());
  if (m.base_color_factor) {
    const auto& f = *m.base_color_factor;
    std::printf("base color factor: %.9g %.9g %.9g %.9g (linear)\n", f[0], f[1], f[2], f[3]);
  }
  std::printf("degenerate triangles: %zu\nunreferenced vertices: %zu\nnon-manifold edges: %zu\n",
              is.degenerate_triangles, is.unreferenced_vertices, is.non_manifold_edges);
  if (is.other_material_primitives > 0) {
    std::printf("primitives with another material than the first: %zu\n",
                is.other_material_primitives);
  }
  std::fflush(stdout);
  return 0;
}

}  // namespace

RunFunction add_info_command(CLI::App& app) {
  auto opt = std::make_shared<InfoOptions>();
  CLI::App* sub = app.add_subcommand(
      "info", "Print a mesh's counts, bounds, attributes present and problems found");
  sub->add_option("mesh", opt->mesh, "Mesh file (.obj, .ply, .off, .stl, .glb, .gltf)")->required();
  sub->add_flag("--json", opt->json, "Print one JSON object instead of text");
  return [opt] { return run_info(*opt); };
}

}  // namespace texbake::cli
