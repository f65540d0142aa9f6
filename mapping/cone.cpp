// Cone inverse mapping (SPEC section 2). In the half-plane through P and the
// axis, with s = distance from the axis and t = depth below the apex, the
// generator runs from the apex (0, 0) to the base rim (R, H). P's closest
// point on that line is at lambda = (s R + t H) / (R^2 + H^2) of the way from
// the apex to the rim, so v = 1 - lambda (0 on the rim, 1 at the apex). The
// outward normal there is (H, -R) / L in (s, t), i.e. (H rho_hat + R axis) / L.
#include <algorithm>
#include <cmath>

#include "mapping/azimuth.h"
#include "mapping/proxy_detail.h"

namespace texbake {

MapResult Cone::inverse_map(Vec3 p) const {
  if (!is_finite(p)) return detail::undefined_result(frame.axis);
  const Vec3 w = p - apex;
  const double slant = std::hypot(radius, height);
  const double s = std::hypot(dot(w, frame.equator), dot(w, frame.east));
  const double t = -dot(w, frame.axis);
  const double v = 1 - (s * radius + t * height) / (slant * slant);
  const Azimuth az = azimuth(frame, w, std::max(slant, length(w)));
  if (az.on_axis) {
    // The apex itself is on the surface (v = 1, u = 0 by convention); any
    // other point of the axis is equally close to a whole circle.
    if (length(w) <= kAxisTolerance * slant) return {{0, 1}, frame.axis, MapStatus::kOk};
    return detail::undefined_result(frame.axis, {0, v});
  }
  const Vec3 rho_hat =
      normalize(frame.equator * dot(w, frame.equator) + frame.east * dot(w, frame.east));
  const Vec3 normal = (rho_hat * height + frame.axis * radius) / slant;
  const MapStatus status = detail::in_unit_interval(v) ? MapStatus::kOk : MapStatus::kOutside;
  return {{az.u, v}, normal, status};
}

Vec3 Cone::forward_map(UV uv) const {
  return apex + (azimuth_direction(frame, uv.u) * radius - frame.axis * height) * (1 - uv.v);
}

}  // namespace texbake
