// A sample's footprint in texture space for --filter ewa (issue #16 item 2,
// SPEC section 13): the inverse mapping's Jacobian (mapping/derivatives.h)
// applied to the sample's footprint on the surface, two 3D vectors t1, t2.
//
// Where the sample lies on the proxy's axis (the sphere's poles, the cone's
// apex, the disk's centre: UvJacobian::u_defined false) every u is under the
// footprint: it spans one whole period in u (1.0), and in v the extent the
// Jacobian gives (or v_rate times the longer surface vector where v has a
// kink there), as an axis-aligned ellipse. Near (not on) the axis the
// Jacobian is finite and the footprint's u extent grows towards a period on
// its own, so the two agree in the limit.
#pragma once

#include <algorithm>
#include <cmath>

#include "mapping/derivatives.h"
#include "mapping/mipmap.h"
#include "mapping/vec.h"

namespace texbake {

inline UvFootprint uv_footprint(const UvJacobian& j, Vec3 t1, Vec3 t2) {
  if (j.u_defined && j.v_defined) {
    return {{dot(j.du, t1), dot(j.dv, t1)}, {dot(j.du, t2), dot(j.dv, t2)}};
  }
  const double eu = j.u_defined ? std::max(std::abs(dot(j.du, t1)), std::abs(dot(j.du, t2))) : 1.0;
  const double ev = j.v_defined ? std::max(std::abs(dot(j.dv, t1)), std::abs(dot(j.dv, t2)))
                                : j.v_rate * std::max(length(t1), length(t2));
  return {{eu, 0}, {0, ev}};
}

// Two tangent vectors of length sqrt(area) perpendicular to `normal` (any
// length, non-zero) and to each other: an isotropic footprint of that area
// on the surface. A zero normal gives zero vectors (no footprint: the lookup
// is bilinear).
inline void isotropic_tangents(Vec3 normal, double area, Vec3& t1, Vec3& t2) {
  const double len = length(normal);
  if (!(len > 0) || !(area > 0)) {
    t1 = t2 = Vec3{};
    return;
  }
  const Vec3 n = normal / len;
  // Frisvad-style: the coordinate axis least aligned with n.
  const Vec3 helper =
      std::abs(n.x) < 0.6 ? Vec3{1, 0, 0} : (std::abs(n.y) < 0.6 ? Vec3{0, 1, 0} : Vec3{0, 0, 1});
  const Vec3 a = normalize(cross(n, helper));
  const Vec3 b = cross(n, a);
  const double side = std::sqrt(area);
  t1 = a * side;
  t2 = b * side;
}

}  // namespace texbake
