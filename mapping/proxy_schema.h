// The one definition of each proxy kind's parameters (issue #10): one table
// per kind listing every field's JSON key, command-line flag, value type,
// role and whether it must be given. The JSON reader and writer
// (mesh_io/proxy_json), the geometry flags (bake/cli/geometry_flags) and
// completion by fitting (bake/fit/complete_proxy) are all driven by it, so a
// parameter is named, typed and documented in exactly one place.
//
// A ProxySpec is a proxy as a user gives it: a kind and the values of some of
// its fields (by key). params_from_spec turns a complete spec into
// ProxyParams; spec_from_params is its inverse (every field present).
#pragma once

#include <array>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mapping/vec.h"

namespace texbake {

enum class ParamType {
  kVec3,     // [x, y, z] / "x,y,z"
  kNumber,   // a finite number
  kCorners,  // four Vec3: [[..] x 4] / "x,y,z;x,y,z;x,y,z;x,y,z"
};

// What a field is to completion by fitting (bake/fit/fit_proxy.h FitOptions).
enum class ParamRole {
  kAnchor,      // the proxy's fixed point (sphere/disk centre, cylinder base,
                // cone apex, plane origin): the fit re-fits the rest around it
  kDirection,   // pole / axis / normal: the fit's fixed direction (sign kept);
                // defaults to --up when not given and nothing is fitted
  kEquator,     // u = 0 reference: optional everywhere (mapping/proxy.h rule)
  kExtent,      // a radius, a height, a plane axis, the quad's corners: replaces
                // the fitted value, nothing depending on it
  kConeHeight,  // the cone's height: passed to the fit (base plane placed there)
};

struct ParamField {
  std::string_view key;   // JSON key, e.g. "u_axis"
  std::string_view flag;  // command-line flag, e.g. "--u-axis"
  ParamType type;
  ParamRole role;
  bool required;          // must be given (after --up defaults) for a proxy without a fit
  std::string_view help;  // one line for --help
};

// The fields of `kind`, in SPEC section 2's order (the JSON writer's order).
std::span<const ParamField> proxy_fields(ProxyKind kind);

// Every flag of every kind, each once, in SPEC section 5's order (for
// registering the geometry flags); the field's help names the kinds.
std::span<const ParamField> all_geometry_fields();

// The field of `kind` with this key (nullptr if none).
const ParamField* find_field(ProxyKind kind, std::string_view key);

using ParamValue = std::variant<double, Vec3, std::array<Vec3, 4>>;

struct ProxySpec {
  ProxyKind kind = ProxyKind::kSphere;
  std::map<std::string, ParamValue, std::less<>> values;  // by key
  // The default direction (pole/axis/normal) and the fit's up hint; +Z when
  // not set (SPEC section 5, --up).
  std::optional<Vec3> up;
};

// Keys of the fields `spec` needs that it does not give (directions default
// to `up` and the equator to mapping/proxy.h's rule, so those are never
// missing). Empty: params_from_spec succeeds without a fit.
std::vector<std::string> missing_fields(const ProxySpec& spec);

// ProxyParams of a complete spec (kInvalidArgument naming the first missing
// field, or a value of the wrong type for its key). Not validated: see
// make_proxy.
Expected<ProxyParams> params_from_spec(const ProxySpec& spec);

// Every field of `params` (the equator when set).
ProxySpec spec_from_params(const ProxyParams& params);

}  // namespace texbake
