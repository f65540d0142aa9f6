// Visibility of mesh vertices from a camera (SPEC section 9): the segment
// from the vertex P to the camera's centre C must hit no triangle, not the
// ray to infinity of the analytic proxies. The segment is traced as the
// ray P + t (C - P), t in [e, 1 - e] with e = offset / |C - P| (the offset
// of bake/trace/visibility.h at both ends: P's own triangles, and a centre
// that lies on the mesh).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bake/trace/embree_scene.h"
#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// Reusable buffers of one thread's batches (allocates only when growing).
struct SegmentScratch {
  RayArrays rays;
  std::vector<float> tnear, tfar;
};

// occluded[i] = 1 when the segment from mesh.positions[vertices[i]] to
// `centre` is blocked, else 0. offset: visibility_offset(scene).
void occluded_segments(const EmbreeScene& scene, double offset, const MeshData& mesh,
                       std::span<const uint32_t> vertices, Vec3 centre, SegmentScratch& scratch,
                       uint8_t* occluded);

// The same for arbitrary surface points (atlas samples): occluded[i] = 1
// when the segment from points[i] to `centre` is blocked.
void occluded_segments(const EmbreeScene& scene, double offset, std::span<const Vec3> points,
                       Vec3 centre, SegmentScratch& scratch, uint8_t* occluded);

}  // namespace texbake
