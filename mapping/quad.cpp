// Quad inverse mapping (SPEC section 2): invert the bilinear patch
//   P = p00 + u e + v f + u v g,  e = p10 - p00, f = p01 - p00, g = p00 - p10 + p11 - p01
// after projecting P onto the quad's plane. Crossing with (e + v g) eliminates
// u and leaves k2 v^2 + k1 v + k0 = 0 with (2D cross products taken about the
// normal) k2 = g x f, k1 = e x f + h x g, k0 = h x e, h = P - p00
// (Haines in Glassner, "Inverse mapping: quadrilateral"; the same algebra as
// Inigo Quilez, "Inverse bilinear interpolation", iquilezles.org).
//
// Roots use the cancellation-free pair q / k2 and k0 / q with
// q = -(k1 + sign(k1) sqrt(disc)) / 2 (Numerical Recipes 5.6): for a
// parallelogram k2 = 0 (or rounding noise) and k0 / q = -k0 / k1 is the
// linear equation's root, so no threshold separates the two cases.
#include <algorithm>
#include <cmath>
#include <limits>

#include "mapping/proxy_detail.h"

namespace texbake {

namespace {

// How far (u, v) lies from the unit square (0 inside): picks among the roots.
double distance_to_unit_square(UV uv) {
  const double du = std::max({0.0, -uv.u, uv.u - 1});
  const double dv = std::max({0.0, -uv.v, uv.v - 1});
  return std::hypot(du, dv);
}

}  // namespace

MapResult Quad::inverse_map(Vec3 p) const {
  if (!is_finite(p)) return detail::undefined_result(normal);
  const auto& [p00, p10, p11, p01] = corners;
  const Vec3 e = p10 - p00, f = p01 - p00, g = p00 - p10 + p11 - p01;
  Vec3 h = p - p00;
  h -= normal * dot(h, normal);  // onto the plane
  const auto cross2 = [this](Vec3 a, Vec3 b) { return dot(cross(a, b), normal); };
  const double k2 = cross2(g, f);
  const double k1 = cross2(e, f) + cross2(h, g);
  const double k0 = cross2(h, e);
  // Points outside a convex quad can give complex roots; the real part (the
  // double root of disc = 0) is then the nearest sensible coordinate.
  const double root = std::sqrt(std::max(0.0, k1 * k1 - 4 * k0 * k2));
  const double q = -0.5 * (k1 + std::copysign(root, k1));

  double candidates[2];
  int count = 0;
  if (k2 != 0) candidates[count++] = q / k2;
  if (q != 0) candidates[count++] = k0 / q;

  UV best{};
  double best_distance = std::numeric_limits<double>::infinity();
  for (int i = 0; i < count; ++i) {
    const double v = candidates[i];
    const Vec3 m = e + g * v;  // dP/du at this v
    const double mm = dot(m, m);
    if (!(mm > 0) || !std::isfinite(v)) continue;
    // u from h - f v = u m, in the least-squares sense (uses both components).
    const UV uv{dot(h - f * v, m) / mm, v};
    const double d = distance_to_unit_square(uv);
    if (d < best_distance) {
      best_distance = d;
      best = uv;
    }
  }
  if (!std::isfinite(best_distance)) return detail::undefined_result(normal);
  const bool inside = best_distance <= detail::kEdgeTolerance;
  return {best, normal, inside ? MapStatus::kOk : MapStatus::kOutside};
}

Vec3 Quad::forward_map(UV uv) const {
  const auto& [p00, p10, p11, p01] = corners;
  const double u = uv.u, v = uv.v;
  return p00 * ((1 - u) * (1 - v)) + p10 * (u * (1 - v)) + p11 * (u * v) + p01 * ((1 - u) * v);
}

}  // namespace texbake
