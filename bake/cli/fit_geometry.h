// The proxy of a command that has a mesh (bake, render, fit): from
// --proxy-file, from the geometry flags, or, for every geometry flag not
// given, from a fit to the mesh. The rules of the fit (which given flags are
// kept, which the rest is fitted around, what --up fixes) are
// complete_spec's (bake/fit/complete_proxy.h), on spec_from_flags; this is
// the command line's wrapper: messages name flags, and the fit is printed.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "bake/cli/geometry_flags.h"
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

// check_geometry_flags (a proxy is required), then --proxy-file, or the flags
// completed by a fit to `mesh`'s referenced vertices (complete_spec). When a
// fit was used and `log` is not null, prints one line to it:
//   texbake: fitted cylinder (--base --radius --height) to N vertices of MESH: {json}
// Errors: the flags' usage errors (kInvalidArgument, exit 2, naming the flag,
// a bad value to fit around included), --proxy-file errors (kIo/kParse), a
// mesh the proxy cannot be fitted to (kParse, exit 1, naming `mesh_name`),
// an invalid result of merging given flags into the fit (kInvalidArgument
// naming the flag, from make_proxy).
Expected<ResolvedProxy> resolve_proxy(const GeometryFlags& flags, const MeshData& mesh,
                                      const std::string& mesh_name, std::ostream* log);

}  // namespace texbake::cli
