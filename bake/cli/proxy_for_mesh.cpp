#include "bake/cli/proxy_for_mesh.h"

#include <utility>

namespace texbake::cli {

Expected<FlagsProxy> proxy_for_mesh(const GeometryFlags& flags, const MeshData& mesh,
                                    const std::string& mesh_name, std::ostream* log,
                                    const RunOptions& run) {
  if (Status s = check_geometry_flags(flags, /*require_proxy=*/true); !s) return s.error();
  if (flags.proxy_file) {
    Expected<Proxy> proxy = read_proxy_file(*flags.proxy_file);
    if (!proxy) return proxy.error();
    return FlagsProxy{std::move(*proxy), {}, {}};
  }
  const ProxyKind kind = *flags.kind;
  Expected<CompletedProxy> done =
      complete_proxy(spec_from_flags(flags), mesh, run, ParamNaming::kFlag);
  if (!done) {
    // The mesh's shape, not the command line, is at fault: exit 1.
    if (category(done.error()) == ErrorCategory::kInput) {
      return make_error(done.error().code, mesh_name + ": " + done.error().message);
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
  return FlagsProxy{std::move(done->proxy), std::move(filled), std::move(done->stats)};
}

}  // namespace texbake::cli
