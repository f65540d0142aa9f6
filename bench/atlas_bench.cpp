// Atlas target benchmarks (issue #4): the bunny (75k triangles) and the
// armadillo subdivided twice 1-to-4 (832k triangles) with generated UVs, a
// sphere proxy around the mesh, the Earth map, visibility on, --occluded fill,
// at 2048 and 4096 and 1 and 4 samples per texel: seconds per stage as
// counters (rasterise, scene_build, sample, fill, pad, write) and the job
// without the UV layout ("bake_write"). The UV layout (bake/uv/uv_*, its
// own benchmark in uv_generate_bench.cpp) is computed once per mesh and size,
// outside the timed loop; its time is the "uv_layout" counter.
//
// Run: build-dev/texbake_bench --benchmark_filter=Atlas
// The laid-out meshes are also written as OBJ with vt to
// $TMPDIR/texbake_atlas_<mesh>_<size>.obj (BM_AtlasWriteLayout) so the CLI
// can be timed end to end with `--uv mesh` (everything but the UV layout) or
// on the .ply of bake_bench.cpp with `--uv generate`.
//
// bake_cpu / write_cpu: process CPU seconds (all threads) of bake_atlas and
// of the write, steadier than wall time when other jobs load the machine.
// Peak memory is a process-wide figure: measure it on the CLI with
// /usr/bin/time -v (see the closing note of issue #4).
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <string>

#include "bake/atlas/dilate.h"
#include "bake/engine/bake_atlas.h"
#include "bake/engine/bake_vertex.h"
#include "bake/uv/uv_generate.h"
#include "bench/bench_meshes.h"
#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "mesh_io/write_mesh.h"
#include "mesh_io/write_textured.h"

