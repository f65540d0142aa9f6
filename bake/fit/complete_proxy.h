// Completing a proxy spec by fitting (SPEC sections 5 and 6): every field of
// a ProxySpec (mapping/proxy_schema.h) not given is fitted to the mesh
// (bake/fit/fit_proxy.h), the given ones are kept. The rules follow the
// fields' roles in the schema's tables:
//  - a given direction (kDirection: sphere pole, disk normal; kAxis:
//    cylinder/cone axis) is the fit's fixed direction, with its sign, and the
//    rest is fitted around it;
//  - without a given axis, spec.up (when set) fixes a cylinder's or cone's
//    axis line (kAxis; the sign still comes from the fit: the cone's apex
//    side); it is also the sphere's pole and the hemisphere of fitted normals
//    (FitOptions::up), as in `texbake fit --up`;
//  - a given anchor (kAnchor: sphere/disk centre, cylinder base, cone apex,
//    plane origin) and a cone's height (kConeHeight) are passed to the fit,
//    which fits the remaining values around them (FitOptions::anchor/height:
//    e.g. a sphere's radius then encloses the mesh around the given centre);
//  - other given values (kExtent: a radius, a cylinder's height, a plane's
//    u_axis/v_axis; kEquator) replace the fitted ones, nothing depending on
//    them.
// When every required field is given (missing_fields is empty), nothing is
// fitted and the mesh is not looked at: the directions default to spec.up.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bake/fit/fit_proxy.h"
#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mapping/proxy_schema.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct SpecCompletion {
  Proxy proxy;
  // Keys of the fields filled by the fit (every field of the kind not given,
  // directions and equator included), in field order; empty when nothing
  // was fitted.
  std::vector<std::string> fitted;
  // How many points the fit used (fit_points(mesh).size()); 0 when nothing
  // was fitted.
  std::size_t points = 0;
};

// The fit's options for `spec` (the rules of the file comment): up = spec.up
// or +Z; axis/keep_axis_sign from a given direction or spec.up; anchor and
// height from the given anchor and cone height. Values of the wrong type are
// ignored (check_spec_keys reports them).
FitOptions fit_options(const ProxySpec& spec);

// The proxy of `spec`, completed by a fit to `mesh`'s referenced vertices
// (fit_points) when a required field is missing. Errors name parameters as
// `naming` says (keys for the library, flags for the CLI):
//  - kInvalidArgument: a bad key or type (check_spec_keys); for a complete
//    spec, make_proxy's errors; for a spec to be fitted, a given value that
//    is invalid whatever the fit gives (check_given_values: a zero axis, a
//    radius or height <= 0), checked before the mesh is looked at; a fitted
//    proxy that the given values make invalid ("the fitted cylinder with the
//    given values is invalid: cylinder: equator is parallel to axis").
//  - kParse: the mesh cannot be fitted (fit_proxy's message, e.g. "cannot
//    fit a cylinder: ... no extent along the axis"; the caller names the
//    mesh).
Expected<SpecCompletion> complete_spec(const ProxySpec& spec, const MeshData& mesh,
                                       ParamNaming naming = ParamNaming::kKey);

}  // namespace texbake
