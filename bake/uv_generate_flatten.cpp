// Chart flattening with CGAL's LSCM (see bake/uv_generate_internal.h). This is
// the only translation unit of the UV generator that includes CGAL.
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/Surface_mesh_parameterization/Error_code.h>
#include <CGAL/Surface_mesh_parameterization/LSCM_parameterizer_3.h>

#include <cmath>

#include "bake/uv_generate_internal.h"

namespace texbake::uv_detail {
namespace {

using Kernel = CGAL::Simple_cartesian<double>;
using SurfaceMesh = CGAL::Surface_mesh<Kernel::Point_3>;
using VertexIndex = SurfaceMesh::Vertex_index;
using HalfedgeIndex = SurfaceMesh::Halfedge_index;
namespace SMP = CGAL::Surface_mesh_parameterization;

// Border parameterizer for LSCM: locks the two vertices the caller chose and
// seeds every vertex with the caller's initial (u, v). CGAL's
// Two_vertices_parameterizer_3 would pick its own pair and leave the other
// vertices at (0, 0), a poor start for the iterative solver.
class FixedPairBorder {
 public:
  explicit FixedPairBorder(const ChartMesh* chart) : chart_(chart) {}

  template <class UvMap, class IndexMap, class ParameterizedMap>
  SMP::Error_code parameterize(const SurfaceMesh& mesh, HalfedgeIndex, UvMap uv_map,
                               IndexMap, ParameterizedMap parameterized_map) {
    for (VertexIndex v : mesh.vertices()) {
      const uint32_t i = static_cast<uint32_t>(v);
      put(uv_map, v, Kernel::Point_2(chart_->initial_uv[2 * i], chart_->initial_uv[2 * i + 1]));
      put(parameterized_map, v, i == chart_->fixed0 || i == chart_->fixed1);
    }
    return SMP::OK;
  }

 private:
  const ChartMesh* chart_;
};

using Lscm = SMP::LSCM_parameterizer_3<SurfaceMesh, FixedPairBorder>;

}  // namespace

FlattenStatus flatten_lscm(const ChartMesh& chart, std::vector<double>& uv) {
  const std::size_t n = chart.positions.size() / 3;
  SurfaceMesh mesh;
  mesh.reserve(n, chart.faces.size() * 3 / 2 + 3, chart.faces.size());
  for (std::size_t i = 0; i < n; ++i) {
    mesh.add_vertex(Kernel::Point_3(chart.positions[3 * i], chart.positions[3 * i + 1],
                                    chart.positions[3 * i + 2]));
  }
  for (const auto& f : chart.faces) {
    if (mesh.add_face(VertexIndex(f[0]), VertexIndex(f[1]), VertexIndex(f[2])) ==
        SurfaceMesh::null_face()) {
      return FlattenStatus::kNotDisk;
    }
  }
  // A topological disk: Euler characteristic 1 and exactly one border cycle
  // (the caller guarantees connectivity).
  const long euler = static_cast<long>(mesh.number_of_vertices()) -
                     static_cast<long>(mesh.number_of_edges()) +
                     static_cast<long>(mesh.number_of_faces());
  if (euler != 1) return FlattenStatus::kNotDisk;
  HalfedgeIndex border;
  std::size_t border_cycles = 0;
  auto visited = mesh.add_property_map<HalfedgeIndex, bool>("h:visited", false).first;
  for (HalfedgeIndex h : mesh.halfedges()) {
    if (!mesh.is_border(h) || visited[h]) continue;
    ++border_cycles;
    border = h;
    HalfedgeIndex g = h;
    do {
      visited[g] = true;
      g = mesh.next(g);
    } while (g != h);
  }
  if (border_cycles != 1) return FlattenStatus::kNotDisk;

  auto uv_map = mesh.add_property_map<VertexIndex, Kernel::Point_2>("v:uv").first;
  auto index_map = mesh.add_property_map<VertexIndex, int>("v:index").first;
  auto parameterized_map = mesh.add_property_map<VertexIndex, bool>("v:fixed", false).first;
  for (VertexIndex v : mesh.vertices()) index_map[v] = static_cast<int>(static_cast<uint32_t>(v));

  Lscm lscm{FixedPairBorder(&chart)};
  if (lscm.parameterize(mesh, border, uv_map, index_map, parameterized_map) != SMP::OK) {
    return FlattenStatus::kSolveFailed;
  }
  uv.resize(2 * n);
  for (VertexIndex v : mesh.vertices()) {
    const uint32_t i = static_cast<uint32_t>(v);
    const Kernel::Point_2& p = uv_map[v];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y())) return FlattenStatus::kSolveFailed;
    uv[2 * i] = p.x();
    uv[2 * i + 1] = p.y();
  }
  return FlattenStatus::kOk;
}

}  // namespace texbake::uv_detail
