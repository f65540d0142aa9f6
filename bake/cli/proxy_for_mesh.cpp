#include "bake/cli/proxy_for_mesh.h"

#include <utility>

#include "texbake/job.h"

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
  Expected<ResolvedProxy> done =
      resolve_proxy(spec_from_flags(flags), mesh, mesh_name, ParamNaming::kFlag, run);
  if (!done) return done.error();
  if (log && !done->note.empty()) *log << "texbake: " << done->note << "\n";
  return FlagsProxy{std::move(done->proxy), std::move(done->fitted), std::move(done->stats)};
}

}  // namespace texbake::cli
