// complete_proxy: bake/fit's completion of a ProxySpec behind the API's
// conventions.
#include <utility>

#include "bake/fit/complete_proxy.h"
#include "bake/texbake/run.h"
#include "bake/util/timing.h"

namespace texbake {

Expected<CompletedProxy> complete_proxy(const ProxySpec& spec, const MeshData& mesh,
                                        const RunOptions& run, ParamNaming naming) {
  const auto start = Clock::now();
  return detail::run_call<CompletedProxy>(run, [&]() -> Expected<CompletedProxy> {
    Expected<SpecCompletion> done = complete_spec(spec, mesh, naming);
    if (!done) return done.error();
    CompletedProxy out{std::move(done->proxy), std::move(done->fitted), done->points, {}};
    out.stats.counts = detail::mesh_counts(mesh);
    out.stats.timings.total = seconds_since(start);
    if (!out.fitted.empty()) out.stats.timings.fit = out.stats.timings.total;
    return out;
  });
}

}  // namespace texbake
