// Fit time of each proxy kind (bake/fit_proxy.h) on the armadillo subdivided
// to 832,000 triangles (two rounds of 1-to-4 midpoint subdivision in memory:
// 416,002 unique vertices). Target: at most 1 s per fit (issue #5).
//
//   build-dev/bench/texbake_bench --benchmark_filter=Fit
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "bake/fit_proxy.h"

namespace texbake {
namespace {

struct TriangleMesh {
  std::vector<Float3> positions;
  std::vector<std::array<uint32_t, 3>> triangles;
};

// A minimal reader for the triangle OFF files of the shared data folder;
// the benchmark does not measure (or depend on) mesh_io.
TriangleMesh read_off_triangles(const std::string& path) {
  std::ifstream in(path);
  std::string magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  in >> magic >> nv >> nf >> ne;
  if (!in || magic != "OFF") throw std::runtime_error("cannot read " + path);
  TriangleMesh mesh;
  mesh.positions.resize(nv);
  for (Float3& p : mesh.positions) in >> p.x >> p.y >> p.z;
  for (std::size_t f = 0; f < nf; ++f) {
    std::size_t k = 0;
    std::array<uint32_t, 3> t{};
    in >> k >> t[0] >> t[1] >> t[2];
    if (k != 3) throw std::runtime_error(path + ": not a triangle mesh");
    mesh.triangles.push_back(t);
  }
  if (!in) throw std::runtime_error("cannot read " + path);
  return mesh;
}

// One round of 1-to-4 midpoint subdivision; edge midpoints are shared.
TriangleMesh subdivide(const TriangleMesh& in) {
  TriangleMesh out;
  out.positions = in.positions;
  std::unordered_map<uint64_t, uint32_t> midpoints;
  auto midpoint = [&](uint32_t a, uint32_t b) {
    const uint64_t key = (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
    auto [it, inserted] = midpoints.try_emplace(key, static_cast<uint32_t>(out.positions.size()));
    if (inserted) {
      const Float3 p = in.positions[a], q = in.positions[b];
      out.positions.push_back({(p.x + q.x) / 2, (p.y + q.y) / 2, (p.z + q.z) / 2});
    }
    return it->second;
  };
  for (const auto& t : in.triangles) {
    const uint32_t ab = midpoint(t[0], t[1]), bc = midpoint(t[1], t[2]), ca = midpoint(t[2], t[0]);
    out.triangles.push_back({t[0], ab, ca});
    out.triangles.push_back({ab, t[1], bc});
    out.triangles.push_back({ca, bc, t[2]});
    out.triangles.push_back({ab, bc, ca});
  }
  return out;
}

const TriangleMesh& big_armadillo() {
  static const TriangleMesh mesh =
      subdivide(subdivide(read_off_triangles(TEXBAKE_SHARED_DATA_DIR "/armadillo.off")));
  return mesh;
}

void BM_Fit(benchmark::State& state) {
  const auto kind = static_cast<ProxyKind>(state.range(0));
  const TriangleMesh& mesh = big_armadillo();
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
