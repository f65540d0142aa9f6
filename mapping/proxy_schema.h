// The one definition of each proxy kind's parameters (issue #10): one table
// per kind listing every field's JSON key, command-line flag, value type,
// role and whether it must be given. The JSON reader and writer
// (mesh_io/proxy_json), the geometry flags (bake/cli/geometry_flags) and
// completion by fitting (bake/fit/complete_proxy) are all driven by it, so a
// parameter is named, typed and documented in exactly one place.
//
// The tables (SPEC section 2's keys and order, SPEC section 5's flags):
//   kind      field    flag      type     role        required
//   sphere    center   --center  vec3     anchor      yes
//             radius   --radius  number   extent      yes
//             pole     --pole    vec3     direction   no (--up)
//             equator  --equator vec3     equator     no
//   cylinder  base     --base    vec3     anchor      yes
//             axis     --axis    vec3     axis        no (--up)
//             equator  --equator vec3     equator     no
//             radius   --radius  number   extent      yes
//             height   --height  number   extent      yes
//   cone      apex     --apex    vec3     anchor      yes
//             axis     --axis    vec3     axis        no (--up)
//             equator  --equator vec3     equator     no
//             height   --height  number   cone height yes
//             radius   --radius  number   extent      yes
//   disk      center   --center  vec3     anchor      yes
//             normal   --normal  vec3     direction   no (--up)
//             equator  --equator vec3     equator     no
//             radius   --radius  number   extent      yes
//   quad      corners  --corners corners  extent      yes
//   plane     origin   --origin  vec3     anchor      yes
//             u_axis   --u-axis  vec3     extent      yes
//             v_axis   --v-axis  vec3     extent      yes
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

// What a field is to completion by fitting (bake/fit/complete_proxy.h, whose
// FitOptions come from these roles).
enum class ParamRole {
  kAnchor,      // the proxy's fixed point (sphere/disk centre, cylinder base,
                // cone apex, plane origin): the fit re-fits the rest around it
  kDirection,   // sphere pole, disk normal: given, the fit's fixed direction
                // (sign kept); defaults to `up` when nothing is fitted
  kAxis,        // cylinder/cone axis: as kDirection, and when not given but
                // `up` is, `up` fixes the fitted axis' line (not its sign)
  kEquator,     // u = 0 reference: optional everywhere (mapping/proxy.h rule)
  kExtent,      // a radius, a cylinder's height, a plane axis, the quad's
                // corners: replaces the fitted value, nothing depending on it
  kConeHeight,  // the cone's height: passed to the fit (base plane placed there)
};

// A pole, axis or normal: defaults to `up` when not given.
constexpr bool is_direction(ParamRole role) {
  return role == ParamRole::kDirection || role == ParamRole::kAxis;
}

// A parameter as the user names it, the same in every kind that has it (a
// sphere's and a disk's --center are one flag with one --help line).
struct GeometryParam {
  std::string_view key;   // JSON key, e.g. "u_axis"
  std::string_view flag;  // command-line flag, e.g. "--u-axis"
  ParamType type;
  std::string_view help;  // the flag's one line for --help (names the kinds)
};

// One field of one kind's table: its parameter and what it is to that kind.
struct ParamField {
  std::string_view key;   // JSON key, e.g. "u_axis"
  std::string_view flag;  // command-line flag, e.g. "--u-axis"
  ParamType type;
  ParamRole role;
  bool required;          // must be given for a proxy without a fit (directions
                          // default to `up`, the equator to mapping/proxy.h's rule)
  std::string_view help;  // the parameter's --help line (GeometryParam::help)
};

// The fields of `kind`, in SPEC section 2's order (the JSON writer's order).
std::span<const ParamField> proxy_fields(ProxyKind kind);

// Every parameter of every kind, each once, in the order the command line
// registers and lists its flags (its --help order: the vectors --center
// --pole --equator --axis --apex --base --normal --origin --u-axis --v-axis,
// then --radius --height, then --corners).
std::span<const GeometryParam> geometry_params();

// The field of `kind` with this key (nullptr if none).
const ParamField* find_field(ProxyKind kind, std::string_view key);

// The field's name in messages: its key or its flag.
std::string_view field_name(const ParamField& field, ParamNaming naming);

using ParamValue = std::variant<double, Vec3, std::array<Vec3, 4>>;
using ParamValues = std::map<std::string, ParamValue, std::less<>>;  // by key

// The alternative of ParamValue that holds a value of `type`.
bool holds_type(const ParamValue& value, ParamType type);

struct ProxySpec {
  ProxyKind kind = ProxyKind::kSphere;
  ParamValues values;  // the given fields, by key
  // The default direction (pole/axis/normal) and the fit's up hint; +Z when
  // not set (SPEC section 5, --up).
  std::optional<Vec3> up;
};

// Keys of the required fields `spec` does not give, in field order
// (directions default to `up` and the equator to mapping/proxy.h's rule, so
// those are never missing). Empty: params_from_spec succeeds without a fit.
// Keys that are not fields of spec.kind are ignored here.
std::vector<std::string> missing_fields(const ProxySpec& spec);

// Structural errors of `spec` (kInvalidArgument, naming the key or flag as
// `naming` says): a key that is not a field of spec.kind, or a value of the
// wrong type for its key.
Status check_spec_keys(const ProxySpec& spec, ParamNaming naming = ParamNaming::kKey);

// check_spec_keys, then every given value make_proxy would reject whatever
// the other fields are (so it can be reported before a fit): a non-finite
// point or corner; a zero or non-finite pole, axis, normal, equator or plane
// axis; a radius or height that is not a finite number > 0; a zero or
// non-finite `up`. Messages as make_proxy's ("cone: height must be a finite
// number > 0 (got 0)", "cylinder: --axis is the zero vector"). A complete
// spec's combination (an equator parallel to the axis, a non-convex quad...)
// is make_proxy's to check.
Status check_given_values(const ProxySpec& spec, ParamNaming naming = ParamNaming::kKey);

// ProxyParams of a complete spec: a direction not given is `up` (+Z when not
// set), an equator not given stays absent. Errors (kInvalidArgument, names as
// `naming` says): check_spec_keys's, the first missing field ("cylinder:
// missing base (needs base, radius, height)"), a zero or non-finite `up`
// used as a default direction. Values are not validated: see make_proxy.
Expected<ProxyParams> params_from_spec(const ProxySpec& spec,
                                       ParamNaming naming = ParamNaming::kKey);

// Every field of `params` (the equator when set); `up` not set.
ProxySpec spec_from_params(const ProxyParams& params);

// `params` with every value `spec` gives written over it (`up` is not
// applied). Errors (kInvalidArgument): check_spec_keys's, or `params` not
// of spec.kind.
Expected<ProxyParams> merge_spec(const ProxySpec& spec, ProxyParams params,
                                 ParamNaming naming = ParamNaming::kKey);

}  // namespace texbake
