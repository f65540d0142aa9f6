// A latitude-longitude ("UV") sphere of radius 1 around the origin, built in
// code for the atlas tests.
#pragma once

#include <cmath>
#include <numbers>

#include "mesh_io/mesh_data.h"

namespace texbake::test {

// `rings` latitude bands (R >= 2), `segments` columns. Vertex 0 is the north
// pole (0, 0, 1), vertex 1 the south pole; ring i (1 .. R-1, polar angle
// pi i / R) has `segments` vertices at azimuth 2 pi (j + phase) / segments.
// Triangles are counter-clockwise seen from outside; each face is a triangle.
// No UVs.
inline MeshData make_uv_sphere(int rings, int segments, double phase) {
  MeshData m;
  m.positions.push_back({0, 0, 1});
  m.positions.push_back({0, 0, -1});
  for (int i = 1; i < rings; ++i) {
    const double theta = std::numbers::pi * i / rings;
    for (int j = 0; j < segments; ++j) {
      const double phi = 2 * std::numbers::pi * (j + phase) / segments;
      m.positions.push_back({float(std::sin(theta) * std::cos(phi)),
                             float(std::sin(theta) * std::sin(phi)), float(std::cos(theta))});
    }
  }
  auto ring = [&](int i, int j) {
    return static_cast<uint32_t>(2 + (i - 1) * segments + ((j % segments) + segments) % segments);
  };
  auto add = [&](uint32_t a, uint32_t b, uint32_t c) {
    const uint32_t base = static_cast<uint32_t>(m.face_vertices.size());
    m.face_vertices.insert(m.face_vertices.end(), {a, b, c});
    if (m.face_offsets.empty()) m.face_offsets.push_back(0);
    m.face_offsets.push_back(base + 3);
    m.triangle_face.push_back(static_cast<uint32_t>(m.triangles.size()));
    m.triangles.push_back({a, b, c});
    m.triangle_corners.push_back({base, base + 1, base + 2});
  };
  for (int j = 0; j < segments; ++j) add(0, ring(1, j), ring(1, j + 1));
  for (int i = 1; i + 1 < rings; ++i) {
    for (int j = 0; j < segments; ++j) {
      add(ring(i, j), ring(i + 1, j), ring(i + 1, j + 1));
      add(ring(i, j), ring(i + 1, j + 1), ring(i, j + 1));
    }
  }
  for (int j = 0; j < segments; ++j) add(1, ring(rings - 1, j + 1), ring(rings - 1, j));
  return m;
}

}  // namespace texbake::test
