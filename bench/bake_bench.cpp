// Per-vertex baking benchmarks (issue #3): the bunny (37k vertices) and the
// armadillo subdivided twice 1-to-4 (832k triangles), sphere proxy around
// the mesh, Earth map, visibility on, both filters; and raw Embree occlusion
// throughput (rtcOccluded1 loop, rtcOccluded1M, rtcOccluded16, rtcOccludedNp)
// on exactly the rays of our visibility path, so its overhead shows.
//
// Run: build-dev/texbake_bench --benchmark_filter=Bake|Visibility|Raw
// The subdivided armadillo is also written as binary PLY to
// $TMPDIR/texbake_armadillo_832k.ply (BM_WritePly) for timing the CLI end to
// end with /usr/bin/time -v.
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <vector>

#include "bake/engine/bake_vertex.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/vertex/occlusion_fill.h"
#include "bench/bench_meshes.h"
#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "mesh_io/write_mesh.h"

namespace texbake {
namespace {

using bench::die;
using bench::earth;
using bench::sphere_around;

const std::filesystem::path kData = TEXBAKE_DATA_DIR;

const MeshData& bunny() {
  static const MeshData mesh = bench::load_shared_mesh("bunny00.off");
  return mesh;
}
const MeshData& armadillo() {
  static const MeshData mesh =
      bench::subdivide(bench::subdivide(bench::load_shared_mesh("armadillo.off")));
  return mesh;
}
const MeshData& mesh_by_index(int64_t i) {
  return i == 0 ? bunny() : armadillo();
}

// ---- The whole per-vertex bake (scene build + bake + fill). ----------------

void BM_BakeVertex(benchmark::State& state) {
  const MeshData& mesh = mesh_by_index(state.range(0));
  const Proxy proxy = sphere_around(mesh);
  VertexBakeOptions options;
  options.filter = state.range(1) == 0 ? VertexFilter::kBilinear : VertexFilter::kArea;
  VertexBakeTimings sum;
  VertexBakeCounts counts;
  for (auto _ : state) {
    Expected<VertexBakeResult> r = bake_vertex(mesh, earth().view(), proxy, options);
    if (!r) die(r.error().message);
    sum.scene_build += r->timings.scene_build;
    sum.bake += r->timings.bake;
    sum.fill += r->timings.fill;
    counts = r->counts;
    benchmark::DoNotOptimize(r->colors.data());
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["scene_s"] = sum.scene_build / n;
  state.counters["bake_s"] = sum.bake / n;
  state.counters["fill_s"] = sum.fill / n;
  state.counters["vertices"] = static_cast<double>(counts.vertices);
  state.counters["triangles"] = static_cast<double>(counts.triangles);
  state.counters["occluded"] = static_cast<double>(counts.occluded);
  state.counters["unfilled"] = static_cast<double>(counts.unfilled);
  state.SetLabel(state.range(0) == 0 ? "bunny" : "armadillo_832k");
}
BENCHMARK(BM_BakeVertex)
    ->ArgsProduct({{0, 1}, {0, 1}})
    ->ArgNames({"mesh", "area"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---- The occlusion fill alone: direct vs multigrid, growth with the mesh. ----
// The shadows of the bench's sphere proxy (rays outward from its centre) on
// the armadillo subdivided 2, 3 and 4 times (832k, 3.3M, 13.3M triangles),
// random known colours; the fill's two solvers on the same system.

struct FillCase {
  MeshData mesh;
  std::vector<uint8_t> unknown;
  std::vector<Rgba> colors;
};

const FillCase& fill_case(int64_t rounds) {
  static std::map<int64_t, FillCase> cache;
  auto it = cache.find(rounds);
  if (it != cache.end()) return it->second;
  FillCase c;
  c.mesh = bench::load_shared_mesh("armadillo.off");
  for (int64_t k = 0; k < rounds; ++k) c.mesh = bench::subdivide(c.mesh);
  const Proxy proxy = sphere_around(c.mesh);
  Expected<EmbreeScene> scene = EmbreeScene::build(c.mesh, BuildQuality::kLow);
  if (!scene) die(scene.error().message);
  std::vector<Vec3> points, dirs;
  for (const Float3& p : c.mesh.positions) {
    points.push_back({p.x, p.y, p.z});
    dirs.push_back(inverse_map(proxy, points.back()).to_projector);
  }
  const std::vector<uint8_t> visible = compute_visibility(*scene, points, dirs);
  c.unknown.resize(visible.size());
  c.colors.resize(visible.size());
  uint32_t state = 12345;
  auto next = [&] { return (state = state * 1664525u + 1013904223u) / 4294967296.0f; };
  for (std::size_t v = 0; v < visible.size(); ++v) {
    c.unknown[v] = visible[v] ? 0 : 1;
    c.colors[v] = visible[v] ? Rgba{next(), next(), next(), 1} : Rgba{0, 0, 0, 0};
  }
  return cache.emplace(rounds, std::move(c)).first->second;
}

// Arguments: subdivision rounds (2, 3, 4), solver (0 direct, 1 multigrid).
void BM_Fill(benchmark::State& state) {
  const FillCase& c = fill_case(state.range(0));
  FillSolverOptions solver;
  if (state.range(1) == 0) solver.direct_rows = static_cast<std::size_t>(-1);
  FillResult result;
  for (auto _ : state) {
    std::vector<Rgba> colors = c.colors;
    Expected<FillResult> r = fill_harmonic(
        c.mesh, colors, c.unknown,
        [](uint32_t) {
          return Rgba{0, 0, 0, 1};
        },
        solver);
    if (!r) die(r.error().message);
    result = *r;
    benchmark::DoNotOptimize(colors.data());
  }
  state.counters["triangles"] = static_cast<double>(c.mesh.triangles.size());
  state.counters["filled"] = static_cast<double>(result.filled);
  state.counters["iterations"] = result.iterations;
  state.SetLabel(state.range(1) == 0 ? "direct" : "multigrid");
}
BENCHMARK(BM_Fill)
    ->ArgsProduct({{2, 3, 4}, {0, 1}})
    ->ArgNames({"rounds", "multigrid"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(1);

// ---- Embree build quality for one-shot scenes: build + one ray per vertex. ----
// What a per-vertex bake does with its scene: build it, trace each vertex's
// visibility ray to the bench's sphere proxy once, free it. Arguments:
// subdivision rounds (2: 832k, 4: 13.3M triangles), quality (0 low, 1 medium).
void BM_SceneQuality(benchmark::State& state) {
  const FillCase& c = fill_case(state.range(0));
  const Proxy proxy = sphere_around(c.mesh);
  std::vector<Vec3> points, dirs;
  for (const Float3& p : c.mesh.positions) {
    points.push_back({p.x, p.y, p.z});
    dirs.push_back(inverse_map(proxy, points.back()).to_projector);
  }
  const BuildQuality quality = state.range(1) == 0 ? BuildQuality::kLow : BuildQuality::kMedium;
  double build_s = 0, trace_s = 0;
  std::size_t visible = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    Expected<EmbreeScene> scene = EmbreeScene::build(c.mesh, quality);
    if (!scene) die(scene.error().message);
    const auto t1 = std::chrono::steady_clock::now();
    const std::vector<uint8_t> v = compute_visibility(*scene, points, dirs);
    const auto t2 = std::chrono::steady_clock::now();
    build_s += std::chrono::duration<double>(t1 - t0).count();
    trace_s += std::chrono::duration<double>(t2 - t1).count();
    visible = std::count(v.begin(), v.end(), 1);
  }
  state.counters["build_s"] = benchmark::Counter(build_s, benchmark::Counter::kAvgIterations);
  state.counters["trace_s"] = benchmark::Counter(trace_s, benchmark::Counter::kAvgIterations);
  state.counters["visible"] = static_cast<double>(visible);
  state.SetLabel(state.range(1) == 0 ? "low" : "medium");
}
BENCHMARK(BM_SceneQuality)
    ->ArgsProduct({{2, 4}, {0, 1}})
    ->ArgNames({"rounds", "medium"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

// ---- Visibility rays: ours vs raw Embree on the same rays and scene flags. ----

struct RaySet {
  std::vector<float> ox, oy, oz, dx, dy, dz;
  float tnear = 0;
};

const RaySet& rays_for(int64_t mesh_index, const EmbreeScene& scene) {
  static std::optional<RaySet> cache[2];
  if (!cache[mesh_index]) {
    const MeshData& mesh = mesh_by_index(mesh_index);
    const Proxy proxy = sphere_around(mesh);
    RaySet rays;
    for (const Float3& p : mesh.positions) {
      const MapResult m = inverse_map(proxy, {p.x, p.y, p.z});
      rays.ox.push_back(p.x), rays.oy.push_back(p.y), rays.oz.push_back(p.z);
      rays.dx.push_back(static_cast<float>(m.to_projector.x));
      rays.dy.push_back(static_cast<float>(m.to_projector.y));
      rays.dz.push_back(static_cast<float>(m.to_projector.z));
    }
    rays.tnear = static_cast<float>(visibility_offset(scene));
    cache[mesh_index] = std::move(rays);
  }
  return *cache[mesh_index];
}

const EmbreeScene& scene_for(int64_t mesh_index) {
  static std::optional<EmbreeScene> cache[2];
  if (!cache[mesh_index]) {
    Expected<EmbreeScene> s = EmbreeScene::build(mesh_by_index(mesh_index), BuildQuality::kLow);
    if (!s) die(s.error().message);
    cache[mesh_index].emplace(std::move(s).value());
  }
  return *cache[mesh_index];
}

constexpr std::size_t kGrain = 4096;  // as bake/trace/visibility.cpp

void BM_VisibilityOurs(benchmark::State& state) {
  ThreadLimit limit(static_cast<int>(state.range(1)));
  const EmbreeScene& scene = scene_for(state.range(0));
  const RaySet& rays = rays_for(state.range(0), scene);
  std::vector<Vec3> points, dirs;
  for (std::size_t i = 0; i < rays.ox.size(); ++i) {
    points.push_back({rays.ox[i], rays.oy[i], rays.oz[i]});
    dirs.push_back({rays.dx[i], rays.dy[i], rays.dz[i]});
  }
  std::size_t visible = 0;
  for (auto _ : state) {
    const std::vector<uint8_t> v = compute_visibility(scene, points, dirs);
    visible = std::count(v.begin(), v.end(), 1);
  }
  state.counters["rays_per_s"] = benchmark::Counter(static_cast<double>(rays.ox.size()),
                                                    benchmark::Counter::kIsIterationInvariantRate);
  state.counters["visible"] = static_cast<double>(visible);
}
BENCHMARK(BM_VisibilityOurs)
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->ArgNames({"mesh", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// The same rays through EmbreeScene::occluded directly (no Vec3 -> float copy).
void BM_VisibilitySceneOccluded(benchmark::State& state) {
  ThreadLimit limit(static_cast<int>(state.range(1)));
  const EmbreeScene& scene = scene_for(state.range(0));
  const RaySet& rays = rays_for(state.range(0), scene);
  const std::size_t n = rays.ox.size();
  std::vector<float> tnear(n, rays.tnear);
  std::vector<uint8_t> occluded(n);
  for (auto _ : state) {
    parallel_for_chunks(n, kGrain, [&](std::size_t b, std::size_t e) {
      RayBatch batch{rays.ox.data() + b,
                     rays.oy.data() + b,
                     rays.oz.data() + b,
                     rays.dx.data() + b,
                     rays.dy.data() + b,
                     rays.dz.data() + b,
                     tnear.data() + b,
                     nullptr,
                     e - b};
      scene.occluded(batch, occluded.data() + b);
    });
  }
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["visible"] = static_cast<double>(std::count(occluded.begin(), occluded.end(), 0));
}
BENCHMARK(BM_VisibilitySceneOccluded)
    ->ArgsProduct({{0, 1}, {1, 2}})
    ->ArgNames({"mesh", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// A raw Embree scene with the same flags as EmbreeScene (robust, compact, low quality).
struct RawScene {
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  std::vector<float> vertices;
  RawScene(const MeshData& mesh, bool compact) {
    rtcSetSceneFlags(scene, static_cast<RTCSceneFlags>(RTC_SCENE_FLAG_ROBUST |
                                                       (compact ? RTC_SCENE_FLAG_COMPACT : 0)));
    rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(g, RTC_BUILD_QUALITY_LOW);
    vertices.resize(mesh.positions.size() * 3 + 1);
    std::memcpy(vertices.data(), mesh.positions.data(), mesh.positions.size() * 12);
    rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices.data(), 0,
                               12, mesh.positions.size());
    auto* idx = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, mesh.triangles.size()));
    std::memcpy(idx, mesh.triangles.data(), mesh.triangles.size() * 12);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
  }
  ~RawScene() {
    rtcReleaseScene(scene);
    rtcReleaseDevice(device);
  }
};

// compact = true: the flags of EmbreeScene; false: without RTC_SCENE_FLAG_COMPACT.
RawScene& raw_scene_for(int64_t mesh_index, bool compact) {
  static std::optional<RawScene> cache[2][2];
  auto& slot = cache[mesh_index][compact ? 1 : 0];
  if (!slot) slot.emplace(mesh_by_index(mesh_index), compact);
  return *slot;
}

RTCRay make_ray(const RaySet& r, std::size_t i) {
  RTCRay ray;
  ray.org_x = r.ox[i], ray.org_y = r.oy[i], ray.org_z = r.oz[i];
  ray.dir_x = r.dx[i], ray.dir_y = r.dy[i], ray.dir_z = r.dz[i];
  ray.tnear = r.tnear;
  ray.tfar = std::numeric_limits<float>::infinity();
  ray.time = 0;
  ray.mask = 0xFFFFFFFFu;  // Debian's Embree has ray masks on
  ray.id = static_cast<unsigned>(i);
  ray.flags = 0;
  return ray;
}

enum RawMode { kOccluded1, kOccluded1M, kOccluded16, kOccludedNp };

void BM_RawEmbree(benchmark::State& state) {
  ThreadLimit limit(static_cast<int>(state.range(2)));
  const int64_t mesh_index = state.range(0);
  const auto mode = static_cast<RawMode>(state.range(1));
  const RaySet& rays = rays_for(mesh_index, scene_for(mesh_index));
  RTCScene scene = raw_scene_for(mesh_index, state.range(3) == 1).scene;
  const std::size_t n = rays.ox.size();
  std::vector<uint8_t> occluded(n);
  for (auto _ : state) {
    parallel_for_chunks(n, kGrain, [&](std::size_t b, std::size_t e) {
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      if (mode == kOccluded1) {
        for (std::size_t i = b; i < e; ++i) {
          RTCRay ray = make_ray(rays, i);
          rtcOccluded1(scene, &context, &ray);
          occluded[i] = ray.tfar < 0;
        }
      } else if (mode == kOccluded1M) {
        std::vector<RTCRay> block(e - b);
        for (std::size_t i = b; i < e; ++i) block[i - b] = make_ray(rays, i);
        rtcOccluded1M(scene, &context, block.data(), static_cast<unsigned>(e - b), sizeof(RTCRay));
        for (std::size_t i = b; i < e; ++i) occluded[i] = block[i - b].tfar < 0;
      } else if (mode == kOccluded16) {
        for (std::size_t s = b; s < e; s += 16) {
          alignas(64) RTCRay16 packet;
          alignas(64) int valid[16];
          for (int k = 0; k < 16; ++k) {
            const std::size_t i = std::min(s + k, e - 1);
            valid[k] = s + k < e ? -1 : 0;
            packet.org_x[k] = rays.ox[i], packet.org_y[k] = rays.oy[i],
            packet.org_z[k] = rays.oz[i];
            packet.dir_x[k] = rays.dx[i], packet.dir_y[k] = rays.dy[i],
            packet.dir_z[k] = rays.dz[i];
            packet.tnear[k] = rays.tnear, packet.tfar[k] = std::numeric_limits<float>::infinity();
            packet.time[k] = 0, packet.mask[k] = 0xFFFFFFFFu, packet.id[k] = k, packet.flags[k] = 0;
          }
          rtcOccluded16(valid, scene, &context, &packet);
          for (int k = 0; k < 16 && s + k < e; ++k) occluded[s + k] = packet.tfar[k] < 0;
        }
      } else {
        const std::size_t m = e - b;
        std::vector<float> ox(rays.ox.begin() + b, rays.ox.begin() + e),
            oy(rays.oy.begin() + b, rays.oy.begin() + e),
            oz(rays.oz.begin() + b, rays.oz.begin() + e),
            dx(rays.dx.begin() + b, rays.dx.begin() + e),
            dy(rays.dy.begin() + b, rays.dy.begin() + e),
            dz(rays.dz.begin() + b, rays.dz.begin() + e), tn(m, rays.tnear), time(m, 0),
            tf(m, std::numeric_limits<float>::infinity());
        std::vector<unsigned> mask(m, 0xFFFFFFFFu), id(m), flags(m, 0);
        RTCRayNp np{ox.data(), oy.data(),   oz.data(), tn.data(),   dx.data(), dy.data(),
                    dz.data(), time.data(), tf.data(), mask.data(), id.data(), flags.data()};
        rtcOccludedNp(scene, &context, &np, static_cast<unsigned>(m));
        for (std::size_t i = 0; i < m; ++i) occluded[b + i] = tf[i] < 0;
      }
    });
  }
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["visible"] = static_cast<double>(std::count(occluded.begin(), occluded.end(), 0));
  static const char* names[] = {"rtcOccluded1", "rtcOccluded1M", "rtcOccluded16", "rtcOccludedNp"};
  state.SetLabel(names[mode]);
}
BENCHMARK(BM_RawEmbree)
    ->ArgsProduct({{0, 1}, {kOccluded1, kOccluded1M, kOccluded16, kOccludedNp}, {1, 2}, {1, 0}})
    ->ArgNames({"mesh", "mode", "threads", "compact"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

// ---- Mesh files: binary PLY write and read of the subdivided armadillo. -----

const std::filesystem::path& armadillo_ply() {
  static const std::filesystem::path path =
      std::filesystem::temp_directory_path() / "texbake_armadillo_832k.ply";
  return path;
}

void BM_WritePly(benchmark::State& state) {
  const MeshData& mesh = armadillo();
  std::vector<std::array<float, 4>> colors(mesh.positions.size(), {0.5f, 0.25f, 1, 1});
  MeshWriteOptions options;
  options.vertex_colors = colors;
  for (auto _ : state) {
    if (Status s = write_mesh(armadillo_ply(), mesh, options); !s) die(s.error().message);
  }
  state.SetLabel(armadillo_ply().string());
}
BENCHMARK(BM_WritePly)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_ReadPly(benchmark::State& state) {
  if (!std::filesystem::exists(armadillo_ply())) {
    if (Status s = write_mesh(armadillo_ply(), armadillo()); !s) die(s.error().message);
  }
  for (auto _ : state) {
    Expected<LoadedMesh> m = read_mesh(armadillo_ply());
    if (!m) die(m.error().message);
    benchmark::DoNotOptimize(m->mesh.positions.data());
  }
}
BENCHMARK(BM_ReadPly)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace texbake
