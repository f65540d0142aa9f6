// Plane inverse mapping (SPEC section 2): u = (P - origin) . u_axis / |u_axis|^2,
// same for v. For axes that are not perpendicular that formula would not
// invert forward_map (origin + u u_axis + v v_axis), so the 2x2 normal
// equations are solved instead; for perpendicular axes both are the same.
#include <cmath>

#include "mapping/proxy_detail.h"

namespace texbake {

MapResult Plane::inverse_map(Vec3 p) const {
  if (!is_finite(p)) return detail::undefined_result(normal);
  const Vec3 h = p - origin;
  // In unit directions so the system stays well scaled for any axis length.
  const double u_len = length(u_axis), v_len = length(v_axis);
  const Vec3 uu = u_axis / u_len, vv = v_axis / v_len;
  const double c = dot(uu, vv);
  const double det = 1 - c * c;  // sin^2 of the axes' angle, > 1e-18 (validated)
  const double a = dot(h, uu), b = dot(h, vv);
  const double u = (a - c * b) / det / u_len;
  const double v = (b - c * a) / det / v_len;
  const bool inside = detail::in_unit_interval(u) && detail::in_unit_interval(v);
  return {{u, v}, normal, inside ? MapStatus::kOk : MapStatus::kOutside};
}

Vec3 Plane::forward_map(UV uv) const {
  return origin + u_axis * uv.u + v_axis * uv.v;
}

}  // namespace texbake
