// Filter quality (issue #16 item 3): a zone plate W x W/2 (frequency rising
// from 0 at the top-left corner to 0.5 cycles per texel, Nyquist, at the
// right and bottom edges) baked onto the bunny through a sphere, against a
// reference supersampled with the box filter at 256 samples (atlas: 256
// bilinear supersamples per texel; vertex: --filter area with 256 samples):
// PSNR (dB, over the baked texels / all vertices, RGB) and seconds for
// bilinear at 1, 4, 16 and 64 samples and ewa at 1 (atlas: bilinear
// supersamples vs ewa with one sample per texel; vertex: bilinear, area 4 /
// 16 / 64 and ewa). Visibility off (--visibility all) so that only the
// filter differs; atlas layout --uv proxy (the sphere's own (u, v), so
// every atlas texel covers about (W / size)^2 image texels: a uniform
// minification).
//
// Method "mip-mapped input": ewa with the image's MIP levels given
// (ImageView::mip_levels, as read_image hands over a maketx file's), made
// before the clock starts: the bake then reduces nothing.
//
// Run: build/texbake_bench --benchmark_filter=FilterQuality
// The case is W = 16384 at atlas 1024 (a 2 GB float image and
// 268M reference samples: minutes on 2 cores); W = 4096 at atlas 256 is the
// same 16:1 minification, quick.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include "bake/engine/bake_atlas.h"
#include "bake/engine/bake_vertex.h"
#include "bake/shade/shade.h"
#include "bake/uv/uv_proxy.h"
#include "bench/bench_meshes.h"
#include "mapping/mipmap.h"

