// Sphere inverse mapping: Glassner (ed.), An Introduction to Ray Tracing,
// ch. 2 (Haines), "Inverse mapping: sphere", in the stable atan2 form of SPEC
// section 2, plus the textbook acos form for the tests.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "mapping/azimuth.h"
#include "mapping/proxy_detail.h"

namespace texbake {

MapResult Sphere::inverse_map(Vec3 p) const {
  const Vec3 w = p - center;
  const double dist = length(w);
  // SPEC section 2: P == center has no mapping. !(>) also catches NaN.
  if (!(dist > kAxisTolerance * radius) || !std::isfinite(dist)) {
    return detail::undefined_result(frame.axis);
  }
  // phi = acos(-Sn . Sp) computed as atan2(|Sn x Sp|, -Sn . Sp): acos loses
  // half the digits near the poles, where its argument is close to +-1.
  const double phi = std::atan2(length(cross(w, frame.axis)), -dot(w, frame.axis));
  const double v = phi / std::numbers::pi;
  // The shared rule: u = atan2((Sp x Se) . Sn, Se . Sn) / 2pi, and u = 0 at the poles.
  const double u = azimuth(frame, w, dist).u;
  return {{u, v}, w / dist, MapStatus::kOk};
}

UV Sphere::inverse_map_textbook(Vec3 p) const {
  const Vec3 sn = normalize(p - center);
  const double phi = std::acos(std::clamp(-dot(sn, frame.axis), -1.0, 1.0));
  const double v = phi / std::numbers::pi;
  if (v == 0 || v == 1) return {0, v};
  const double theta = std::acos(std::clamp(dot(frame.equator, sn) / std::sin(phi), -1.0, 1.0)) /
                       (2 * std::numbers::pi);
  const double u = dot(cross(frame.axis, frame.equator), sn) > 0 ? theta : 1 - theta;
  return {u, v};
}

Vec3 Sphere::forward_map(UV uv) const {
  // v = 0 at -pole (bottom image row), v = 1 at +pole.
  const double phi = std::numbers::pi * uv.v;
  const Vec3 sn = frame.axis * -std::cos(phi) + azimuth_direction(frame, uv.u) * std::sin(phi);
  return center + sn * radius;
}

}  // namespace texbake
