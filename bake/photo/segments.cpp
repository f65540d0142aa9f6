#include "bake/photo/segments.h"

#include <algorithm>

namespace texbake {

namespace {

template <class PointOf>
void trace_segments(const EmbreeScene& scene, double offset, std::size_t m, PointOf point_of,
                    Vec3 centre, SegmentScratch& scratch, uint8_t* occluded) {
  if (m == 0) return;
  scratch.rays.resize(m);
  scratch.tnear.resize(m);
  scratch.tfar.resize(m);
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3 p = point_of(i);
    const Vec3 segment = centre - p;
    const double relative = offset / length(segment);
    scratch.rays.set(i, p, segment);
    scratch.tnear[i] = static_cast<float>(relative);
    scratch.tfar[i] = static_cast<float>(std::max(relative, 1 - relative));
  }
  RayBatch batch = scratch.rays.batch(m);
  batch.tnear = scratch.tnear.data();
  batch.tfar = scratch.tfar.data();
  scene.occluded(batch, occluded);
}

}  // namespace

void occluded_segments(const EmbreeScene& scene, double offset, const MeshData& mesh,
                       std::span<const uint32_t> vertices, Vec3 centre, SegmentScratch& scratch,
                       uint8_t* occluded) {
  trace_segments(
      scene, offset, vertices.size(),
      [&](std::size_t i) {
        const Float3 q = mesh.positions[vertices[i]];
        return Vec3{q.x, q.y, q.z};
      },
      centre, scratch, occluded);
}

void occluded_segments(const EmbreeScene& scene, double offset, std::span<const Vec3> points,
                       Vec3 centre, SegmentScratch& scratch, uint8_t* occluded) {
  trace_segments(
      scene, offset, points.size(), [&](std::size_t i) { return points[i]; }, centre, scratch,
      occluded);
}

}  // namespace texbake
