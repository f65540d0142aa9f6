// The geometry options of SPEC section 5 (the job options of a proxy,
// texbake/job_options.h; the command line's map, bake, fit and render): --proxy KIND | --proxy-file
// F, --center --radius --pole --equator
// --axis --apex --height --base --normal --corners --origin --u-axis --v-axis,
// and --up x|y|z|-x|-y|-z (the default pole/axis/normal; default z). The
// geometry flags, their types, help lines and which kinds take them come from
// the parameter tables of mapping/proxy_schema.h.
//
// Values are checked as they are set (set_geometry_option): vectors "x,y,z",
// corners four "x,y,z" separated by ';', numbers finite (no nan, inf,
// garbage or overflow). A bad value is a kInvalidArgument error naming the
// flag (exit 2).
//
// Contract of the combination (check_geometry_flags): --proxy and
// --proxy-file exclude each other; with --proxy-file no geometry flag is
// allowed (the file holds the whole proxy); with --proxy KIND only the flags
// of KIND (flags_of_kind) are allowed.
#pragma once

#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapping/error.h"
#include "mapping/projector.h"
#include "mapping/proxy.h"
#include "mapping/proxy_schema.h"

namespace texbake {

struct GeometryFlags {
  std::optional<ProxyKind> kind;                    // --proxy
  std::optional<std::filesystem::path> proxy_file;  // --proxy-file
  // The geometry flags given, by the key of their parameter (--u-axis is
  // "u_axis"; mapping/proxy_schema.h), each of its parameter's type.
  ParamValues values;
  std::optional<Vec3> up;  // --up as a unit vector (+-X, +-Y, +-Z)
};

// The parsers of the values: a finite number, "x,y,z", four "x,y,z"
// separated by ';'. Errors (kInvalidArgument) start with "FLAG: ".
Expected<double> parse_number_option(std::string_view text, const std::string& flag);
Expected<Vec3> parse_vec3_option(std::string_view text, const std::string& flag);
Expected<std::array<Vec3, 4>> parse_corners_option(std::string_view text, const std::string& flag);

// Sets one geometry option by its flag ("--proxy", "--proxy-file", a
// parameter of geometry_params() such as "--u-axis", or "--up") from its
// text. Errors (kInvalidArgument) name the flag: an unknown proxy kind, a
// bad number or vector, an --up other than x, y, z, -x, -y, -z.
Status set_geometry_option(GeometryFlags& flags, std::string_view flag, std::string_view text);

// The type name of a geometry parameter in --help ("X,Y,Z", "NUMBER", ...).
const char* geometry_type_name(ParamType type);

// --up, or +Z when not given.
Vec3 up_direction(const GeometryFlags& flags);

// The geometry flags given (not --proxy/--proxy-file), as "--center", ...,
// in geometry_params()'s order, then --up.
std::vector<std::string> given_geometry_flags(const GeometryFlags& flags);

// The flags a kind uses, in its table's order (proxy_fields), then --up if
// the kind has a pole/axis/normal; e.g. sphere: --center --radius --pole
// --equator --up.
std::vector<std::string> flags_of_kind(ProxyKind kind);

// The flags a kind needs that were not given (missing_fields: pole/axis/
// normal default to --up and equator to the rule of mapping/proxy.h, so they
// are never missing). A fit fills these from the mesh.
std::vector<std::string> missing_geometry_flags(const GeometryFlags& flags, ProxyKind kind);

// The spec the flags give: --proxy's kind, the given values, --up.
// Precondition: flags.kind is set.
ProxySpec spec_from_flags(const GeometryFlags& flags);

// Checks the combination (see the file comment). Errors: kInvalidArgument.
// `require_proxy`: one of --proxy / --proxy-file must be given. With
// --proxy KIND and a required flag missing (the rest is to be fitted), the
// given values are checked too, before any mesh is read:
// check_given_values names the flag of a zero --pole/--axis/--normal/
// --equator/--u-axis/--v-axis or a --radius/--height <= 0 (e.g. "cone:
// --height must be a finite number > 0 (got 0)"). A complete set of flags is
// validated by make_proxy instead (proxy_from_flags).
Status check_geometry_flags(const GeometryFlags& flags, bool require_proxy);

// ProxyParams of `kind` from the flags alone (params_from_spec: directions
// default to --up); the error (kInvalidArgument) names the first missing
// flag: "missing --base for --proxy cylinder (needs --base, --radius,
// --height)". Not validated: see make_proxy.
Expected<ProxyParams> params_from_flags(const GeometryFlags& flags, ProxyKind kind);

// `fitted` (e.g. from texbake fit) with every given geometry flag written
// over it (merge_spec). --up is not applied (fit takes it as its axis hint).
// Error (kInvalidArgument) if `fitted` is not of the --proxy kind, or a
// given flag is not one of its kind's.
Expected<ProxyParams> merge_flags(const GeometryFlags& flags, ProxyParams fitted);

// The whole path for commands that do not fit: check_geometry_flags's
// combination checks (not the value checks, which are for a fit: a missing
// flag is reported first), then read --proxy-file (errors kIo/kParse: exit 1, naming file and key)
// or build from the flags and validate with make_proxy (errors kInvalidArgument: exit 2, naming the
// flag).
Expected<Proxy> proxy_from_flags(const GeometryFlags& flags);
// The same for commands that also take a camera: a --proxy-file may hold a
// camera ("kind":"camera", SPEC section 9).
Expected<Projector> projector_from_flags(const GeometryFlags& flags);

}  // namespace texbake
