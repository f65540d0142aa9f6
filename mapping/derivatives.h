// Analytic derivatives of the six proxies' inverse mappings (issue #16 item
// 2): the 2x3 Jacobian d(u, v)/dP at a world point P, as its two rows, the
// gradients grad u and grad v. A footprint filter turns a sample's footprint
// on the surface (two 3D vectors t1, t2) into one in texture space:
// (grad u . t, grad v . t) for t = t1, t2.
//
// Limits, stated per proxy below and tested in tests/mapping/derivatives_test.cpp:
//  - The u seam: u is periodic, so its derivative is the continuous one of
//    the azimuth, the same on both sides of u = 0 and at it; it never sees
//    the wrap (a finite difference across the seam must be wrapped into
//    [-0.5, 0.5] to agree with it).
//  - The axis (the sphere's poles, a cylinder's or cone's axis, the disk's
//    centre, the cone's apex): the azimuth has no derivative there (|grad u|
//    grows as 1 / (2 pi distance from the axis)). There u_defined is false
//    and du is the zero vector: a footprint touching the axis covers every
//    u, and callers must treat it as spanning the whole period.
//    Where v has a kink on the axis as well (the sphere's poles, the cone's
//    axis, the disk's centre) v_defined is false, dv is the zero vector, and
//    v_rate is |dv| per unit of distance along the surface, which is the
//    same in every direction there (sphere pole: 1 / (pi |P - center|); cone
//    apex: 1 / slant, slant = hypot(radius, height); disk centre: 1 / radius).
//    On a cylinder's axis v = h / height stays smooth: v_defined stays true.
//  - No mapping at all (the sphere's centre, the cone's axis off the apex,
//    MapStatus::kUndefined): both flags false, v_rate 0.
//  - Points "on the axis" are those inverse_map treats so (azimuth.h,
//    kAxisTolerance): the flags agree with MapResult's u = 0 convention.
//  - Quad: P's component along the quad's normal does not change (u, v)
//    (inverse_map projects P onto the plane); where the bilinear patch
//    folds (outside a convex quad, (dP/du x dP/dv) . n = 0) both flags are
//    false and both gradients zero. Plane: constant gradients, always defined.
//  - A non-finite P: both flags false, gradients zero.
//
// Standard C++ only; no allocation; one overload per proxy type, so hot
// loops that std::visit once per chunk call the concrete one directly. A new
// alternative of Proxy (e.g. a camera projector) needs its own overload
// (in its own file if need be): the dispatch below and the bakes' visits
// then fail to compile without one, on purpose (a made-up "undefined"
// Jacobian would silently blur every lookup over a whole period).
#pragma once

#include "mapping/proxy.h"
#include "mapping/vec.h"

namespace texbake {

struct UvJacobian {
  Vec3 du;                // grad u (zero when !u_defined)
  Vec3 dv;                // grad v (zero when !v_defined)
  bool u_defined = true;  // false on the axis: a footprint there spans every u
  bool v_defined = true;  // false where v has a kink: use v_rate
  double v_rate = 0;      // when !v_defined and finite: |dv| per unit surface distance
};

UvJacobian inverse_map_jacobian(const Sphere& s, Vec3 p);
UvJacobian inverse_map_jacobian(const Cylinder& c, Vec3 p);
UvJacobian inverse_map_jacobian(const Cone& c, Vec3 p);
UvJacobian inverse_map_jacobian(const Disk& d, Vec3 p);
UvJacobian inverse_map_jacobian(const Quad& q, Vec3 p);
UvJacobian inverse_map_jacobian(const Plane& pl, Vec3 p);
// Dispatching convenience (one std::visit).
UvJacobian inverse_map_jacobian(const Proxy& proxy, Vec3 p);

}  // namespace texbake
