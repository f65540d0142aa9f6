#include "bake/trace/visibility.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "bake/util/parallel.h"

namespace texbake {

namespace {
// Queries per parallel chunk: enough to amortise Embree's per-call set-up,
// small enough to balance two to a few dozen cores.
constexpr std::size_t kVisibilityGrain = 4096;
}  // namespace

double visibility_offset(const EmbreeScene& scene) {
  const double relative = kVisibilityOffsetRelative * scene.diagonal();
  const double ulp = scene.max_abs_coordinate() * std::numeric_limits<float>::epsilon();
  return std::max(relative, kVisibilityOffsetUlps * ulp);
}

void VisibilityBatch::clear() {
  org_x_.clear();
  org_y_.clear();
  org_z_.clear();
  dir_x_.clear();
  dir_y_.clear();
  dir_z_.clear();
}

void VisibilityBatch::reserve(std::size_t n) {
  for (auto* v : {&org_x_, &org_y_, &org_z_, &dir_x_, &dir_y_, &dir_z_}) v->reserve(n);
}

void VisibilityBatch::add(Vec3 p, Vec3 d) {
  org_x_.push_back(static_cast<float>(p.x));
  org_y_.push_back(static_cast<float>(p.y));
  org_z_.push_back(static_cast<float>(p.z));
  dir_x_.push_back(static_cast<float>(d.x));
  dir_y_.push_back(static_cast<float>(d.y));
  dir_z_.push_back(static_cast<float>(d.z));
}

void VisibilityBatch::trace(const EmbreeScene& scene, double offset, uint8_t* visible) {
  const std::size_t n = size();
  tnear_.assign(n, static_cast<float>(offset));
  occluded_.resize(n);
  RayBatch rays;
  rays.org_x = org_x_.data();
  rays.org_y = org_y_.data();
  rays.org_z = org_z_.data();
  rays.dir_x = dir_x_.data();
  rays.dir_y = dir_y_.data();
  rays.dir_z = dir_z_.data();
  rays.tnear = tnear_.data();
  rays.count = n;
  scene.occluded(rays, occluded_.data());
  for (std::size_t i = 0; i < n; ++i) visible[i] = occluded_[i] ? 0 : 1;
}

std::vector<uint8_t> compute_visibility(const EmbreeScene& scene, const std::vector<Vec3>& points,
                                        const std::vector<Vec3>& directions) {
  assert(points.size() == directions.size());
  std::vector<uint8_t> visible(points.size(), 0);
  const double offset = visibility_offset(scene);
  parallel_for_chunks(points.size(), kVisibilityGrain, [&](std::size_t begin, std::size_t end) {
    VisibilityBatch batch;
    batch.reserve(end - begin);
    for (std::size_t i = begin; i < end; ++i) batch.add(points[i], directions[i]);
    batch.trace(scene, offset, visible.data() + begin);
  });
  return visible;
}

}  // namespace texbake
