// The Embree 3 scene over a mesh's triangles: one RAII object per run, built
// once, queried by batches of rays. This header names no Embree type; only
// embree_scene.cpp includes <embree3/rtcore.h>.
//
// Rays come as structure-of-arrays batches; the implementation copies them in
// blocks into aligned arrays for Embree's stream API (rtcOccluded1M /
// rtcIntersectNp). Every ray is fully initialised inside (mask = -1: Debian's
// Embree is built with ray masks, and a ray with another mask hits nothing).
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "mapping/error.h"
#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

enum class BuildQuality {
  kLow,     // fastest build, for one-shot visibility queries
  kMedium,  // better traversal, for renders that trace many rays
};

// A batch of n rays, structure of arrays. Directions need not be unit; t is
// measured in units of the direction's length. Pointers are not owned.
struct RayBatch {
  const float* org_x = nullptr;
  const float* org_y = nullptr;
  const float* org_z = nullptr;
  const float* dir_x = nullptr;
  const float* dir_y = nullptr;
  const float* dir_z = nullptr;
  const float* tnear = nullptr;  // may be null: 0 for every ray
  const float* tfar = nullptr;   // may be null: infinity for every ray
  std::size_t count = 0;
};

// Storage for rays as structure of arrays (what RayBatch views), for callers
// that build a batch ray by ray: set() fills slot i, batch(n) views the first
// n (tnear 0, tfar infinity). No allocation after resize().
struct RayArrays {
  std::vector<float> org_x, org_y, org_z, dir_x, dir_y, dir_z;

  void resize(std::size_t n) {
    for (auto* v : {&org_x, &org_y, &org_z, &dir_x, &dir_y, &dir_z}) v->resize(n);
  }
  void set(std::size_t i, Vec3 origin, Vec3 direction) {
    org_x[i] = static_cast<float>(origin.x);
    org_y[i] = static_cast<float>(origin.y);
    org_z[i] = static_cast<float>(origin.z);
    dir_x[i] = static_cast<float>(direction.x);
    dir_y[i] = static_cast<float>(direction.y);
    dir_z[i] = static_cast<float>(direction.z);
  }
  RayBatch batch(std::size_t n) const {
    RayBatch b;
    b.org_x = org_x.data();
    b.org_y = org_y.data();
    b.org_z = org_z.data();
    b.dir_x = dir_x.data();
    b.dir_y = dir_y.data();
    b.dir_z = dir_z.data();
    b.count = n;
    return b;
  }
};

inline constexpr uint32_t kNoHit = 0xFFFFFFFFu;

// Nearest hit of one ray. triangle indexes MeshData::triangles; (b1, b2) are
// the barycentric weights of its 2nd and 3rd vertex (the 1st is 1 - b1 - b2).
struct Hit {
  uint32_t triangle = kNoHit;
  float t = 0;
  float b1 = 0, b2 = 0;
  Float3 normal;  // geometric normal, unnormalised, (v1 - v0) x (v2 - v0)
};

class EmbreeScene {
 public:
  // Builds the scene over mesh.triangles (positions copied into a padded
  // buffer, SPEC: Embree reads the last vertex with a 16-byte load).
  // Errors: kInternal with Embree's message.
  static Expected<EmbreeScene> build(const MeshData& mesh, BuildQuality quality);

  EmbreeScene(EmbreeScene&&) noexcept;
  EmbreeScene& operator=(EmbreeScene&&) noexcept;
  ~EmbreeScene();

  // Length of the bounding-box diagonal of the mesh's referenced vertices:
  // the scale that ray offsets are relative to (SPEC section 3).
  double diagonal() const;
  // Largest |coordinate| of the referenced vertices: float positions have an
  // absolute precision of about this times 2^-24, which bounds how small a
  // ray offset may be (bake/trace/visibility.h).
  double max_abs_coordinate() const;

  // occluded[i] = 1 if ray i hits any triangle with t in [tnear, tfar], else 0.
  // Thread-safe: may be called from many threads at once.
  void occluded(const RayBatch& rays, uint8_t* occluded) const;

  // hits[i] = the nearest hit of ray i in [tnear, tfar], or triangle == kNoHit.
  // Thread-safe.
  void intersect(const RayBatch& rays, Hit* hits) const;

 private:
  struct Impl;
  explicit EmbreeScene(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace texbake