namespace texbake {
namespace {

using bench::die;
using bench::earth;
using bench::sphere_around;

namespace fs = std::filesystem;
const fs::path kData = TEXBAKE_DATA_DIR;

fs::path temp_dir() {
  const char* t = std::getenv("TMPDIR");
  return t && *t ? fs::path(t) : fs::temp_directory_path();
}

const MeshData& source_mesh(int which) {
  const MeshData& bunny = bench::bunny();
  if (which == 0) return bunny;
  const MeshData& armadillo = bench::armadillo_832k();
  return armadillo;
}
const char* mesh_name(int which) {
  return which == 0 ? "bunny" : "armadillo832k";
}

// Process CPU seconds (user + system, all threads): on a loaded machine a
// steadier figure than wall time.
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

struct Layout {
  MeshData mesh;
  double seconds = 0;
};

// The generated UV layout of mesh `which` at `size` (gutter: the default
// padding, at least 2, as lay_out_uvs uses, bake/uv/uv_layout.h), computed once.
const Layout& layout(int which, int size) {
  static std::map<std::pair<int, int>, Layout> cache;
  auto it = cache.find({which, size});
  if (it != cache.end()) return it->second;
  const MeshData& m = source_mesh(which);
  UvGenerateOptions go;
  go.atlas_size = size;
  go.padding = std::max(default_padding(size), 2);
  const auto t0 = std::chrono::steady_clock::now();
  Expected<UvAtlas> atlas = generate_uv_atlas(m, go);
  if (!atlas) die(atlas.error().message);
  Layout l;
  l.mesh = mesh_with_triangle_uvs(m, atlas->uvs, atlas->triangle_uvs);
  l.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return cache.emplace(std::pair{which, size}, std::move(l)).first->second;
}

// Arguments: mesh (0 bunny, 1 armadillo 832k), size, samples per texel,
// output (0 .obj + .png, 1 .glb).
void BM_AtlasJob(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const int size = static_cast<int>(state.range(1));
  const Layout& l = layout(which, size);
  const Proxy proxy = sphere_around(l.mesh);
  AtlasBakeOptions options;
  options.size = size;
  options.samples = static_cast<int>(state.range(2));
  const bool glb = state.range(3) != 0;
  const fs::path out = temp_dir() / (std::string("texbake_atlas_bench_") + mesh_name(which) +
                                     (glb ? ".glb" : ".obj"));
  AtlasBakeTimings sum;
  AtlasBakeCounts counts;
  double write = 0, total = 0, bake_cpu = 0, write_cpu = 0;
  for (auto _ : state) {
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    Expected<AtlasBakeResult> r = bake_atlas(l.mesh, earth().view(), proxy, options);
    if (!r) {
      state.SkipWithError(r.error().message.c_str());
      return;
    }
    const auto t1 = std::chrono::steady_clock::now();
    const double c1 = cpu_seconds();
    if (Status s = write_textured_mesh(out, l.mesh, r->atlas.view()); !s) {
      state.SkipWithError(s.error().message.c_str());
      return;
    }
    const auto t2 = std::chrono::steady_clock::now();
    bake_cpu += c1 - c0;
    write_cpu += cpu_seconds() - c1;
    write += std::chrono::duration<double>(t2 - t1).count();
    total += std::chrono::duration<double>(t2 - t0).count();
    sum.rasterize += r->timings.rasterize;
    sum.scene_build += r->timings.scene_build;
    sum.sample += r->timings.sample;
    sum.fill += r->timings.fill;
    sum.pad += r->timings.pad;
    counts = r->counts;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["uv_layout"] = l.seconds;
  state.counters["rasterize"] = sum.rasterize / n;
  state.counters["scene_build"] = sum.scene_build / n;
  state.counters["sample"] = sum.sample / n;
  state.counters["fill"] = sum.fill / n;
  state.counters["pad"] = sum.pad / n;
  state.counters["write"] = write / n;
  state.counters["bake_write"] = total / n;
  state.counters["bake_cpu"] = bake_cpu / n;
  state.counters["write_cpu"] = write_cpu / n;
  state.counters["texels"] = static_cast<double>(counts.texels);
  state.counters["samples"] = static_cast<double>(counts.samples);
  state.counters["occluded"] = static_cast<double>(counts.occluded);
  state.SetLabel(mesh_name(which));
  std::error_code ec;
  fs::remove(out, ec);
  fs::remove(fs::path(out).replace_extension(".mtl"), ec);
  fs::remove(fs::path(out).replace_extension(".png"), ec);
}

BENCHMARK(BM_AtlasJob)
    ->ArgNames({"mesh", "size", "samples", "glb"})
    ->Args({0, 2048, 4, 0})
    ->Args({0, 2048, 1, 0})
    ->Args({0, 4096, 4, 0})
    ->Args({0, 4096, 1, 0})
    ->Args({0, 2048, 4, 1})
    ->Args({1, 2048, 4, 0})
    ->Args({1, 2048, 1, 0})
    ->Args({1, 4096, 4, 0})
    ->Args({1, 4096, 1, 0})
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// The --occluded fill's per-vertex bake as bake_atlas runs it (bilinear
// filter, visibility, fill) on the laid-out mesh: its own stages.
void BM_AtlasFillVertexBake(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const Layout& l = layout(which, 2048);
  VertexBakeOptions vo;
  vo.filter = VertexFilter::kBilinear;
  VertexBakeTimings t;
  for (auto _ : state) {
    Expected<VertexBakeResult> r = bake_vertex(l.mesh, earth().view(), sphere_around(l.mesh), vo);
    if (!r) die(r.error().message);
    t = r->timings;
  }
  state.counters["scene_build"] = t.scene_build;
  state.counters["bake"] = t.bake;
  state.counters["fill"] = t.fill;
}
BENCHMARK(BM_AtlasFillVertexBake)
    ->Arg(0)
    ->Arg(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime()
    ->Iterations(1);

// The PNG atlas write at each zlib level (TexturedWriteOptions::png_compression):
// seconds and bytes of the padded bunny atlas (2048 or 4096, 4 samples), the
// measurement behind kAtlasPngCompression.
void BM_AtlasPngLevel(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  static std::map<int, Image> atlases;
  if (!atlases.count(size)) {
    const Layout& l = layout(0, size);
    AtlasBakeOptions options;
    options.size = size;
    Expected<AtlasBakeResult> r =
        bake_atlas(l.mesh, earth().view(), sphere_around(l.mesh), options);
    if (!r) die(r.error().message);
    atlases[size] = std::move(r->atlas);
  }
  const Image& atlas = atlases[size];
  ImageWriteOptions o;
  o.png_compression = static_cast<int>(state.range(1));
  const fs::path out = temp_dir() / "texbake_atlas_bench_level.png";
  for (auto _ : state) {
    if (Status s = write_image(out, atlas.view(), o); !s) {
      state.SkipWithError(s.error().message.c_str());
      return;
    }
  }
  state.counters["MB"] = static_cast<double>(fs::file_size(out)) / 1e6;
  std::error_code ec;
  fs::remove(out, ec);
}
BENCHMARK(BM_AtlasPngLevel)
    ->ArgNames({"size", "level"})
    ->ArgsProduct({{2048, 4096}, {1, 2, 3, 4, 6}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->Iterations(2);

// Writes the laid-out meshes as OBJ with vt for CLI timing (see the top).
void BM_AtlasWriteLayout(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0));
  const int size = static_cast<int>(state.range(1));
  const Layout& l = layout(which, size);
  const fs::path out = temp_dir() / (std::string("texbake_atlas_") + mesh_name(which) + "_" +
                                     std::to_string(size) + ".obj");
  for (auto _ : state) {
    if (Status s = write_mesh(out, l.mesh); !s) {
      state.SkipWithError(s.error().message.c_str());
      return;
    }
  }
  state.SetLabel(out.string());
}
BENCHMARK(BM_AtlasWriteLayout)
    ->Args({0, 2048})
    ->Args({1, 2048})
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

}  // namespace
}  // namespace texbake
