// Disk (Glassner/Haines "circle") inverse mapping (SPEC section 2): P
// projected onto the disk's plane; u = azimuth around the normal by the shared
// rule, v = distance from the centre / radius.
#include <algorithm>
#include <cmath>

#include "mapping/azimuth.h"
#include "mapping/proxy_detail.h"

namespace texbake {

MapResult Disk::inverse_map(Vec3 p) const {
  if (!is_finite(p)) return detail::undefined_result(frame.axis);
  const Vec3 w = p - center;
  const double r = std::hypot(dot(w, frame.equator), dot(w, frame.east));
  const double v = r / radius;
  // At the centre on_axis holds and azimuth() already gives u = 0.
  const double u = azimuth(frame, w, std::max(radius, length(w))).u;
  const MapStatus status = v <= 1 + detail::kEdgeTolerance ? MapStatus::kOk : MapStatus::kOutside;
  return {{u, v}, frame.axis, status};
}

Vec3 Disk::forward_map(UV uv) const {
  return center + azimuth_direction(frame, uv.u) * (uv.v * radius);
}

}  // namespace texbake
