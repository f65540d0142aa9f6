// The six analytic proxies of SPEC section 2 and their inverse mappings.
//
// A proxy is a small immutable value: construct it from user parameters with
// make_proxy() (which validates and normalises, SPEC section 1), then call
// inverse_map() for world points. No I/O, no third-party library.
//
// Conventions (SPEC section 1):
//  - (u, v) in [0, 1]; v = 0 is the bottom image row.
//  - Seen from the tip of the pole/axis/normal, u grows counter-clockwise
//    (sphere, cylinder, cone, disk) or to the right (quad, plane).
//  - u is periodic for sphere, cylinder, cone and disk (wrap_u() == kRepeat).
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <variant>

#include "mapping/error.h"
#include "mapping/vec.h"

namespace texbake {

enum class ProxyKind { kSphere, kCylinder, kCone, kDisk, kQuad, kPlane };

// "sphere", "cylinder", ... (the names of the CLI and the JSON "kind" key).
const char* to_string(ProxyKind kind);
std::optional<ProxyKind> parse_proxy_kind(std::string_view name);

// ---- User parameters, as given on the command line or in JSON. ----------
// Vectors need not be unit. An absent equator means: the first of +X, +Y, +Z
// that is not parallel to the pole/axis/normal (then made perpendicular).

struct SphereParams {
  Vec3 center;
  double radius = 1;
  Vec3 pole{0, 0, 1};
  std::optional<Vec3> equator;
};
struct CylinderParams {
  Vec3 base;  // centre of the bottom cap (v = 0)
  Vec3 axis{0, 0, 1};
  std::optional<Vec3> equator;
  double radius = 1;
  double height = 1;
};
struct ConeParams {
  Vec3 apex;           // v = 1
  Vec3 axis{0, 0, 1};  // from the base centre towards the apex
  std::optional<Vec3> equator;
  double height = 1;  // apex to base plane
  double radius = 1;  // base radius
};
struct DiskParams {
  Vec3 center;
  Vec3 normal{0, 0, 1};
  std::optional<Vec3> equator;
  double radius = 1;
};
struct QuadParams {
  std::array<Vec3, 4> corners;  // p00, p10, p11, p01 (u runs p00->p10, v p00->p01)
};
struct PlaneParams {
  Vec3 origin;           // (u, v) = (0, 0)
  Vec3 u_axis{1, 0, 0};  // (u, v) = (1, 0) at origin + u_axis
  Vec3 v_axis{0, 1, 0};
};

using ProxyParams =
    std::variant<SphereParams, CylinderParams, ConeParams, DiskParams, QuadParams, PlaneParams>;

// ---- Results. -----------------------------------------------------------

enum class MapStatus {
  kOk,         // inside the proxy's (u, v) domain
  kOutside,    // outside it (cylinder/cone height, disk radius, quad, plane): uv is
               // the unclamped coordinate; the sampler's clamp or --outside decides
  kUndefined,  // no mapping exists (P at the sphere's centre, on a cylinder's axis...)
};

struct MapResult {
  UV uv;              // may lie outside [0,1] when status == kOutside
  Vec3 to_projector;  // d(P): unit vector from P towards the projector (SPEC section 2)
  MapStatus status = MapStatus::kOk;
};

enum class WrapMode { kClamp, kRepeat };

// ---- Validated proxies. -------------------------------------------------
// An orthonormal frame: axis (pole/axis/normal), equator (u = 0 direction),
// east = axis x equator (u = 0.25 direction).
struct Frame {
  Vec3 axis, equator, east;
};

struct Sphere {
  Vec3 center;
  double radius;
  Frame frame;
  MapResult inverse_map(Vec3 p) const;
  // The textbook acos form of SPEC section 2, kept for the tests.
  UV inverse_map_textbook(Vec3 p) const;
  Vec3 forward_map(UV uv) const;  // point on the sphere's surface
};
struct Cylinder {
  Vec3 base;
  Frame frame;
  double radius, height;
  MapResult inverse_map(Vec3 p) const;
  Vec3 forward_map(UV uv) const;
};
struct Cone {
  Vec3 apex;
  Frame frame;
  double height, radius;
  MapResult inverse_map(Vec3 p) const;
  Vec3 forward_map(UV uv) const;
};
struct Disk {
  Vec3 center;
  Frame frame;
  double radius;
  MapResult inverse_map(Vec3 p) const;
  Vec3 forward_map(UV uv) const;
};
struct Quad {
  std::array<Vec3, 4> corners;  // p00, p10, p11, p01
  Vec3 normal;                  // normalize((p10 - p00) x (p01 - p00))
  MapResult inverse_map(Vec3 p) const;
  Vec3 forward_map(UV uv) const;
};
struct Plane {
  Vec3 origin, u_axis, v_axis;
  Vec3 normal;  // normalize(u_axis x v_axis)
  MapResult inverse_map(Vec3 p) const;
  Vec3 forward_map(UV uv) const;
};

using Proxy = std::variant<Sphere, Cylinder, Cone, Disk, Quad, Plane>;

// How error messages name a parameter: as its JSON key ("u_axis") or as its
// command-line flag ("--u-axis").
enum class ParamNaming { kKey, kFlag };

// Validates and normalises (errors: kInvalidArgument, message names the
// parameter, e.g. "sphere: pole is the zero vector", "quad: corners are not
// convex"). Rejected: non-finite values, zero vectors, an equator parallel to
// the pole/axis/normal, radius or height <= 0, parallel plane axes, and quads
// that are not planar (a corner off the plane of the other three by more than
// 1e-6 of the longer diagonal), not convex (including bow-ties), or degenerate.
Expected<Proxy> make_proxy(const ProxyParams& params, ParamNaming naming = ParamNaming::kKey);

// The parameters that rebuild `proxy` (equator filled in, pole/axis/normal and
// equator unit; plane axes keep their length, which is the image's extent).
ProxyParams params_of(const Proxy& proxy);

ProxyKind kind_of(const Proxy& proxy);
ProxyKind kind_of(const ProxyParams& params);
WrapMode wrap_u(const Proxy& proxy);  // kRepeat for sphere, cylinder, cone, disk
inline WrapMode wrap_v(const Proxy&) {
  return WrapMode::kClamp;
}

// Dispatching conveniences. Hot loops should std::visit once per chunk and
// call the concrete type's inverse_map directly.
MapResult inverse_map(const Proxy& proxy, Vec3 p);
Vec3 forward_map(const Proxy& proxy, UV uv);

}  // namespace texbake
