// Small meshes built in code for the bake tests (no files, no readers).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "mesh_io/mesh_data.h"

namespace texbake::test {

// Sets the polygon arrays of `mesh` from its triangles (one face per triangle).
inline void faces_from_triangles(MeshData& mesh) {
  mesh.face_offsets.assign(1, 0);
  mesh.face_vertices.clear();
  mesh.triangle_corners.clear();
  mesh.triangle_face.clear();
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uint32_t c = static_cast<uint32_t>(mesh.face_vertices.size());
    for (uint32_t v : mesh.triangles[t]) mesh.face_vertices.push_back(v);
    mesh.face_offsets.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
    mesh.triangle_corners.push_back({c, c + 1, c + 2});
    mesh.triangle_face.push_back(static_cast<uint32_t>(t));
  }
}

// Appends a (nx+1) x (ny+1) vertex grid whose vertex (i, j) is at(i / nx, j / ny),
// each cell split by its (i,j)-(i+1,j+1) diagonal into two counter-clockwise
// triangles (seen with s to the right and t up). Returns the first vertex index;
// vertex (i, j) is first + j * (nx + 1) + i.
inline uint32_t append_grid(MeshData& mesh, int nx, int ny,
                            const std::function<Float3(double s, double t)>& at) {
  const uint32_t first = static_cast<uint32_t>(mesh.positions.size());
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) mesh.positions.push_back(at(double(i) / nx, double(j) / ny));
  }
  auto id = [&](int i, int j) { return first + static_cast<uint32_t>(j * (nx + 1) + i); };
  for (int j = 0; j < ny; ++j) {
    for (int i = 0; i < nx; ++i) {
      mesh.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      mesh.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  }
  return first;
}

// One round of 1-to-4 midpoint subdivision of mesh.triangles (positions only;
// every edge's midpoint is shared by its two triangles), one face per triangle.
inline MeshData subdivide(const MeshData& in) {
  MeshData out;
  out.positions = in.positions;
  std::unordered_map<uint64_t, uint32_t> midpoints;
  midpoints.reserve(in.triangles.size() * 2);
  auto midpoint = [&](uint32_t a, uint32_t b) {
    const uint64_t key = (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    auto [it, fresh] = midpoints.try_emplace(key, static_cast<uint32_t>(out.positions.size()));
    if (fresh) {
      const Float3 p = in.positions[a], q = in.positions[b];
      out.positions.push_back({(p.x + q.x) / 2, (p.y + q.y) / 2, (p.z + q.z) / 2});
    }
    return it->second;
  };
  out.triangles.reserve(in.triangles.size() * 4);
  for (const auto& t : in.triangles) {
    const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    out.triangles.push_back({t[0], ab, ca});
    out.triangles.push_back({ab, t[1], bc});
    out.triangles.push_back({ca, bc, t[2]});
    out.triangles.push_back({ab, bc, ca});
  }
  faces_from_triangles(out);
  return out;
}

// Appends an axis-aligned box [lo, hi] as 8 vertices and 12 outward triangles.
inline uint32_t append_box(MeshData& mesh, Float3 lo, Float3 hi) {
  const uint32_t f = static_cast<uint32_t>(mesh.positions.size());
  for (int k = 0; k < 8; ++k) {
    mesh.positions.push_back({(k & 1) ? hi.x : lo.x, (k & 2) ? hi.y : lo.y, (k & 4) ? hi.z : lo.z});
  }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    mesh.triangles.push_back({f + q[0], f + q[1], f + q[2]});
    mesh.triangles.push_back({f + q[0], f + q[2], f + q[3]});
  }
  return f;
}

// A closed UV sphere of radius r around c: `rings` latitude bands, `segments`
// longitudes, poles as single vertices; outward counter-clockwise triangles.
inline MeshData uv_sphere(Float3 c, double r, int rings, int segments) {
  MeshData mesh;
  mesh.positions.push_back({c.x, c.y, static_cast<float>(c.z + r)});
  for (int i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * std::numbers::pi * j / segments;
      mesh.positions.push_back({static_cast<float>(c.x + r * std::sin(theta) * std::cos(phi)),
                                static_cast<float>(c.y + r * std::sin(theta) * std::sin(phi)),
                                static_cast<float>(c.z + r * std::cos(theta))});
    }
  }
  const uint32_t south = static_cast<uint32_t>(mesh.positions.size());
  mesh.positions.push_back({c.x, c.y, static_cast<float>(c.z - r)});
  auto ring = [&](int i, int j) {
    return 1u + static_cast<uint32_t>((i - 1) * segments + (j % segments));
  };
  for (int j = 0; j < segments; ++j) mesh.triangles.push_back({0, ring(1, j), ring(1, j + 1)});
  for (int i = 1; i + 1 < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
      mesh.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
    }
  }
  for (int j = 0; j < segments; ++j) {
    mesh.triangles.push_back({ring(rings - 1, j), south, ring(rings - 1, j + 1)});
  }
  faces_from_triangles(mesh);
  return mesh;
}

}  // namespace texbake::test
