// The proxy of a command that has a mesh (bake, render, fit): from
// --proxy-file, from the geometry flags, or, for every geometry flag not
// given, from a fit to the mesh (SPEC sections 5 and 6, bake/fit_proxy.h).
//
// Given flags are kept as they are. A given pole/axis/normal is the fit's
// fixed direction, with its sign (the rest is fitted around it); without one,
// --up fixes a cylinder's or cone's axis line (the cone's apex side still
// comes from the fit) and is the sphere's pole, as in `texbake fit`. A given
// fixed point (sphere/disk --center, cylinder --base, cone --apex, plane
// --origin) and a cone's --height are passed to the fit, which fits the
// remaining values around them (FitOptions::anchor: e.g. a sphere's radius
// then encloses the mesh around the given centre); other given values (a
// --radius, a cylinder's --height, --equator, a plane's --u-axis/--v-axis)
// replace the fitted ones, nothing depending on them. When every flag the
// kind requires is given, nothing is fitted (the pole/axis/normal then
// defaults to --up, as geometry_flags.h says).
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "bake/cli/geometry_flags.h"
#include "bake/fit/fit_proxy.h"
#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mesh_io/mesh_data.h"

namespace texbake::cli {

struct ResolvedProxy {
  Proxy proxy;
  // The flags filled from the fit, e.g. {"--base", "--radius", "--height"};
  // empty when nothing was fitted (all given, or --proxy-file).
  std::vector<std::string> fitted_flags;
};

// The fit's options for --proxy `kind` under `flags` (see the file comment).
FitOptions fit_options_from_flags(const GeometryFlags& flags, ProxyKind kind);

// check_geometry_flags (a proxy is required), then --proxy-file, or the flags
// completed by a fit to `mesh`'s referenced vertices. When a fit was used and
// `log` is not null, prints one line to it:
//   texbake: fitted cylinder (--base --radius --height) to N vertices of MESH: {json}
// Errors: the flags' usage errors (kInvalidArgument, exit 2), --proxy-file
// errors (kIo/kParse), a mesh the proxy cannot be fitted to (kParse, exit 1,
// naming `mesh_name`), an invalid result of merging given flags into the fit
// (kInvalidArgument naming the flag, from make_proxy).
Expected<ResolvedProxy> resolve_proxy(const GeometryFlags& flags, const MeshData& mesh,
                                      const std::string& mesh_name, std::ostream* log);

}  // namespace texbake::cli
