// Proxy kinds, validation (SPEC section 1) and dispatch. The inverse and
// forward maps live in one file per proxy (sphere.cpp, cylinder.cpp, ...).
#include "mapping/proxy.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "mapping/azimuth.h"

namespace texbake {

namespace {

constexpr const char* kKindNames[] = {"sphere", "cylinder", "cone", "disk", "quad", "plane"};

// The one translation from a parameter's key to its flag: "u_axis" -> "--u-axis".
std::string param_name(std::string_view key, ParamNaming naming) {
  if (naming == ParamNaming::kKey) return std::string(key);
  std::string flag = "--";
  for (char c : key) flag += (c == '_') ? '-' : c;
  return flag;
}

std::string number_text(double x) {
  std::ostringstream out;
  out.precision(17);
  out << x;
  return out.str();
}

struct Validator {
  ProxyKind kind;
  ParamNaming naming;

  std::string name(std::string_view key) const { return param_name(key, naming); }
  Error fail(const std::string& what) const {
    return make_error(ErrorCode::kInvalidArgument, std::string(to_string(kind)) + ": " + what);
  }
  // Prefixes the kind to an error from a helper that already names the parameter.
  Error wrap(const Error& e) const { return fail(e.message); }

  std::optional<Error> point(Vec3 p, std::string_view key) const {
    if (!is_finite(p)) return fail(name(key) + " is not finite");
    return std::nullopt;
  }
  std::optional<Error> positive(double x, std::string_view key) const {
    if (!std::isfinite(x) || x <= 0) {
      return fail(name(key) + " must be a finite number > 0 (got " + number_text(x) + ")");
    }
    return std::nullopt;
  }
  Expected<Frame> frame(Vec3 axis, const std::optional<Vec3>& equator,
                        std::string_view axis_key) const {
    Expected<Frame> f = make_frame(axis, equator, name(axis_key), name("equator"));
    if (!f) return wrap(f.error());
    return f;
  }
};

Expected<Proxy> make(const SphereParams& p, const Validator& check) {
  if (auto e = check.point(p.center, "center")) return *e;
  if (auto e = check.positive(p.radius, "radius")) return *e;
  Expected<Frame> frame = check.frame(p.pole, p.equator, "pole");
  if (!frame) return frame.error();
  return Proxy{Sphere{p.center, p.radius, *frame}};
}

Expected<Proxy> make(const CylinderParams& p, const Validator& check) {
  if (auto e = check.point(p.base, "base")) return *e;
  if (auto e = check.positive(p.radius, "radius")) return *e;
  if (auto e = check.positive(p.height, "height")) return *e;
  Expected<Frame> frame = check.frame(p.axis, p.equator, "axis");
  if (!frame) return frame.error();
  return Proxy{Cylinder{p.base, *frame, p.radius, p.height}};
}

Expected<Proxy> make(const ConeParams& p, const Validator& check) {
  if (auto e = check.point(p.apex, "apex")) return *e;
  if (auto e = check.positive(p.height, "height")) return *e;
  if (auto e = check.positive(p.radius, "radius")) return *e;
  Expected<Frame> frame = check.frame(p.axis, p.equator, "axis");
  if (!frame) return frame.error();
  return Proxy{Cone{p.apex, *frame, p.height, p.radius}};
}

Expected<Proxy> make(const DiskParams& p, const Validator& check) {
  if (auto e = check.point(p.center, "center")) return *e;
  if (auto e = check.positive(p.radius, "radius")) return *e;
  Expected<Frame> frame = check.frame(p.normal, p.equator, "normal");
  if (!frame) return frame.error();
  return Proxy{Disk{p.center, *frame, p.radius}};
}

// SPEC section 2: convex and planar within 1e-6 of the quad's size.
constexpr double kQuadPlanarity = 1e-6;
// Each corner's turn must enclose more than this fraction of size^2: rejects
// three collinear corners and coincident corners, not just strict bow-ties.
constexpr double kQuadMinTurn = 1e-9;

Expected<Proxy> make(const QuadParams& p, const Validator& check) {
  static constexpr const char* kCornerNames[] = {"p00", "p10", "p11", "p01"};
  const std::string corners = check.name("corners");
  for (const Vec3& c : p.corners) {
    if (!is_finite(c)) return check.fail(corners + " contain a non-finite coordinate");
  }
  const auto& q = p.corners;  // p00, p10, p11, p01: a cycle around the quad
  const double size = std::max(length(q[2] - q[0]), length(q[3] - q[1]));
  if (!(size > 0)) return check.fail(corners + " are all the same point");
  // The turn at each corner, (incoming edge) x (outgoing edge). The largest
  // one gives the reference plane: the three corners around it.
  Vec3 turn[4];
  int k = 0;
  for (int i = 0; i < 4; ++i) {
    turn[i] = cross(q[i] - q[(i + 3) % 4], q[(i + 1) % 4] - q[i]);
    if (length(turn[i]) > length(turn[k])) k = i;
  }
  const double min_turn = kQuadMinTurn * size * size;
  if (length(turn[k]) <= min_turn) return check.fail(corners + " are degenerate (all on a line)");
  const Vec3 n = normalize(turn[k]);
  const double off_plane = std::abs(dot(q[(k + 2) % 4] - q[k], n));
  if (off_plane > kQuadPlanarity * size) {
    return check.fail(corners + " are not planar (" + kCornerNames[(k + 2) % 4] + " lies " +
                      number_text(off_plane) +
                      " off the plane of the other three, more than 1e-6 of the diagonal)");
  }
  // Convex (and not a bow-tie) iff every corner turns the same way, by more
  // than rounding noise.
  for (int i = 0; i < 4; ++i) {
    if (dot(turn[i], n) <= min_turn) {
      return check.fail(corners + " are not convex at " + kCornerNames[i] +
                        " (expected a convex quad with corners p00, p10, p11, p01 in order "
                        "around it)");
    }
  }
  // SPEC section 2: d = normalize((p10 - p00) x (p01 - p00)) = turn[0].
  return Proxy{Quad{q, normalize(turn[0])}};
}

Expected<Proxy> make(const PlaneParams& p, const Validator& check) {
  if (auto e = check.point(p.origin, "origin")) return *e;
  Expected<Vec3> u = unit_vector(p.u_axis, check.name("u_axis"));
  if (!u) return check.wrap(u.error());
  Expected<Vec3> v = unit_vector(p.v_axis, check.name("v_axis"));
  if (!v) return check.wrap(v.error());
  const Vec3 normal = cross(*u, *v);
  if (length(normal) <= kParallelTolerance) {
    return check.fail(check.name("v_axis") + " is parallel to " + check.name("u_axis"));
  }
  const double scale2 = std::max(dot(p.u_axis, p.u_axis), dot(p.v_axis, p.v_axis));
  if (!std::isfinite(scale2)) return check.fail("axes are too long (overflow)");
  return Proxy{Plane{p.origin, p.u_axis, p.v_axis, normalize(normal)}};
}

}  // namespace

const char* to_string(ProxyKind kind) {
  return kKindNames[static_cast<int>(kind)];
}

std::optional<ProxyKind> parse_proxy_kind(std::string_view name) {
  for (int i = 0; i < 6; ++i) {
    if (name == kKindNames[i]) return static_cast<ProxyKind>(i);
  }
  return std::nullopt;
}

Expected<Proxy> make_proxy(const ProxyParams& params, ParamNaming naming) {
  return std::visit(
      [&](const auto& p) {
        return make(p, Validator{kind_of(params), naming});
      },
      params);
}

ProxyParams params_of(const Proxy& proxy) {
  struct Visitor {
    ProxyParams operator()(const Sphere& s) const {
      return SphereParams{s.center, s.radius, s.frame.axis, s.frame.equator};
    }
    ProxyParams operator()(const Cylinder& c) const {
      return CylinderParams{c.base, c.frame.axis, c.frame.equator, c.radius, c.height};
    }
    ProxyParams operator()(const Cone& c) const {
      return ConeParams{c.apex, c.frame.axis, c.frame.equator, c.height, c.radius};
    }
    ProxyParams operator()(const Disk& d) const {
      return DiskParams{d.center, d.frame.axis, d.frame.equator, d.radius};
    }
    ProxyParams operator()(const Quad& q) const { return QuadParams{q.corners}; }
    ProxyParams operator()(const Plane& p) const {
      return PlaneParams{p.origin, p.u_axis, p.v_axis};
    }
  };
  return std::visit(Visitor{}, proxy);
}

// The variants list the kinds in ProxyKind's order.
ProxyKind kind_of(const Proxy& proxy) {
  return static_cast<ProxyKind>(proxy.index());
}
ProxyKind kind_of(const ProxyParams& params) {
  return static_cast<ProxyKind>(params.index());
}

WrapMode wrap_u(const Proxy& proxy) {
  switch (kind_of(proxy)) {
    case ProxyKind::kSphere:
    case ProxyKind::kCylinder:
    case ProxyKind::kCone:
    case ProxyKind::kDisk:
      return WrapMode::kRepeat;
    case ProxyKind::kQuad:
    case ProxyKind::kPlane:
      return WrapMode::kClamp;
  }
  return WrapMode::kClamp;
}

MapResult inverse_map(const Proxy& proxy, Vec3 p) {
  return std::visit([p](const auto& shape) { return shape.inverse_map(p); }, proxy);
}

Vec3 forward_map(const Proxy& proxy, UV uv) {
  return std::visit([uv](const auto& shape) { return shape.forward_map(uv); }, proxy);
}

}  // namespace texbake
