#include "texbake/geometry_options.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string_view>

#include "mesh_io/proxy_json.h"

namespace texbake {

namespace {

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

Error usage(const std::string& message) {
  return make_error(ErrorCode::kInvalidArgument, message);
}

// "FLAG: WHY", as the command line's parser words a bad value.
Error bad_value(const std::string& flag, const std::string& why) {
  return usage(flag + ": " + why);
}

Expected<Vec3> parse_up(std::string_view text) {
  static constexpr std::pair<std::string_view, Vec3> kAxes[] = {
      {"x", {1, 0, 0}},   {"y", {0, 1, 0}},   {"z", {0, 0, 1}},
      {"+x", {1, 0, 0}},  {"+y", {0, 1, 0}},  {"+z", {0, 0, 1}},
      {"-x", {-1, 0, 0}}, {"-y", {0, -1, 0}}, {"-z", {0, 0, -1}}};
  for (const auto& [name, v] : kAxes) {
    if (text == name) return v;
  }
  return bad_value("--up", "expected x, y, z, -x, -y or -z, got '" + std::string(text) + "'");
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const std::string& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

// The value of a flag of `type`, parsed from its text.
Expected<ParamValue> parse_value(ParamType type, std::string_view text, const std::string& flag) {
  switch (type) {
    case ParamType::kVec3: {
      Expected<Vec3> v = parse_vec3_option(text, flag);
      if (!v) return v.error();
      return ParamValue{*v};
    }
    case ParamType::kNumber: {
      Expected<double> v = parse_number_option(text, flag);
      if (!v) return v.error();
      return ParamValue{*v};
    }
    case ParamType::kCorners: {
      Expected<std::array<Vec3, 4>> v = parse_corners_option(text, flag);
      if (!v) return v.error();
      return ParamValue{*v};
    }
  }
  return bad_value(flag, "has an unknown type");
}

}  // namespace

const char* geometry_type_name(ParamType type) {
  switch (type) {
    case ParamType::kVec3:
      return "X,Y,Z";
    case ParamType::kNumber:
      return "NUMBER";
    case ParamType::kCorners:
      return "X,Y,Z;X,Y,Z;X,Y,Z;X,Y,Z";
  }
  return "VALUE";
}

namespace {

ProxySpec spec_of_kind(const GeometryFlags& flags, ProxyKind kind) {
  return ProxySpec{kind, flags.values, flags.up};
}

// The flags of `keys` (fields of `kind`).
std::vector<std::string> flags_of_keys(ProxyKind kind, const std::vector<std::string>& keys) {
  std::vector<std::string> flags;
  for (const std::string& key : keys) flags.emplace_back(find_field(kind, key)->flag);
  return flags;
}

// check_geometry_flags without the value checks.
Status check_combination(const GeometryFlags& flags, bool require_proxy) {
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

}  // namespace

// std::from_chars: locale-independent, and it reports overflow, where
// strtod would give inf and a stream would accept "nan".
Expected<double> parse_number_option(std::string_view text, const std::string& flag) {
  const std::string_view t = trim(text);
  double x = 0;
  const char* first = t.data();
  if (!t.empty() && t.front() == '+') ++first;  // from_chars rejects a leading '+'
  const auto [end, ec] = std::from_chars(first, t.data() + t.size(), x);
  if (ec == std::errc::result_out_of_range) {
    return bad_value(flag, "'" + std::string(text) + "' is out of range (not finite)");
  }
  if (t.empty() || ec != std::errc() || end != t.data() + t.size()) {
    return bad_value(flag, "'" + std::string(text) + "' is not a number");
  }
  if (!std::isfinite(x))
    return bad_value(flag, "'" + std::string(text) + "' is not a finite number");
  return x;
}

Expected<Vec3> parse_vec3_option(std::string_view text, const std::string& flag) {
  const std::vector<std::string_view> parts = split(text, ',');
  if (parts.size() != 3) {
    return bad_value(flag, "expected x,y,z (three numbers), got '" + std::string(text) + "'");
  }
  double c[3];
  for (int i = 0; i < 3; ++i) {
    Expected<double> x = parse_number_option(parts[i], flag);
    if (!x) return x.error();
    c[i] = *x;
  }
  return Vec3{c[0], c[1], c[2]};
}

Expected<std::array<Vec3, 4>> parse_corners_option(std::string_view text, const std::string& flag) {
  const std::vector<std::string_view> parts = split(text, ';');
  if (parts.size() != 4) {
    return bad_value(flag, "expected four x,y,z separated by ';' (p00;p10;p11;p01), got '" +
                               std::string(text) + "'");
  }
  std::array<Vec3, 4> corners;
  for (int i = 0; i < 4; ++i) {
    Expected<Vec3> c = parse_vec3_option(parts[i], flag);
    if (!c) return c.error();
    corners[i] = *c;
  }
  return corners;
}

Status set_geometry_option(GeometryFlags& flags, std::string_view flag, std::string_view text) {
  if (flag == "--proxy") {
    flags.kind = parse_proxy_kind(text);
    if (!flags.kind) {
      return bad_value("--proxy", "unknown proxy kind '" + std::string(text) +
                                      "' (expected sphere, cylinder, cone, disk, quad or plane)");
    }
    return ok_status();
  }
  if (flag == "--proxy-file") {
    flags.proxy_file = std::filesystem::path(std::string(text));
    return ok_status();
  }
  if (flag == "--up") {
    Expected<Vec3> up = parse_up(text);
    if (!up) return up.error();
    flags.up = *up;
    return ok_status();
  }
  for (const GeometryParam& p : geometry_params()) {
    if (p.flag != flag) continue;
    Expected<ParamValue> v = parse_value(p.type, text, std::string(flag));
    if (!v) return v.error();
    flags.values.insert_or_assign(std::string(p.key), std::move(*v));
    return ok_status();
  }
  return usage(std::string(flag) + " is not a geometry option");
}

Vec3 up_direction(const GeometryFlags& flags) {
  return flags.up.value_or(Vec3{0, 0, 1});
}

std::vector<std::string> given_geometry_flags(const GeometryFlags& flags) {
  std::vector<std::string> given;
  for (const GeometryParam& p : geometry_params()) {
    if (flags.values.contains(p.key)) given.emplace_back(p.flag);
  }
  if (flags.up) given.push_back("--up");
  return given;
}

std::vector<std::string> flags_of_kind(ProxyKind kind) {
  std::vector<std::string> flags;
  bool has_direction = false;
  for (const ParamField& f : proxy_fields(kind)) {
    flags.emplace_back(f.flag);
    has_direction |= is_direction(f.role);
  }
  if (has_direction) flags.push_back("--up");
  return flags;
}

std::vector<std::string> missing_geometry_flags(const GeometryFlags& flags, ProxyKind kind) {
  return flags_of_keys(kind, missing_fields(spec_of_kind(flags, kind)));
}

ProxySpec spec_from_flags(const GeometryFlags& flags) {
  return spec_of_kind(flags, flags.kind.value());
}

Status check_geometry_flags(const GeometryFlags& flags, bool require_proxy) {
  if (Status s = check_combination(flags, require_proxy); !s) return s;
  if (flags.kind && !missing_geometry_flags(flags, *flags.kind).empty()) {
    return check_given_values(spec_from_flags(flags), ParamNaming::kFlag);
  }
  return ok_status();
}

Expected<ProxyParams> params_from_flags(const GeometryFlags& flags, ProxyKind kind) {
  const std::vector<std::string> missing = missing_geometry_flags(flags, kind);
  if (!missing.empty()) {
    std::vector<std::string> required;
    for (const ParamField& f : proxy_fields(kind)) {
      if (f.required) required.emplace_back(f.flag);
    }
    return usage("missing " + missing.front() + " for --proxy " + to_string(kind) + " (needs " +
                 join(required) + ")");
  }
  return params_from_spec(spec_of_kind(flags, kind), ParamNaming::kFlag);
}

Expected<ProxyParams> merge_flags(const GeometryFlags& flags, ProxyParams fitted) {
  if (flags.kind && kind_of(fitted) != *flags.kind) {
    return usage(std::string("fitted proxy is a ") + to_string(kind_of(fitted)) +
                 ", not the --proxy " + to_string(*flags.kind));
  }
  return merge_spec(spec_of_kind(flags, kind_of(fitted)), std::move(fitted), ParamNaming::kFlag);
}

Expected<Projector> projector_from_flags(const GeometryFlags& flags) {
  if (Status s = check_combination(flags, /*require_proxy=*/true); !s) return s.error();
  if (flags.proxy_file) return read_projector_file(*flags.proxy_file);
  Expected<Proxy> proxy = proxy_from_flags(flags);
  if (!proxy) return proxy.error();
  return Projector{*proxy};
}

Expected<Proxy> proxy_from_flags(const GeometryFlags& flags) {
  if (Status s = check_combination(flags, /*require_proxy=*/true); !s) return s.error();
  if (flags.proxy_file) return read_proxy_file(*flags.proxy_file);
  Expected<ProxyParams> params = params_from_flags(flags, *flags.kind);
  if (!params) return params.error();
  return make_proxy(*params, ParamNaming::kFlag);
}

}  // namespace texbake
