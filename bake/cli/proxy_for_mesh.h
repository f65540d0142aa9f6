// The proxy of a command that has a mesh (bake, render, fit): from
// --proxy-file, or the geometry flags completed by texbake::complete_proxy
// (every field not given is fitted to the mesh by complete_spec's rules,
// bake/fit/complete_proxy.h), with messages naming flags and the fit
// printed.
#pragma once

#include <ostream>
#include <string>
#include <vector>

#include "bake/cli/geometry_flags.h"
#include "texbake/texbake.h"

namespace texbake::cli {

struct FlagsProxy {
  Proxy proxy;
  // The flags filled from the fit, e.g. {"--base", "--radius", "--height"};
  // empty when nothing was fitted (all given, or --proxy-file).
  std::vector<std::string> fitted_flags;
  Stats stats;  // complete_proxy's (timings.fit); zero for --proxy-file
};

// check_geometry_flags (a proxy is required), then --proxy-file, or
// complete_proxy on spec_from_flags. When a fit was used and `log` is not
// null, prints one line to it:
//   texbake: fitted cylinder (--base --radius --height) to N vertices of MESH: {json}
// Errors: the flags' usage errors (kInvalidArgument, exit 2, naming the
// flag, a bad value to fit around included), --proxy-file errors
// (kIo/kParse), a mesh the proxy cannot be fitted to (kParse, exit 1,
// "MESH: ..." with `mesh_name`), an invalid result of the given flags over
// the fit (kInvalidArgument naming the flag).
Expected<FlagsProxy> proxy_for_mesh(const GeometryFlags& flags, const MeshData& mesh,
                                    const std::string& mesh_name, std::ostream* log,
                                    const RunOptions& run = {});

}  // namespace texbake::cli
