// Cylinder inverse mapping (SPEC section 2): azimuth around the axis by the
// shared rule, v = height fraction along the axis.
#include <algorithm>
#include <cmath>

#include "mapping/azimuth.h"
#include "mapping/proxy_detail.h"

namespace texbake {

MapResult Cylinder::inverse_map(Vec3 p) const {
  if (!is_finite(p)) return detail::undefined_result(frame.axis);
  const Vec3 w = p - base;
  const double v = dot(w, frame.axis) / height;
  const Azimuth az = azimuth(frame, w, std::max(radius, length(w)));
  // On the axis the closest surface point is a whole circle: no d(P), no u.
  if (az.on_axis) return detail::undefined_result(frame.axis, {0, v});
  const Vec3 rho = frame.equator * dot(w, frame.equator) + frame.east * dot(w, frame.east);
  const MapStatus status = detail::in_unit_interval(v) ? MapStatus::kOk : MapStatus::kOutside;
  return {{az.u, v}, normalize(rho), status};
}

Vec3 Cylinder::forward_map(UV uv) const {
  return base + frame.axis * (uv.v * height) + azimuth_direction(frame, uv.u) * radius;
}

}  // namespace texbake
