#include "mapping/azimuth.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace texbake {

double wrap_unit(double u) {
  double w = u - std::floor(u);
  // u = -1e-18 gives 1 - 1e-18, which rounds to exactly 1.0: that is the seam.
  return w >= 1.0 ? 0.0 : w;
}

Azimuth azimuth(const Frame& frame, Vec3 w, double scale) {
  const double along_equator = dot(w, frame.equator);
  const double along_east = dot(w, frame.east);
  // Across-axis length: at the poles, the apex or the disk centre it is
  // rounding noise whose atan2 would be an arbitrary angle.
  if (std::hypot(along_equator, along_east) <= kAxisTolerance * scale) return {0.0, true};
  // The stable atan2 form of SPEC section 2: no acos near +-1, no division by
  // sin(phi). atan2's range (-pi, pi] is folded into [0, 1).
  return {wrap_unit(std::atan2(along_east, along_equator) / (2 * std::numbers::pi)), false};
}

Vec3 azimuth_direction(const Frame& frame, double u) {
  const double angle = 2 * std::numbers::pi * u;
  return frame.equator * std::cos(angle) + frame.east * std::sin(angle);
}

Expected<Vec3> unit_vector(Vec3 v, const std::string& name) {
  if (!is_finite(v)) return make_error(ErrorCode::kInvalidArgument, name + " is not finite");
  const double largest = std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
  if (largest == 0) return make_error(ErrorCode::kInvalidArgument, name + " is the zero vector");
  // Scaling first keeps |v|^2 from overflowing (1e200) or underflowing (1e-200).
  return normalize(v / largest);
}

namespace {

// The component of unit `v` perpendicular to unit `axis`, or nullopt when v is
// parallel to it. Two Gram-Schmidt passes: the second removes what rounding
// left of the axis component when v was nearly parallel (classical GS loses
// orthogonality as 1e-16 / sin(angle); twice is enough, Giraud et al. 2005).
std::optional<Vec3> perpendicular_part(Vec3 axis, Vec3 v) {
  Vec3 p = v - axis * dot(v, axis);
  if (length(p) <= kParallelTolerance) return std::nullopt;
  p = normalize(p);
  p = p - axis * dot(p, axis);
  return normalize(p);
}

}  // namespace

Expected<Frame> make_frame(Vec3 axis, const std::optional<Vec3>& equator,
                           const std::string& axis_name, const std::string& equator_name) {
  Expected<Vec3> a = unit_vector(axis, axis_name);
  if (!a) return a.error();
  std::optional<Vec3> e;
  if (equator) {
    Expected<Vec3> given = unit_vector(*equator, equator_name);
    if (!given) return given.error();
    e = perpendicular_part(*a, *given);
    if (!e) {
      return make_error(ErrorCode::kInvalidArgument, equator_name + " is parallel to " + axis_name);
    }
  } else {
    for (Vec3 candidate : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}) {
      e = perpendicular_part(*a, candidate);
      if (e) break;
    }
    // A unit axis is parallel to at most one coordinate axis.
    assert(e);
  }
  return Frame{*a, *e, cross(*a, *e)};
}

}  // namespace texbake
