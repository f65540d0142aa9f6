// Analytic derivatives of the inverse mappings (mapping/derivatives.h). The
// formulas are the inverse mappings of sphere.cpp ... quad.cpp differentiated
// by hand; tests/mapping/derivatives_test.cpp checks them against central
// finite differences.
#include "mapping/derivatives.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <variant>

#include "mapping/azimuth.h"

namespace texbake {

namespace {

UvJacobian no_jacobian() {
  return {{}, {}, false, false, 0};
}

// grad of u = atan2(w . east, w . equator) / (2 pi) with respect to P (w = P - origin):
// (x east - y equator) / (2 pi (x^2 + y^2)), x = w . equator, y = w . east.
// Continuous across the seam (atan2's branch cut adds a constant only).
Vec3 azimuth_gradient(const Frame& frame, Vec3 w) {
  const double x = dot(w, frame.equator), y = dot(w, frame.east);
  return (frame.east * x - frame.equator * y) / (2 * std::numbers::pi * (x * x + y * y));
}

// The unit vector from the axis towards w, across it (w off the axis).
Vec3 across_axis(const Frame& frame, Vec3 w) {
  return normalize(frame.equator * dot(w, frame.equator) + frame.east * dot(w, frame.east));
}

}  // namespace

UvJacobian inverse_map_jacobian(const Sphere& s, Vec3 p) {
  const Vec3 w = p - s.center;
  const double dist = length(w);
  if (!(dist > kAxisTolerance * s.radius) || !std::isfinite(dist)) return no_jacobian();
  if (azimuth(s.frame, w, dist).on_axis) {
    // A pole: v = phi / pi grows as (distance along the surface) / (pi dist)
    // in every direction; u takes every value.
    return {{}, {}, false, false, 1 / (std::numbers::pi * dist)};
  }
  // phi = acos(-z / r), z = w . axis: grad phi = (axis r^2 - z w) / (r^2 |w x axis|).
  const double z = dot(w, s.frame.axis);
  const double across = length(cross(w, s.frame.axis));
  const Vec3 dphi = (s.frame.axis * (dist * dist) - w * z) / (dist * dist * across);
  return {azimuth_gradient(s.frame, w), dphi / std::numbers::pi, true, true, 0};
}

UvJacobian inverse_map_jacobian(const Cylinder& c, Vec3 p) {
  if (!is_finite(p)) return no_jacobian();
  const Vec3 w = p - c.base;
  const Vec3 dv = c.frame.axis / c.height;  // v = (w . axis) / height
  if (azimuth(c.frame, w, std::max(c.radius, length(w))).on_axis) return {{}, dv, false, true, 0};
  return {azimuth_gradient(c.frame, w), dv, true, true, 0};
}

UvJacobian inverse_map_jacobian(const Cone& c, Vec3 p) {
  if (!is_finite(p)) return no_jacobian();
  const Vec3 w = p - c.apex;
  const double slant = std::hypot(c.radius, c.height);
  if (azimuth(c.frame, w, std::max(slant, length(w))).on_axis) {
    if (length(w) <= kAxisTolerance * slant) return {{}, {}, false, false, 1 / slant};  // apex
    return no_jacobian();  // the rest of the axis has no mapping
  }
  // v = 1 - (s R + t H) / L^2 with s = distance from the axis (grad s = the
  // unit vector across it) and t = -w . axis.
  const Vec3 dv = (c.frame.axis * c.height - across_axis(c.frame, w) * c.radius) / (slant * slant);
  return {azimuth_gradient(c.frame, w), dv, true, true, 0};
}

UvJacobian inverse_map_jacobian(const Disk& d, Vec3 p) {
  if (!is_finite(p)) return no_jacobian();
  const Vec3 w = p - d.center;
  if (azimuth(d.frame, w, std::max(d.radius, length(w))).on_axis) {
    return {{}, {}, false, false, 1 / d.radius};  // the centre: v = r / radius
  }
  return {azimuth_gradient(d.frame, w), across_axis(d.frame, w) / d.radius, true, true, 0};
}

UvJacobian inverse_map_jacobian(const Quad& q, Vec3 p) {
  if (!is_finite(p)) return no_jacobian();
  const MapResult m = q.inverse_map(p);
  if (m.status == MapStatus::kUndefined) return no_jacobian();
  // P(u, v) = p00 + u e + v f + u v g: the tangents dP/du = e + v g and
  // dP/dv = f + u g. The gradients are the dual basis in the quad's plane:
  // grad u . dP/du = 1, grad u . dP/dv = 0, grad u . n = 0 (and likewise v).
  const auto& [p00, p10, p11, p01] = q.corners;
  const Vec3 e = p10 - p00, f = p01 - p00, g = p00 - p10 + p11 - p01;
  const Vec3 pu = e + g * m.uv.v, pv = f + g * m.uv.u;
  const double area = dot(q.normal, cross(pu, pv));
  const double scale = dot(pu, pu) + dot(pv, pv);
  if (!(std::abs(area) > 1e-12 * scale)) return no_jacobian();  // the patch folds here
  return {cross(pv, q.normal) / area, cross(q.normal, pu) / area, true, true, 0};
}

UvJacobian inverse_map_jacobian(const Plane& pl, Vec3 p) {
  if (!is_finite(p)) return no_jacobian();
  // plane.cpp: u = (a - c b) / det / |u_axis|, v = (b - c a) / det / |v_axis|
  // with a = h . uu, b = h . vv (uu, vv the unit axes, c = uu . vv): linear in P.
  const double u_len = length(pl.u_axis), v_len = length(pl.v_axis);
  const Vec3 uu = pl.u_axis / u_len, vv = pl.v_axis / v_len;
  const double c = dot(uu, vv);
  const double det = 1 - c * c;
  return {(uu - vv * c) / (det * u_len), (vv - uu * c) / (det * v_len), true, true, 0};
}

UvJacobian inverse_map_jacobian(const Proxy& proxy, Vec3 p) {
  return std::visit([p](const auto& concrete) { return inverse_map_jacobian(concrete, p); }, proxy);
}

}  // namespace texbake
