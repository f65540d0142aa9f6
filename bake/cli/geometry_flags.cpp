#include "bake/cli/geometry_flags.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "mesh_io/proxy_json.h"

namespace texbake::cli {

namespace {

using Vec3Member = std::optional<Vec3> GeometryFlags::*;
using NumberMember = std::optional<double> GeometryFlags::*;

struct VectorFlag {
  const char* name;
  Vec3Member member;
  const char* help;
};
struct NumberFlag {
  const char* name;
  NumberMember member;
  const char* help;
};

// SPEC section 5's order.
constexpr VectorFlag kVectorFlags[] = {
    {"--center", &GeometryFlags::center, "sphere/disk centre"},
    {"--pole", &GeometryFlags::pole, "sphere pole: v = 1 at its tip (default: --up)"},
    {"--equator", &GeometryFlags::equator,
     "direction of u = 0 (default: first of +X, +Y, +Z not parallel to the pole/axis/normal)"},
    {"--axis", &GeometryFlags::axis,
     "cylinder axis (base -> top) or cone axis (base -> apex) (default: --up)"},
    {"--apex", &GeometryFlags::apex, "cone apex (v = 1)"},
    {"--base", &GeometryFlags::base, "cylinder base centre (v = 0)"},
    {"--normal", &GeometryFlags::normal, "disk normal, towards the projector (default: --up)"},
    {"--origin", &GeometryFlags::origin, "plane point of (u, v) = (0, 0)"},
    {"--u-axis", &GeometryFlags::u_axis, "plane: origin + u-axis is (u, v) = (1, 0)"},
    {"--v-axis", &GeometryFlags::v_axis, "plane: origin + v-axis is (u, v) = (0, 1)"},
};
constexpr NumberFlag kNumberFlags[] = {
    {"--radius", &GeometryFlags::radius, "sphere/cylinder/disk radius, cone base radius"},
    {"--height", &GeometryFlags::height, "cylinder height, cone height (apex to base plane)"},
};

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> split(std::string_view s, char separator) {
  std::vector<std::string_view> parts;
  for (;;) {
    const std::size_t at = s.find(separator);
    parts.push_back(s.substr(0, at));
    if (at == std::string_view::npos) return parts;
    s.remove_prefix(at + 1);
  }
}

// std::from_chars: locale-independent, and it reports overflow, where
// strtod would give inf and CLI11's lexical cast would accept "nan".
double parse_number(std::string_view text, const std::string& flag) {
  const std::string_view t = trim(text);
  double x = 0;
  const char* first = t.data();
  if (!t.empty() && t.front() == '+') ++first;  // from_chars rejects a leading '+'
  const auto [end, ec] = std::from_chars(first, t.data() + t.size(), x);
  if (ec == std::errc::result_out_of_range) {
    throw CLI::ValidationError(flag, "'" + std::string(text) + "' is out of range (not finite)");
  }
  if (t.empty() || ec != std::errc() || end != t.data() + t.size()) {
    throw CLI::ValidationError(flag, "'" + std::string(text) + "' is not a number");
  }
  if (!std::isfinite(x)) {
    throw CLI::ValidationError(flag, "'" + std::string(text) + "' is not a finite number");
  }
  return x;
}

Vec3 parse_vec3(std::string_view text, const std::string& flag) {
  const std::vector<std::string_view> parts = split(text, ',');
  if (parts.size() != 3) {
    throw CLI::ValidationError(flag,
                               "expected x,y,z (three numbers), got '" + std::string(text) + "'");
  }
  return {parse_number(parts[0], flag), parse_number(parts[1], flag), parse_number(parts[2], flag)};
}

std::array<Vec3, 4> parse_corners(std::string_view text, const std::string& flag) {
  const std::vector<std::string_view> parts = split(text, ';');
  if (parts.size() != 4) {
    throw CLI::ValidationError(
        flag,
        "expected four x,y,z separated by ';' (p00;p10;p11;p01), got '" + std::string(text) + "'");
  }
  std::array<Vec3, 4> corners;
  for (int i = 0; i < 4; ++i) corners[i] = parse_vec3(parts[i], flag);
  return corners;
}

Vec3 parse_up(std::string_view text) {
  static constexpr std::pair<std::string_view, Vec3> kAxes[] = {
      {"x", {1, 0, 0}},   {"y", {0, 1, 0}},   {"z", {0, 0, 1}},
      {"+x", {1, 0, 0}},  {"+y", {0, 1, 0}},  {"+z", {0, 0, 1}},
      {"-x", {-1, 0, 0}}, {"-y", {0, -1, 0}}, {"-z", {0, 0, -1}}};
  for (const auto& [name, v] : kAxes) {
    if (text == name) return v;
  }
  throw CLI::ValidationError("--up",
                             "expected x, y, z, -x, -y or -z, got '" + std::string(text) + "'");
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

Error usage(const std::string& message) {
  return make_error(ErrorCode::kInvalidArgument, message);
}

std::vector<std::string> required_flags(ProxyKind kind) {
  switch (kind) {
    case ProxyKind::kSphere:
      return {"--center", "--radius"};
    case ProxyKind::kCylinder:
      return {"--base", "--radius", "--height"};
    case ProxyKind::kCone:
      return {"--apex", "--height", "--radius"};
    case ProxyKind::kDisk:
      return {"--center", "--radius"};
    case ProxyKind::kQuad:
      return {"--corners"};
    case ProxyKind::kPlane:
      return {"--origin", "--u-axis", "--v-axis"};
  }
  return {};
}

// Writes the given flags over `p`, one overload per kind.
void overlay(const GeometryFlags& f, SphereParams& p) {
  if (f.center) p.center = *f.center;
  if (f.radius) p.radius = *f.radius;
  if (f.pole) p.pole = *f.pole;
  if (f.equator) p.equator = f.equator;
}
void overlay(const GeometryFlags& f, CylinderParams& p) {
  if (f.base) p.base = *f.base;
  if (f.axis) p.axis = *f.axis;
  if (f.equator) p.equator = f.equator;
  if (f.radius) p.radius = *f.radius;
  if (f.height) p.height = *f.height;
}
void overlay(const GeometryFlags& f, ConeParams& p) {
  if (f.apex) p.apex = *f.apex;
  if (f.axis) p.axis = *f.axis;
  if (f.equator) p.equator = f.equator;
  if (f.height) p.height = *f.height;
  if (f.radius) p.radius = *f.radius;
}
void overlay(const GeometryFlags& f, DiskParams& p) {
  if (f.center) p.center = *f.center;
  if (f.normal) p.normal = *f.normal;
  if (f.equator) p.equator = f.equator;
  if (f.radius) p.radius = *f.radius;
}
void overlay(const GeometryFlags& f, QuadParams& p) {
  if (f.corners) p.corners = *f.corners;
}
void overlay(const GeometryFlags& f, PlaneParams& p) {
  if (f.origin) p.origin = *f.origin;
  if (f.u_axis) p.u_axis = *f.u_axis;
  if (f.v_axis) p.v_axis = *f.v_axis;
}

}  // namespace

Vec3 parse_vec3_flag(std::string_view text, const std::string& flag) {
  return parse_vec3(text, flag);
}
double parse_number_flag(std::string_view text, const std::string& flag) {
  return parse_number(text, flag);
}

void add_geometry_flags(CLI::App& command, GeometryFlags& flags) {
  CLI::Option* kind = command.add_option_function<std::string>(
      "--proxy",
      [&flags](const std::string& name) {
        flags.kind = parse_proxy_kind(name);
        if (!flags.kind) {
          throw CLI::ValidationError("--proxy", "unknown proxy kind '" + name +
                                                    "' (expected sphere, cylinder, cone, disk, "
                                                    "quad or plane)");
        }
      },
      "proxy shape: sphere, cylinder, cone, disk, quad or plane");
  kind->type_name("KIND");
  CLI::Option* file = command.add_option_function<std::string>(
      "--proxy-file", [&flags](const std::string& path) { flags.proxy_file = path; },
      "read the proxy from a JSON file (as written by texbake fit) instead of --proxy and "
      "geometry flags");
  file->type_name("FILE");
  file->excludes(kind);

  for (const VectorFlag& f : kVectorFlags) {
    const std::string name = f.name;
    const Vec3Member member = f.member;
    command
        .add_option_function<std::string>(
            name,
            [&flags, name, member](const std::string& s) { flags.*member = parse_vec3(s, name); },
            f.help)
        ->type_name("X,Y,Z");
  }
  for (const NumberFlag& f : kNumberFlags) {
    const std::string name = f.name;
    const NumberMember member = f.member;
    command
        .add_option_function<std::string>(
            name,
            [&flags, name, member](const std::string& s) { flags.*member = parse_number(s, name); },
            f.help)
        ->type_name("NUMBER");
  }
  command
      .add_option_function<std::string>(
          "--corners",
          [&flags](const std::string& s) { flags.corners = parse_corners(s, "--corners"); },
          "quad corners p00;p10;p11;p01 (u runs p00 -> p10, v runs p00 -> p01; convex, planar)")
      ->type_name("X,Y,Z;X,Y,Z;X,Y,Z;X,Y,Z");
  command
      .add_option_function<std::string>(
          "--up", [&flags](const std::string& s) { flags.up = parse_up(s); },
          "default pole/axis/normal: x, y, z, -x, -y or -z (default z)")
      ->type_name("AXIS");
}

Vec3 up_direction(const GeometryFlags& flags) {
  return flags.up.value_or(Vec3{0, 0, 1});
}

std::vector<std::string> given_geometry_flags(const GeometryFlags& flags) {
  std::vector<std::string> given;
  for (const VectorFlag& f : kVectorFlags) {
    if (flags.*(f.member)) given.push_back(f.name);
  }
  for (const NumberFlag& f : kNumberFlags) {
    if (flags.*(f.member)) given.push_back(f.name);
  }
  if (flags.corners) given.push_back("--corners");
  if (flags.up) given.push_back("--up");
  return given;
}

std::vector<std::string> flags_of_kind(ProxyKind kind) {
  switch (kind) {
    case ProxyKind::kSphere:
      return {"--center", "--radius", "--pole", "--equator", "--up"};
    case ProxyKind::kCylinder:
      return {"--base", "--axis", "--equator", "--radius", "--height", "--up"};
    case ProxyKind::kCone:
      return {"--apex", "--axis", "--equator", "--height", "--radius", "--up"};
    case ProxyKind::kDisk:
      return {"--center", "--normal", "--equator", "--radius", "--up"};
    case ProxyKind::kQuad:
      return {"--corners"};
    case ProxyKind::kPlane:
      return {"--origin", "--u-axis", "--v-axis"};
  }
  return {};
}

std::vector<std::string> missing_geometry_flags(const GeometryFlags& flags, ProxyKind kind) {
  const std::vector<std::string> given = given_geometry_flags(flags);
  std::vector<std::string> missing;
  for (const std::string& f : required_flags(kind)) {
    if (std::find(given.begin(), given.end(), f) == given.end()) missing.push_back(f);
  }
  return missing;
}

Status check_geometry_flags(const GeometryFlags& flags, bool require_proxy) {
  const std::vector<std::string> given = given_geometry_flags(flags);
  if (flags.kind && flags.proxy_file) return usage("--proxy and --proxy-file exclude each other");
  if (flags.proxy_file && !given.empty()) {
    return usage(given.front() +
                 " cannot be combined with --proxy-file (the file holds the "
                 "whole proxy)");
  }
  if (!flags.kind && !flags.proxy_file) {
    if (require_proxy) return usage("missing --proxy KIND or --proxy-file FILE");
    if (!given.empty()) return usage(given.front() + " needs --proxy KIND");
    return ok_status();
  }
  if (flags.kind) {
    const std::vector<std::string> allowed = flags_of_kind(*flags.kind);
    for (const std::string& f : given) {
      if (std::find(allowed.begin(), allowed.end(), f) == allowed.end()) {
        return usage(f + " does not apply to --proxy " + to_string(*flags.kind) +
                     " (its flags: " + join(allowed) + ")");
      }
    }
  }
  return ok_status();
}

Expected<ProxyParams> params_from_flags(const GeometryFlags& flags, ProxyKind kind) {
  const std::vector<std::string> missing = missing_geometry_flags(flags, kind);
  if (!missing.empty()) {
    return usage("missing " + missing.front() + " for --proxy " + to_string(kind) + " (needs " +
                 join(required_flags(kind)) + ")");
  }
  const Vec3 up = up_direction(flags);
  ProxyParams params;
  switch (kind) {
    case ProxyKind::kSphere:
      params = SphereParams{Vec3{}, 1, up, std::nullopt};
      break;
    case ProxyKind::kCylinder:
      params = CylinderParams{Vec3{}, up, std::nullopt, 1, 1};
      break;
    case ProxyKind::kCone:
      params = ConeParams{Vec3{}, up, std::nullopt, 1, 1};
      break;
    case ProxyKind::kDisk:
      params = DiskParams{Vec3{}, up, std::nullopt, 1};
      break;
    case ProxyKind::kQuad:
      params = QuadParams{};
      break;
    case ProxyKind::kPlane:
      params = PlaneParams{};
      break;
  }
  // Every required value is given, so the placeholders above are overwritten.
  std::visit([&](auto& p) { overlay(flags, p); }, params);
  return params;
}

Expected<ProxyParams> merge_flags(const GeometryFlags& flags, ProxyParams fitted) {
  if (flags.kind && kind_of(fitted) != *flags.kind) {
    return usage(std::string("fitted proxy is a ") + to_string(kind_of(fitted)) +
                 ", not the --proxy " + to_string(*flags.kind));
  }
  std::visit([&](auto& p) { overlay(flags, p); }, fitted);
  return fitted;
}

Expected<Proxy> proxy_from_flags(const GeometryFlags& flags) {
  if (Status s = check_geometry_flags(flags, /*require_proxy=*/true); !s) return s.error();
  if (flags.proxy_file) return read_proxy_file(*flags.proxy_file);
  Expected<ProxyParams> params = params_from_flags(flags, *flags.kind);
  if (!params) return params.error();
  return make_proxy(*params, ParamNaming::kFlag);
}

}  // namespace texbake::cli
