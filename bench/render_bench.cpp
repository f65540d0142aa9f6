// texbake render on a large mesh: 1024x1024, 4 samples per pixel, shadows, the
// armadillo subdivided twice (1-to-4 midpoint) to 832,000 triangles.
// Target (issue #6): at most 3 s on the 2-core development machine.
//
// Next to the full render, the same primary rays go through
//  - EmbreeScene::intersect alone (texbake's wrapper, stream API), and
//  - raw Embree (rtcIntersect1 per ray over a scene built here),
// so the rays-per-second figures show what shading and shadows cost.
//
// Run: build-dev/texbake_bench --benchmark_filter=Render
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>

#include <cstdio>
#include <cstdlib>
#include <unordered_map>
#include <vector>

#include "bake/render/render_preview.h"
#include "bake/trace/embree_scene.h"
#include "bake/util/parallel.h"
#include "bench/bench_meshes.h"
#include "mesh_io/read_mesh.h"

namespace texbake {
namespace {

struct Fixture {
  MeshData mesh;
  EmbreeScene scene;
  RenderOptions options;
};

Fixture& fixture() {
  static Fixture* f = [] {
    MeshData mesh = bench::armadillo_832k();
    auto scene = EmbreeScene::build(mesh, BuildQuality::kMedium);
    if (!scene) std::exit(1);
    RenderOptions o;
    o.width = o.height = 1024;
    o.samples_per_pixel = 4;
    o.shadows = true;
    o.up = {0, 1, 0};  // the Stanford scans are +Y up
    o.elevation_deg = 15;
    return new Fixture{std::move(mesh), std::move(scene).value(), o};
  }();
  return *f;
}

void BM_RenderArmadillo(benchmark::State& state) {
  Fixture& f = fixture();
  RenderStats stats;
  for (auto _ : state) {
    auto img = render_preview(f.mesh, f.scene, GreySource{}, f.options, &stats);
    benchmark::DoNotOptimize(img);
  }
  state.counters["triangles"] = static_cast<double>(f.mesh.triangles.size());
  state.counters["primary_rays"] = static_cast<double>(stats.primary_rays);
  state.counters["shadow_rays"] = static_cast<double>(stats.shadow_rays);
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(stats.primary_rays + stats.shadow_rays),
                         benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_RenderArmadillo)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Scene build plus render: what `texbake render` spends after loading.
void BM_RenderArmadilloWithBuild(benchmark::State& state) {
  Fixture& f = fixture();
  for (auto _ : state) {
    auto scene = EmbreeScene::build(f.mesh, BuildQuality::kMedium);
    auto img = render_preview(f.mesh, *scene, GreySource{}, f.options);
    benchmark::DoNotOptimize(img);
  }
}
BENCHMARK(BM_RenderArmadilloWithBuild)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(2);

// The primary rays of the render (pixel centres jittered the same way is not
// needed for throughput: 4 rays per pixel through the pixel's quarter
// centres), in 16x16-pixel tiles like the renderer.
struct PrimaryRays {
  std::vector<float> ox, oy, oz, dx, dy, dz;
};

PrimaryRays primary_rays(const Fixture& f) {
  auto bounds = bounding_sphere(f.mesh);
  auto cam = make_camera(*bounds, f.options, f.options.azimuth_deg);
  PrimaryRays r;
  const int w = f.options.width, h = f.options.height;
  for (int ty = 0; ty < h; ty += 16) {
    for (int tx = 0; tx < w; tx += 16) {
      for (int y = ty; y < ty + 16; ++y) {
        for (int x = tx; x < tx + 16; ++x) {
          for (int s = 0; s < 4; ++s) {
            const Ray ray = cam->ray(x + 0.25 + 0.5 * (s % 2), y + 0.25 + 0.5 * (s / 2));
            r.ox.push_back(static_cast<float>(ray.origin.x));
            r.oy.push_back(static_cast<float>(ray.origin.y));
            r.oz.push_back(static_cast<float>(ray.origin.z));
            r.dx.push_back(static_cast<float>(ray.direction.x));
            r.dy.push_back(static_cast<float>(ray.direction.y));
            r.dz.push_back(static_cast<float>(ray.direction.z));
          }
        }
      }
    }
  }
  return r;
}

constexpr std::size_t kChunk = 16 * 16 * 4;  // one tile's rays

void BM_PrimaryRaysEmbreeScene(benchmark::State& state) {
  Fixture& f = fixture();
  static const PrimaryRays rays = primary_rays(f);
  const std::size_t n = rays.ox.size();
  std::vector<Hit> hits(n);
  for (auto _ : state) {
    parallel_for_chunks(n / kChunk, 1, [&](std::size_t b, std::size_t e) {
      RayBatch batch;
      batch.org_x = rays.ox.data() + b * kChunk;
      batch.org_y = rays.oy.data() + b * kChunk;
      batch.org_z = rays.oz.data() + b * kChunk;
      batch.dir_x = rays.dx.data() + b * kChunk;
      batch.dir_y = rays.dy.data() + b * kChunk;
      batch.dir_z = rays.dz.data() + b * kChunk;
      batch.count = (e - b) * kChunk;
      f.scene.intersect(batch, hits.data() + b * kChunk);
    });
    benchmark::DoNotOptimize(hits.data());
  }
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_PrimaryRaysEmbreeScene)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

// Raw Embree: its own device and scene (same triangles, medium quality),
// rtcIntersect1 per ray with a coherent context, the same tiles and threads.
void BM_PrimaryRaysRawEmbree(benchmark::State& state) {
  Fixture& f = fixture();
  static const PrimaryRays rays = primary_rays(f);
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene scene = rtcNewScene(device);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                        f.mesh.vertex_count()));
  for (std::size_t i = 0; i < f.mesh.vertex_count(); ++i) {
    v[3 * i] = f.mesh.positions[i].x;
    v[3 * i + 1] = f.mesh.positions[i].y;
    v[3 * i + 2] = f.mesh.positions[i].z;
  }
  auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0,
                                                             RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                                             f.mesh.triangles.size()));
  for (std::size_t t = 0; t < f.mesh.triangles.size(); ++t) {
    for (int k = 0; k < 3; ++k) idx[3 * t + k] = f.mesh.triangles[t][k];
  }
  rtcCommitGeometry(geom);
  rtcAttachGeometry(scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(scene);

  const std::size_t n = rays.ox.size();
  std::vector<unsigned> prim(n);
  for (auto _ : state) {
    parallel_for_chunks(n / kChunk, 1, [&](std::size_t b, std::size_t e) {
      RTCIntersectContext ctx;
      rtcInitIntersectContext(&ctx);
      ctx.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
      for (std::size_t i = b * kChunk; i < e * kChunk; ++i) {
        RTCRayHit rh;
        rh.ray.org_x = rays.ox[i];
        rh.ray.org_y = rays.oy[i];
        rh.ray.org_z = rays.oz[i];
        rh.ray.dir_x = rays.dx[i];
        rh.ray.dir_y = rays.dy[i];
        rh.ray.dir_z = rays.dz[i];
        rh.ray.tnear = 0;
        rh.ray.tfar = INFINITY;
        rh.ray.time = 0;
        rh.ray.mask = 0xFFFFFFFFu;  // Debian's Embree has ray masks on
        rh.ray.id = 0;
        rh.ray.flags = 0;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene, &ctx, &rh);
        prim[i] = rh.hit.primID;
      }
    });
    benchmark::DoNotOptimize(prim.data());
  }
  state.counters["rays_per_s"] =
      benchmark::Counter(static_cast<double>(n), benchmark::Counter::kIsIterationInvariantRate);
  rtcReleaseScene(scene);
  rtcReleaseDevice(device);
}
BENCHMARK(BM_PrimaryRaysRawEmbree)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace
}  // namespace texbake