namespace texbake {
namespace {

using bench::die;

const Image& zone_plate(int width) {
  static std::map<int, std::unique_ptr<Image>> cache;
  std::unique_ptr<Image>& slot = cache[width];
  if (!slot) {
    slot = std::make_unique<Image>();
    Image& img = *slot;
    img.width = width;
    img.height = width / 2;
    img.pixels.resize(static_cast<std::size_t>(img.width) * img.height * 4);
    // phase = pi x^2 / (2 W) + pi y^2 / (2 H): local frequency x / (2W) + y / (2H).
    for (int y = 0; y < img.height; ++y) {
      for (int x = 0; x < img.width; ++x) {
        const double phase = std::numbers::pi * (static_cast<double>(x) * x / (2.0 * img.width) +
                                                 static_cast<double>(y) * y / (2.0 * img.height));
        const float c = static_cast<float>(0.5 + 0.5 * std::cos(phase));
        float* p = &img.pixels[(static_cast<std::size_t>(y) * img.width + x) * 4];
        p[0] = p[1] = p[2] = c;
        p[3] = 1;
      }
    }
  }
  return *slot;
}

// The zone plate with its MIP levels given, as a MIP-mapped file (maketx)
// hands them to the bake: the levels are made once, outside the timed bake
// (here by the same box reduction the bake would run).
ImageView zone_plate_with_levels(int width) {
  struct Levels {
    std::unique_ptr<MipPyramid> mip;
    std::vector<ImageView> views;
  };
  static std::map<int, Levels> cache;
  Levels& l = cache[width];
  if (!l.mip) {
    l.mip = std::make_unique<MipPyramid>(zone_plate(width).view(), pyramid_rows);
    for (int i = 1; i < l.mip->levels(); ++i) l.views.push_back(l.mip->level(i));
  }
  ImageView v = zone_plate(width).view();
  v.mip_levels = l.views.data();
  v.mip_level_count = static_cast<int>(l.views.size());
  return v;
}

const MeshData& bunny_uv() {
  static const MeshData mesh = [] {
    Expected<ProxyUvLayout> l =
        proxy_uv_layout(bench::bunny(), bench::sphere_around(bench::bunny()));
    if (!l) die(l.error().message);
    return std::move(l->mesh);
  }();
  return mesh;
}

double psnr(const std::vector<Rgba>& a, const std::vector<Rgba>& b) {
  double sq = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    for (int k = 0; k < 3; ++k) sq += (a[i][k] - b[i][k]) * (a[i][k] - b[i][k]);
  }
  return -10 * std::log10(sq / (3.0 * static_cast<double>(a.size())));
}

// The baked texels of an atlas, in texel order.
std::vector<Rgba> baked_texels(const AtlasBakeResult& r) {
  std::vector<Rgba> out;
  for (std::size_t t = 0; t < r.baked.size(); ++t) {
    if (!r.baked[t]) continue;
    const float* p = &r.atlas.pixels[t * 4];
    out.push_back({p[0], p[1], p[2], p[3]});
  }
  return out;
}

AtlasBakeOptions atlas_options(int size, int samples, VertexFilter filter) {
  AtlasBakeOptions o;
  o.size = size;
  o.samples = samples;
  o.padding = 0;
  o.shading.visibility = Visibility::kAll;
  o.shading.filter = filter;
  return o;
}

AtlasBakeResult bake_atlas_or_die(int width, const AtlasBakeOptions& o, bool levels = false) {
  const MeshData& mesh = bunny_uv();
  Expected<AtlasBakeResult> r =
      bake_atlas(mesh, levels ? zone_plate_with_levels(width) : zone_plate(width).view(),
                 bench::sphere_around(bench::bunny()), o);
  if (!r) die(r.error().message);
  return std::move(*r);
}

// method: 0..3 bilinear at 1, 4, 16, 64 samples per texel, 4 ewa at 1, 5 ewa at 4,
// 6 ewa at 1 with the MIP levels given (a MIP-mapped input).
void BM_FilterQualityAtlas(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int size = static_cast<int>(state.range(1));
  const int method = static_cast<int>(state.range(2));
  static std::map<std::pair<int, int>, std::vector<Rgba>> references;
  std::vector<Rgba>& ref = references[{width, size}];
  if (ref.empty()) {
    ref = baked_texels(bake_atlas_or_die(width, atlas_options(size, 256, VertexFilter::kBilinear)));
  }
  const int samples[] = {1, 4, 16, 64, 1, 4, 1};
  const AtlasBakeOptions o = atlas_options(
      size, samples[method], method >= 4 ? VertexFilter::kEwa : VertexFilter::kBilinear);
  if (method == 6) zone_plate_with_levels(width);  // made before the clock starts
  double seconds = 0, db = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const AtlasBakeResult r = bake_atlas_or_die(width, o, method == 6);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    db = psnr(baked_texels(r), ref);
  }
  state.counters["psnr_db"] = db;
  state.counters["bake_s"] = seconds / static_cast<double>(state.iterations());
  const char* names[] = {"bilinear x1", "bilinear x4", "bilinear x16",           "bilinear x64",
                         "ewa x1",      "ewa x4",      "ewa x1 mip-mapped input"};
  state.SetLabel(names[method]);
}
BENCHMARK(BM_FilterQualityAtlas)
    ->ArgNames({"image", "atlas", "method"})
    ->ArgsProduct({{4096}, {256}, {0, 1, 2, 3, 4, 5, 6}})
    ->ArgsProduct({{16384}, {1024}, {0, 1, 2, 3, 4, 5, 6}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

VertexBakeResult bake_vertex_or_die(int width, VertexFilter filter, int samples,
                                    bool levels = false) {
  VertexBakeOptions o;
  o.visibility = Visibility::kAll;
  o.filter = filter;
  o.samples = samples;
  Expected<VertexBakeResult> r =
      bake_vertex(bench::bunny(), levels ? zone_plate_with_levels(width) : zone_plate(width).view(),
                  bench::sphere_around(bench::bunny()), o);
  if (!r) die(r.error().message);
  return std::move(*r);
}

// method: 0 bilinear, 1..3 area at 4, 16, 64 samples, 4 ewa, 5 ewa with the
// MIP levels given (a MIP-mapped input).
void BM_FilterQualityVertex(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int method = static_cast<int>(state.range(1));
  static std::map<int, std::vector<Rgba>> references;
  std::vector<Rgba>& ref = references[width];
  if (ref.empty()) ref = bake_vertex_or_die(width, VertexFilter::kArea, 256).colors;
  const VertexFilter filters[] = {VertexFilter::kBilinear, VertexFilter::kArea, VertexFilter::kArea,
                                  VertexFilter::kArea,     VertexFilter::kEwa,  VertexFilter::kEwa};
  const int samples[] = {1, 4, 16, 64, 1, 1};
  if (method == 5) zone_plate_with_levels(width);  // made before the clock starts
  double seconds = 0, db = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    const VertexBakeResult r =
        bake_vertex_or_die(width, filters[method], samples[method], method == 5);
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    db = psnr(r.colors, ref);
  }
  state.counters["psnr_db"] = db;
  state.counters["bake_s"] = seconds / static_cast<double>(state.iterations());
  const char* names[] = {"bilinear", "area x4", "area x16",
                         "area x64", "ewa",     "ewa mip-mapped input"};
  state.SetLabel(names[method]);
}
BENCHMARK(BM_FilterQualityVertex)
    ->ArgNames({"image", "method"})
    ->ArgsProduct({{4096, 16384}, {0, 1, 2, 3, 4, 5}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->UseRealTime();

}  // namespace
}  // namespace texbake

namespace texbake {
namespace {

// The pyramid's construction alone (levels and row means), W x W/2,
// serial (threads 0) or on the bake's threads (1, as the bakes build it).
void BM_MipPyramidBuild(benchmark::State& state) {
  const Image& img = zone_plate(static_cast<int>(state.range(0)));
  const RowRunner rows = state.range(1) ? RowRunner(pyramid_rows) : RowRunner();
  for (auto _ : state) {
    const MipPyramid mip(img.view(), rows);
    benchmark::DoNotOptimize(mip.level(1).data);
  }
}
BENCHMARK(BM_MipPyramidBuild)
    ->ArgNames({"image", "threads"})
    ->ArgsProduct({{4096}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace
}  // namespace texbake
