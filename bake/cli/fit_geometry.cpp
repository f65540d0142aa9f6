// Completing the geometry flags from a fit (see fit_geometry.h).
#include "bake/cli/fit_geometry.h"

#include "bake/fit/complete_proxy.h"
#include "mesh_io/proxy_json.h"

namespace texbake::cli {

Expected<ResolvedProxy> resolve_proxy(const GeometryFlags& flags, const MeshData& mesh,
                                      const std::string& mesh_name, std::ostream* log) {
  if (Status s = check_geometry_flags(flags, /*require_proxy=*/true); !s) return s.error();
  if (flags.proxy_file) {
    Expected<Proxy> proxy = read_proxy_file(*flags.proxy_file);
    if (!proxy) return proxy.error();
    return ResolvedProxy{std::move(*proxy), {}};
  }
  const ProxyKind kind = *flags.kind;
  Expected<SpecCompletion> done = complete_spec(spec_from_flags(flags), mesh, ParamNaming::kFlag);
  if (!done) {
    // The mesh's shape, not the command line, is at fault: exit 1.
    if (done.error().code == ErrorCode::kParse) {
      return make_error(ErrorCode::kParse, mesh_name + ": " + done.error().message);
    }
    return done.error();
  }
  std::vector<std::string> filled;
  for (const std::string& key : done->fitted) filled.emplace_back(find_field(kind, key)->flag);
  if (log && !filled.empty()) {
    std::string names;
    for (const std::string& f : filled) names += (names.empty() ? "" : " ") + f;
    *log << "texbake: fitted " << to_string(kind) << " (" << names << ") to " << done->points
         << " vertices of " << mesh_name << ": " << proxy_to_json(done->proxy) << "\n";
  }
  return ResolvedProxy{std::move(done->proxy), std::move(filled)};
}

}  // namespace texbake::cli
