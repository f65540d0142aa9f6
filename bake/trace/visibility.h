// Visibility towards the projector (SPEC section 3): a point P is visible if
// the ray from P along d(P) (the proxy's MapResult::to_projector) to infinity
// hits no mesh triangle.
//
// Self-intersection: P lies on the mesh (a vertex, or a point inside one of
// its triangles), so the triangles through P are hit at t = 0 up to rounding.
// The ray therefore starts at P with tnear = visibility_offset(scene) along
// the unit direction d: every hit closer than that is ignored, and the offset
// scales with the mesh (a fraction of its bounding-box diagonal, never an
// absolute 0.001), with a floor from float precision for meshes far from the
// origin. An occluder closer to P than the offset is missed; at 1e-4 of the
// diagonal that is far below a texel of any practical projection.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bake/trace/embree_scene.h"
#include "mapping/vec.h"

namespace texbake {

// Ray start distance as a fraction of the bounding-box diagonal.
inline constexpr double kVisibilityOffsetRelative = 1e-4;
// Floor: this many float ulps of the largest |coordinate|, because positions
// are float32 in the scene and rounding of t near 0 grows with the coordinates.
inline constexpr double kVisibilityOffsetUlps = 64;

// The tnear of visibility rays for `scene`, in scene units:
// max(kVisibilityOffsetRelative * diagonal, kVisibilityOffsetUlps * ulp(max |coordinate|)).
double visibility_offset(const EmbreeScene& scene);

// A reusable batch of visibility queries in structure-of-arrays form: fill it
// with add(), then trace(). Create one per chunk of work (or reuse it after
// clear()); it allocates only when growing.
class VisibilityBatch {
 public:
  void clear();
  void reserve(std::size_t n);
  // Adds the query "is the ray from p along the unit vector d free?".
  void add(Vec3 p, Vec3 d);
  std::size_t size() const { return org_x_.size(); }

  // visible[i] = 1 if query i's ray, from tnear = offset to infinity, hits
  // nothing, else 0. visible has size() entries. Thread-safe for distinct batches.
  void trace(const EmbreeScene& scene, double offset, uint8_t* visible);

 private:
  std::vector<float> org_x_, org_y_, org_z_, dir_x_, dir_y_, dir_z_, tnear_;
  std::vector<uint8_t> occluded_;
};

// Convenience over whole arrays, batched and in parallel (parallel_for_chunks;
// the result does not depend on the thread count): visible[i] for the ray from
// points[i] along directions[i] (unit vectors). Sizes must match.
std::vector<uint8_t> compute_visibility(const EmbreeScene& scene, const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& directions);

}  // namespace texbake
