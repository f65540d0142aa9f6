#include "bake/vertex/vertex_share.h"

#include <algorithm>
#include <cmath>

#include "bake/shade/sample_pattern.h"

namespace texbake {

namespace {

Vec3 to_vec(const Float3& p) {
  return {p.x, p.y, p.z};
}

// Per-(vertex, sample) jitter in [0, 1), without generator state.
double hash01(uint64_t vertex, uint64_t index) {
  return unit_double(hash_pair(vertex, index));
}

}  // namespace

Adjacency build_adjacency(const MeshData& mesh) {
  Adjacency adj;
  adj.offsets.assign(mesh.positions.size() + 1, 0);
  for (const auto& tri : mesh.triangles) {
    for (uint32_t v : tri) ++adj.offsets[v + 1];
  }
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) adj.offsets[v + 1] += adj.offsets[v];
  adj.triangles.resize(adj.offsets.back());
  std::vector<uint32_t> cursor(adj.offsets.begin(), adj.offsets.end() - 1);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (uint32_t v : mesh.triangles[t]) adj.triangles[cursor[v]++] = static_cast<uint32_t>(t);
  }
  return adj;
}

void vertex_share(const MeshData& mesh, const Adjacency& adjacency, uint32_t v,
                  VertexShare& share) {
  share.first = adjacency.offsets[v];
  share.count = adjacency.offsets[v + 1] - share.first;
  share.total = 0;
  share.normal = Vec3{};
  share.cdf.resize(share.count);
  for (uint32_t j = 0; j < share.count; ++j) {
    const auto& tri = mesh.triangles[adjacency.triangles[share.first + j]];
    const Vec3 p0 = to_vec(mesh.positions[tri[0]]);
    const Vec3 e = cross(to_vec(mesh.positions[tri[1]]) - p0, to_vec(mesh.positions[tri[2]]) - p0);
    share.total += 0.5 * length(e);
    share.normal += e;
    share.cdf[j] = share.total;
  }
}

Vec3 share_point(const MeshData& mesh, const Adjacency& adjacency, uint32_t v,
                 const VertexShare& share, int s, int samples, uint32_t& j) {
  const Vec3 a = to_vec(mesh.positions[v]);
  // Rotation of the second coordinate per vertex (Cranley-Patterson).
  const double rotation = hash01(v, 0xFFFFFFFFull);
  // x: stratified (one sample per 1/n of the vertex's share, jittered),
  // y: a rotated van der Corput point, so (x, y) is a jittered Hammersley set.
  const double x = (s + hash01(v, static_cast<uint64_t>(s))) / samples;
  double y = radical_inverse2(static_cast<uint32_t>(s)) + rotation;
  if (y >= 1) y -= 1;
  // x runs over the cumulative area: find the triangle (x grows with s).
  const double target = x * share.total;
  while (j + 1 < share.count && share.cdf[j] <= target) ++j;
  const double before = j > 0 ? share.cdf[j - 1] : 0.0;
  const double local = std::clamp((target - before) / (share.cdf[j] - before), 0.0, 1.0);

  // The vertex's share of triangle (a, b, c) is the quad a, (a+b)/2,
  // centroid, (a+c)/2: two triangles of equal area, split on `local`.
  const auto& tri = mesh.triangles[adjacency.triangles[share.first + j]];
  const int at = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
  const Vec3 b = to_vec(mesh.positions[tri[(at + 1) % 3]]);
  const Vec3 c = to_vec(mesh.positions[tri[(at + 2) % 3]]);
  const Vec3 centroid = (a + b + c) / 3.0;
  const bool first_half = local < 0.5;
  const double r1 = first_half ? 2 * local : 2 * local - 1;
  const Vec3 q1 = first_half ? (a + b) * 0.5 : centroid;
  const Vec3 q2 = first_half ? centroid : (a + c) * 0.5;
  // Uniform point in triangle (a, q1, q2) (Shirley's square-to-triangle map).
  const double su = std::sqrt(r1);
  return a * (1 - su) + q1 * (su * (1 - y)) + q2 * (su * y);
}

}  // namespace texbake
