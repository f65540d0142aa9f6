// `--uv generate` timings and atlas quality on the shared meshes (issue #4):
// bunny (75k triangles), armadillo (52k) and the armadillo after two rounds of
// 1-to-4 midpoint subdivision (832k), at 2048 with an 8 texel gutter.
// Counters: charts, utilisation, stretch (area-weighted L2, 1 = isometric).
#include <benchmark/benchmark.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "bake/uv/uv_generate.h"
#include "bench/bench_meshes.h"

namespace {

// 0: bunny, 1: armadillo, 2: armadillo subdivided twice (832k triangles).
const texbake::MeshData& mesh(int which) {
  static const texbake::MeshData armadillo = texbake::bench::load_shared_mesh("armadillo.off");
  if (which == 0) return texbake::bench::bunny();
  if (which == 1) return armadillo;
  return texbake::bench::armadillo_832k();
}

void BM_UvGenerate(benchmark::State& state) {
  const texbake::MeshData& m = mesh(static_cast<int>(state.range(0)));
  texbake::UvGenerateOptions options;
  options.atlas_size = static_cast<int>(state.range(1));
  options.padding = 8 * options.atlas_size / 2048;
  texbake::UvAtlas atlas;
  for (auto _ : state) {
    auto result = texbake::generate_uv_atlas(m, options);
    if (!result) {
      state.SkipWithError(result.error().message.c_str());
      return;
    }
    atlas = std::move(*result);
  }
  state.counters["triangles"] = static_cast<double>(m.triangles.size());
  state.counters["charts"] = atlas.chart_count;
  state.counters["utilisation"] = atlas.utilisation;
  state.counters["stretch"] = atlas.stretch_l2;
}

// Arguments: mesh (0 bunny, 1 armadillo, 2 armadillo x16), atlas size.
BENCHMARK(BM_UvGenerate)
    ->Args({0, 2048})
    ->Args({1, 2048})
    ->Args({2, 2048})
    ->Args({0, 4096})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(2);

}  // namespace
