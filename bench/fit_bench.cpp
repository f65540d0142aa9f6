// Fit time of each proxy kind (bake/fit/fit_proxy.h) on the armadillo subdivided
// to 832,000 triangles (two rounds of 1-to-4 midpoint subdivision in memory:
// 416,002 unique vertices). Target: at most 1 s per fit (issue #5).
//
//   build-dev/bench/texbake_bench --benchmark_filter=Fit
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "bake/fit/fit_proxy.h"
#include "bench/bench_meshes.h"

namespace texbake {
namespace {

void BM_Fit(benchmark::State& state) {
  const auto kind = static_cast<ProxyKind>(state.range(0));
  const MeshData& mesh = bench::armadillo_832k();
  for (auto _ : state) {
    auto fit = fit_proxy(kind, mesh.positions);
    if (!fit) {
      state.SkipWithError(fit.error().message.c_str());
      break;
    }
    benchmark::DoNotOptimize(fit);
  }
  state.SetLabel(to_string(kind));
  state.counters["points"] = static_cast<double>(mesh.positions.size());
  state.counters["triangles"] = static_cast<double>(mesh.triangles.size());
}

BENCHMARK(BM_Fit)
    ->DenseRange(static_cast<int>(ProxyKind::kSphere), static_cast<int>(ProxyKind::kPlane))
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace texbake
