// `--uv generate` timings and atlas quality on the shared meshes (issue #4):
// bunny (75k triangles), armadillo (52k) and the armadillo after two rounds of
// 1-to-4 midpoint subdivision (832k), at 2048 with an 8 texel gutter.
// Counters: charts, utilisation, stretch (area-weighted L2, 1 = isometric).
#include <benchmark/benchmark.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include "bake/uv_generate.h"

namespace {

// Minimal OFF reader for benchmark inputs (the project's mesh reader lives in
// mesh_io; this keeps the benchmark independent of it). Triangulates polygons
// as fans; no error handling beyond an empty result.
texbake::MeshData read_off(const std::string& path) {
  texbake::MeshData m;
  std::ifstream in(path);
  std::string word;
  in >> word;
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> nv >> nf >> ne;
  m.positions.resize(nv);
  for (auto& p : m.positions) in >> p.x >> p.y >> p.z;
  for (std::size_t f = 0; f < nf; ++f) {
    std::size_t k = 0;
    in >> k;
    std::vector<uint32_t> v(k);
    for (auto& x : v) in >> x;
    std::string rest;
    std::getline(in, rest);
    for (std::size_t i = 1; i + 1 < k; ++i) m.triangles.push_back({v[0], v[i], v[i + 1]});
  }
  return m;
}

// One round of 1-to-4 midpoint subdivision (flat: keeps the surface).
texbake::MeshData subdivide(const texbake::MeshData& in) {
  texbake::MeshData out;
  out.positions = in.positions;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
  auto midpoint = [&](uint32_t a, uint32_t b) {
    const auto key = std::minmax(a, b);
    auto [it, fresh] = mid.try_emplace({key.first, key.second}, 0u);
    if (fresh) {
      const auto& p = out.positions[a];
      const auto& q = out.positions[b];
      it->second = static_cast<uint32_t>(out.positions.size());
      out.positions.push_back({(p.x + q.x) / 2, (p.y + q.y) / 2, (p.z + q.z) / 2});
    }
    return it->second;
  };
  for (const auto& t : in.triangles) {
    const uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
    out.triangles.push_back({t[0], a, c});
    out.triangles.push_back({a, t[1], b});
    out.triangles.push_back({c, b, t[2]});
    out.triangles.push_back({a, b, c});
  }
  return out;
}

const texbake::MeshData& mesh(int which) {
  static std::map<int, texbake::MeshData> cache;
  auto it = cache.find(which);
  if (it != cache.end()) return it->second;
  const std::string dir = TEXBAKE_SHARED_DATA_DIR;
  texbake::MeshData m;
  if (which == 0) m = read_off(dir + "/bunny00.off");
  if (which == 1) m = read_off(dir + "/armadillo.off");
  if (which == 2) m = subdivide(subdivide(read_off(dir + "/armadillo.off")));
  return cache.emplace(which, std::move(m)).first->second;
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
