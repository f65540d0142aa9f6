// Completing the geometry flags from a fit (see fit_geometry.h).
#include "bake/cli/fit_geometry.h"

#include <algorithm>

#include "mesh_io/proxy_json.h"

namespace texbake::cli {

FitOptions fit_options_from_flags(const GeometryFlags& flags, ProxyKind kind) {
  FitOptions options;
  options.up = up_direction(flags);
  std::optional<Vec3> given;
  switch (kind) {
    case ProxyKind::kSphere:
      given = flags.pole;
      break;
    case ProxyKind::kCylinder:
    case ProxyKind::kCone:
      given = flags.axis;
      break;
    case ProxyKind::kDisk:
    case ProxyKind::kQuad:
    case ProxyKind::kPlane:
      given = flags.normal;
      break;
  }
  // The proxy's fixed point and the cone's height: the fit re-fits the
  // rest around them (fit_proxy.h, FitOptions::anchor).
  switch (kind) {
    case ProxyKind::kSphere:
    case ProxyKind::kDisk:
      options.anchor = flags.center;
      break;
    case ProxyKind::kCylinder:
      options.anchor = flags.base;
      break;
    case ProxyKind::kCone:
      options.anchor = flags.apex;
      options.height = flags.height;
      break;
    case ProxyKind::kPlane:
      options.anchor = flags.origin;
      break;
    case ProxyKind::kQuad:
      break;
  }
  if (given) {
    options.axis = given;
    options.keep_axis_sign = true;
  } else if (flags.up && (kind == ProxyKind::kCylinder || kind == ProxyKind::kCone)) {
    // --up is the shorthand for the default axis (SPEC section 5).
    options.axis = flags.up;
    options.keep_axis_sign = false;
  }
  return options;
}

Expected<ResolvedProxy> resolve_proxy(const GeometryFlags& flags, const MeshData& mesh,
                                      const std::string& mesh_name, std::ostream* log) {
  if (Status s = check_geometry_flags(flags, /*require_proxy=*/true); !s) return s.error();
  if (flags.proxy_file) {
    Expected<Proxy> proxy = read_proxy_file(*flags.proxy_file);
    if (!proxy) return proxy.error();
    return ResolvedProxy{std::move(*proxy), {}};
  }
  const ProxyKind kind = *flags.kind;
  if (missing_geometry_flags(flags, kind).empty()) {
    Expected<Proxy> proxy = proxy_from_flags(flags);
    if (!proxy) return proxy.error();
    return ResolvedProxy{std::move(*proxy), {}};
  }

  const std::vector<Float3> points = fit_points(mesh);
  Expected<ProxyParams> fitted = fit_proxy(kind, points, fit_options_from_flags(flags, kind));
  if (!fitted) {
    // The mesh's shape, not the command line, is at fault: exit 1.
    return make_error(ErrorCode::kParse, mesh_name + ": " + fitted.error().message);
  }
  Expected<ProxyParams> merged = merge_flags(flags, std::move(*fitted));
  if (!merged) return merged.error();
  Expected<Proxy> proxy = make_proxy(*merged, ParamNaming::kFlag);
  if (!proxy) {
    return make_error(proxy.error().code,
                      "the fitted " + std::string(to_string(kind)) +
                          " with the given flags is invalid: " + proxy.error().message);
  }
  // Every flag of the kind not given came from the fit (directions too).
  const std::vector<std::string> given = given_geometry_flags(flags);
  std::vector<std::string> filled;
  for (const std::string& f : flags_of_kind(kind)) {
    if (f != "--up" && std::find(given.begin(), given.end(), f) == given.end()) filled.push_back(f);
  }
  if (log) {
    std::string names;
    for (const std::string& f : filled) names += (names.empty() ? "" : " ") + f;
    *log << "texbake: fitted " << to_string(kind) << " (" << names << ") to " << points.size()
         << " vertices of " << mesh_name << ": " << proxy_to_json(*proxy) << "\n";
  }
  return ResolvedProxy{std::move(*proxy), std::move(filled)};
}

}  // namespace texbake::cli
