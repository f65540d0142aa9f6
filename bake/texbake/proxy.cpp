// complete_proxy: bake/fit's completion of a ProxySpec behind the API's
// conventions.
#include <string>
#include <utility>
#include <vector>

#include "bake/texbake/run.h"
#include "bake/util/timing.h"

namespace texbake {

// bake/fit/complete_proxy.h (branch `schema`, not merged here yet): the
// proxy of `spec` with every missing field fitted to the mesh.
struct SpecCompletion {
  Proxy proxy;
  std::vector<std::string> fitted;
};
Expected<SpecCompletion> complete_spec(const ProxySpec& spec, const MeshData& mesh);

Expected<CompletedProxy> complete_proxy(const ProxySpec& spec, const MeshData& mesh,
                                        const RunOptions& run) {
  const auto start = Clock::now();
  return detail::run_call<CompletedProxy>(run, [&]() -> Expected<CompletedProxy> {
    Expected<SpecCompletion> done = complete_spec(spec, mesh);
    if (!done) return done.error();
    CompletedProxy out{std::move(done->proxy), std::move(done->fitted), {}};
    if (!out.fitted.empty()) out.stats.timings.fit = seconds_since(start);
    out.stats.counts = detail::mesh_counts(mesh);
    out.stats.timings.total = seconds_since(start);
    return out;
  });
}

}  // namespace texbake
