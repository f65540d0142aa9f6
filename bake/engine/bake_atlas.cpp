#include "bake/engine/bake_atlas.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <mutex>
#include <optional>
#include <string>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/atlas_samples.h"
#include "bake/atlas/dilate.h"
#include "bake/engine/bake_vertex.h"
#include "bake/shade/footprint.h"
#include "bake/shade/shade.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "mapping/derivatives.h"
#include "mapping/mipmap.h"
#include "mapping/sample.h"
#include "mapping/tiled_image.h"

namespace texbake {
namespace {

// Covered texels per sample batch: large enough to amortise a ray batch,
// small enough that the batch's buffers stay in cache.
constexpr std::size_t kTexelBatch = 1024;

struct SampleContext {
  const MeshData* mesh = nullptr;
  ShadeRule shade;  // image and constants in the working encoding
  const EmbreeScene* scene = nullptr;
  double ray_offset = 0;
  // Per vertex, working encoding: the fill, when computed before the pass
  // (null: texels that need it are deferred, see Deferred).
  const std::vector<Rgba>* fill_colors = nullptr;
  // --occluded R,G,B[,A] as given (sRGB-encoded): a texel all of whose
  // samples take it stores it exactly, as the vertex target does.
  Rgba occluded_color{};
  float* atlas = nullptr;    // size * size * 4
  uint8_t* baked = nullptr;  // size * size
  // --filter ewa: the footprint vectors' length in atlas UV units, the
  // supersample's cell side 1 / (size sqrt(samples)) over sqrt(2) (the
  // ellipse through the cell's corners; 0.85 of it at one sample per
  // texel, see bake_atlas); 0: the bilinear lookup.
  double cell = 0;
};

struct ChunkCounts {
  std::size_t occluded = 0, undefined = 0, outside = 0;
};

// Texels with samples to fill when the fill was not computed up front: their
// coloured sum so far and the fill samples' (triangle, b1, b2), finished after
// the pass (finish_deferred).
struct Deferred {
  struct Texel {
    uint32_t texel;
    std::array<double, 4> acc;
    uint32_t first, count;  // range in samples
  };
  struct Sample {
    uint32_t triangle;
    float b1, b2;
  };
  std::vector<Texel> texels;
  std::vector<Sample> samples;
};

// Per-thread buffers, reused across bands and batches: the hot loop does not
// allocate once they have grown.
struct Worker {
  AtlasBandScratch scratch;
  AtlasRaster band;
  VisibilityBatch batch;
  std::vector<MapResult> maps;
  std::vector<uint8_t> visible;
  ChunkCounts counts;
  Deferred deferred;
};

// An sRGB-encoded colour into texel t.
inline void store_color(const SampleContext& ctx, uint32_t t, const Rgba& c) {
  std::copy(c.begin(), c.end(), ctx.atlas + static_cast<std::size_t>(t) * 4);
  ctx.baked[t] = 1;
}

// The texel's plain mean into the atlas (back to sRGB when working in
// linear); `constants` of its samples took the --occluded colour.
inline void store_texel(const SampleContext& ctx, uint32_t t, const std::array<double, 4>& acc,
                        std::size_t spt, std::size_t constants = 0) {
  store_color(ctx, t, plain_texel(acc, spt, constants, ctx.occluded_color, [&](const Rgba& c) {
                return ctx.shade.stored(c);
              }));
}

Vec3 sample_point(const MeshData& mesh, uint32_t t, float b1, float b2) {
  const auto& tri = mesh.triangles[t];
  const Float3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
  const double w0 = 1.0 - b1 - b2;
  return {w0 * a.x + b1 * b.x + b2 * c.x, w0 * a.y + b1 * b.y + b2 * c.y,
          w0 * a.z + b1 * b.z + b2 * c.z};
}

// Texels [begin, end) of w.band: maps, traces and samples their samples and
// stores each texel's mean in the atlas. A texel's sum is the coloured
// samples in sample order, then the filled ones in sample order (double).
//
// Samples with further candidate triangles (r.alt_*, an overlapping layout;
// only listed when traced): each candidate's point is mapped and traced too
// (after the samples' own rays in the batch), and a sample whose own
// (lowest-index) triangle is occluded or undefined moves to the first
// candidate, in ascending triangle index, whose point is visible and mapped,
// if any: a texel shared by visible and hidden surfaces takes the visible
// ones' colour. The choice depends only on the sample, never on the thread
// count.
template <class P>
void bake_texels(const P& proxy, const SampleContext& ctx, Worker& w, std::size_t begin,
                 std::size_t end) {
  AtlasRaster& r = w.band;
  const std::size_t spt = r.samples_per_texel;
  const std::size_t s0 = begin * spt, s1 = end * spt;
  std::size_t a0 = 0, a1 = 0;  // r.alt_* entries of samples [s0, s1)
  if (ctx.scene && !r.alt_sample.empty()) {
    a0 = std::lower_bound(r.alt_sample.begin(), r.alt_sample.end(), s0) - r.alt_sample.begin();
    a1 = std::lower_bound(r.alt_sample.begin(), r.alt_sample.end(), s1) - r.alt_sample.begin();
  }
  const std::size_t own = s1 - s0;  // maps/visible: own samples, then the candidates
  w.maps.resize(own + (a1 - a0));
  w.batch.clear();
  for (std::size_t s = s0; s < s1; ++s) {
    const Vec3 p = sample_point(*ctx.mesh, r.sample_triangle[s], r.sample_b1[s], r.sample_b2[s]);
    MapResult& m = w.maps[s - s0];
    m = proxy.inverse_map(p);
    if (ctx.scene) {
      // Undefined samples get a dummy ray (their result is ignored) so that
      // batch index == sample index.
      w.batch.add(p, m.status == MapStatus::kUndefined ? Vec3{0, 0, 1} : m.to_projector);
    }
  }
  for (std::size_t a = a0; a < a1; ++a) {
    const Vec3 p = sample_point(*ctx.mesh, r.alt_triangle[a], r.alt_b1[a], r.alt_b2[a]);
    MapResult& m = w.maps[own + (a - a0)];
    m = proxy.inverse_map(p);
    w.batch.add(p, m.status == MapStatus::kUndefined ? Vec3{0, 0, 1} : m.to_projector);
  }
  w.visible.assign(own + (a1 - a0), 1);
  if (ctx.scene) w.batch.trace(*ctx.scene, ctx.ray_offset, w.visible.data());
  auto seen = [&](std::size_t i) {
    return w.visible[i] != 0 && w.maps[i].status != MapStatus::kUndefined;
  };
  for (std::size_t a = a0; a < a1;) {
    const std::size_t s = r.alt_sample[a];
    std::size_t a_end = a;
    while (a_end < a1 && r.alt_sample[a_end] == s) ++a_end;
    if (!seen(s - s0)) {
      for (std::size_t b = a; b < a_end; ++b) {
        if (!seen(own + (b - a0))) continue;
        w.maps[s - s0] = w.maps[own + (b - a0)];
        w.visible[s - s0] = 1;
        r.sample_triangle[s] = r.alt_triangle[b];
        r.sample_b1[s] = r.alt_b1[b];
        r.sample_b2[s] = r.alt_b2[b];
        break;
      }
    }
    a = a_end;
  }

  ChunkCounts& counts = w.counts;
  for (std::size_t k = begin; k < end; ++k) {
    std::array<double, 4> acc{0, 0, 0, 0};
    bool any_fill = false;
    std::size_t constants = 0;  // samples taking the --occluded colour
    for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
      const MapResult& m = w.maps[s - s0];
      const bool visible = w.visible[s - s0] != 0;
      if (m.status == MapStatus::kUndefined) {
        ++counts.undefined;
      } else if (!visible) {
        ++counts.occluded;
      }
      UvFootprint footprint{};
      if (ctx.cell > 0 && m.status != MapStatus::kUndefined) {
        // The sample's triangle after the overlap choice above.
        const uint32_t tri = r.sample_triangle[s];
        Vec3 ts, tt;
        cell_tangents(*ctx.mesh, tri, ctx.cell, ts, tt);
        const Vec3 p = sample_point(*ctx.mesh, tri, r.sample_b1[s], r.sample_b2[s]);
        footprint = uv_footprint(inverse_map_jacobian(proxy, p), ts, tt);
      }
      const Shaded c = ctx.shade.shade(m, visible, footprint);
      if (c.kind == Shade::kFill) {
        any_fill = true;
        continue;
      }
      if (c.kind == Shade::kOutside) ++counts.outside;
      if (c.kind == Shade::kConstant) ++constants;
      for (int ch = 0; ch < 4; ++ch) acc[ch] += c.color[ch];
    }
    const uint32_t t = r.texels[k];
    if (!any_fill) {
      store_texel(ctx, t, acc, spt, constants);
      continue;
    }
    // Occluded / undefined samples under --occluded fill (kProject fills
    // only the undefined ones): the per-vertex inpainting, interpolated over
    // the sample's triangle, added after the coloured samples.
    Deferred::Texel* later = nullptr;
    if (!ctx.fill_colors) {
      w.deferred.texels.push_back({t, acc, static_cast<uint32_t>(w.deferred.samples.size()), 0});
      later = &w.deferred.texels.back();
    }
    for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
      if (!ctx.shade.needs_fill(w.maps[s - s0], w.visible[s - s0] != 0)) continue;
      if (later) {
        w.deferred.samples.push_back({r.sample_triangle[s], r.sample_b1[s], r.sample_b2[s]});
        ++later->count;
      } else {
        add_interpolated(*ctx.mesh, *ctx.fill_colors, r.sample_triangle[s], r.sample_b1[s],
                         r.sample_b2[s], acc);
      }
    }
    if (!later) store_texel(ctx, t, acc, spt);
  }
}

int64_t nanoseconds(Clock::duration d) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(d).count();
}

}  // namespace

Expected<AtlasBakeResult> bake_atlas(const MeshData& mesh, const ImageView& image,
                                     const Proxy& proxy, const AtlasBakeOptions& options,
                                     Progress* progress) {
  if (Status s = check_padding(options.padding); !s) return s.error();
  const VertexBakeOptions& sh = options.shading;
  AtlasBakeResult result;

  // 1. Rasterise: the triangles binned into bands of rows. Each band is
  // rasterised and baked in one go below, so the samples of the whole atlas
  // (16 bytes each, 67M at 4096 with 4 samples) never exist at once. The
  // input is checked first; the bands themselves (48 bytes a triangle) are
  // made after the fill, whose solver then does not hold its memory beside
  // them (the 13.3M-triangle bake of bench/scale peaked during the fill).
  auto t0 = Clock::now();
  // Candidate triangles of overlapping samples matter only when rays choose.
  const bool overlaps = options.resolve_overlaps && sh.visibility == Visibility::kFirst;
  const AtlasRasterOptions raster_options{options.size, options.samples, overlaps};
  bool covers = false;  // some triangle reaches the atlas' rows: the bands are not empty
  if (Status s = AtlasBands::check(mesh, raster_options, &covers); !s) return s.error();
  double prepare_seconds = seconds_since(t0);

  // The scene, shared by the samples' rays and the fill's vertex bake.
  std::optional<EmbreeScene> scene;
  if (sh.visibility == Visibility::kFirst && covers) {
    t0 = Clock::now();
    Expected<EmbreeScene> built = EmbreeScene::build(mesh, BuildQuality::kLow);
    if (!built) return built.error();
    scene.emplace(std::move(*built));
    result.timings.scene_build = seconds_since(t0);
  }

  // The fill (per-vertex inpainting: bake_vertex with the bilinear filter and
  // --occluded fill), in the working encoding.
  auto fill_colors_for = [&]() -> Expected<std::vector<Rgba>> {
    VertexBakeOptions vo = sh;
    vo.filter = VertexFilter::kBilinear;
    vo.occluded = OccludedMode::kFill;
    Expected<VertexBakeStage> stage =
        bake_vertex_sample(mesh, image, proxy, vo, nullptr, scene ? &*scene : nullptr);
    if (!stage) return stage.error();
    Expected<VertexBakeResult> vertex = bake_vertex_finish(mesh, std::move(*stage));
    if (!vertex) return vertex.error();
    std::vector<Rgba> vc = std::move(vertex->colors);  // sRGB-encoded
    if (works_in_linear(image, sh.linear)) {
      for (Rgba& c : vc) c = srgb_to_linear(c);
    }
    return vc;
  };
  // With visibility and --occluded fill nearly every mesh has occluded
  // samples: compute the fill before the pass, so each streamed texel is
  // final once written. Otherwise only undefined samples (a proxy's singular
  // points) need it: their texels are deferred and finished after the pass,
  // if there are any.
  std::vector<Rgba> fill_colors;
  const bool fill_first =
      sh.occluded == OccludedMode::kFill && sh.visibility == Visibility::kFirst && covers;
  if (fill_first) {
    if (is_cancelled(progress)) return cancelled_error();
    t0 = Clock::now();
    Expected<std::vector<Rgba>> vc = fill_colors_for();
    if (!vc) return vc.error();
    fill_colors = std::move(*vc);
    result.timings.fill = seconds_since(t0);
  }

  t0 = Clock::now();
  Expected<AtlasBands> bands_or = AtlasBands::prepare(mesh, raster_options);
  if (!bands_or) return bands_or.error();
  const AtlasBands& bands = *bands_or;
  prepare_seconds += seconds_since(t0);

  // 2. Sample.
  t0 = Clock::now();
  const WorkingImage working = working_image(image, sh.linear);
  SampleContext ctx;
  ctx.mesh = &mesh;
  ctx.shade = make_shade_rule(working.view, proxy, sh);
  // --filter ewa: the pyramid of the working image, and each supersample's
  // cell (the texel split into samples cells of equal area).
  std::optional<MipPyramid> mip;
  if (sh.filter == VertexFilter::kEwa) {
    mip.emplace(working.view, pyramid_rows);
    ctx.shade.mip = &*mip;
    // The ellipse with conjugate semi-axes ts / sqrt(2), tt / sqrt(2) passes
    // through the cell's corners (ts +- tt) / 2: the smallest such ellipse
    // that covers the cell. (With the whole cell side as semi-axes, pbrt's
    // convention for a pixel's differentials, the zone-plate benchmark of
    // bench/filter_quality_bench.cpp loses 2.2 dB against the box reference.)
    // One lookup per texel (--samples 1) stands for the whole box alone: its
    // ellipse is 0.85 of that one, since the Gaussian widened by a texel of
    // its MIP level (and blended with the next, coarser level) is otherwise
    // wider than the box. Measured on that benchmark (one sample, 16:1):
    // 0.8 / 0.85 / 0.9 / 0.95 / 1 of the corner ellipse give 37.36 / 37.68 /
    // 37.64 / 37.35 / 36.93 dB at 16384 and 36.05 / 36.26 / 36.24 / 36.05 /
    // 35.76 at 4096. With several samples the cells' lookups overlap in the
    // texel's mean and the corner ellipse is best (at 4 samples 0.85 loses
    // 0.5 to 0.7 dB).
    ctx.cell = ewa_cell(options.size, options.samples);
  }
  ctx.fill_colors = fill_first ? &fill_colors : nullptr;
  ctx.occluded_color = sh.occluded_color;
  if (scene) {
    ctx.scene = &*scene;
    ctx.ray_offset = visibility_offset(*scene);
  }

  const int n = options.size;
  result.atlas.width = n;
  result.atlas.height = n;
  result.atlas.pixels.assign(static_cast<std::size_t>(n) * n * 4, 0.f);
  result.baked.assign(static_cast<std::size_t>(n) * n, 0);
  ctx.atlas = result.atlas.pixels.data();
  ctx.baked = result.baked.data();

  // Bands write disjoint rows of the atlas: no race, and each texel's value
  // depends only on its own samples, so the result is independent of the
  // thread count. Counts are integer sums (order-free).
  std::atomic<std::size_t> texels{0}, border{0}, occluded{0}, undefined{0}, outside{0};
  std::atomic<int64_t> raster_ns{0}, sample_ns{0};
  std::mutex deferred_mutex;
  std::vector<Deferred> deferred;
  if (progress) progress->start("sample", static_cast<std::size_t>(n));
  parallel_for_chunks(bands.band_count(), 1, [&](std::size_t band_begin, std::size_t band_end) {
    if (is_cancelled(progress)) return;
    Worker w;
    int64_t r_ns = 0, s_ns = 0;
    std::size_t t_count = 0, b_count = 0;
    std::visit(
        [&](const auto& p) {
          for (std::size_t band = band_begin; band < band_end; ++band) {
            const auto ta = Clock::now();
            bands.rasterize(band, w.band, w.scratch);
            const auto tb = Clock::now();
            const std::size_t count = w.band.texels.size();
            for (std::size_t k = 0; k < count; k += kTexelBatch) {
              bake_texels(p, ctx, w, k, std::min(count, k + kTexelBatch));
            }
            r_ns += nanoseconds(tb - ta);
            s_ns += nanoseconds(Clock::now() - tb);
            t_count += count;
            b_count += w.band.border_samples;
            if (progress) progress->advance(bands.band_rows(band));
          }
        },
        proxy);
    texels += t_count;
    border += b_count;
    occluded += w.counts.occluded;
    undefined += w.counts.undefined;
    outside += w.counts.outside;
    raster_ns += r_ns;
    sample_ns += s_ns;
    if (!w.deferred.texels.empty()) {
      std::lock_guard<std::mutex> lock(deferred_mutex);
      deferred.push_back(std::move(w.deferred));
    }
  });
  if (is_cancelled(progress)) return cancelled_error();
  if (progress) progress->finish();
  scene.reset();
  result.counts.texels = texels.load();
  result.counts.samples = result.counts.texels * static_cast<std::size_t>(options.samples);
  result.counts.border_samples = border.load();
  result.counts.occluded = occluded.load();
  result.counts.undefined = undefined.load();
  result.counts.outside = outside.load();
  // Rasterising and sampling interleave per band: the pass's wall time is
  // split between the two in proportion to the thread time each took.
  const double pass = seconds_since(t0);
  const double busy = static_cast<double>(raster_ns.load() + sample_ns.load());
  const double raster_share = busy > 0 ? raster_ns.load() / busy : 0;
  result.timings.rasterize = prepare_seconds + pass * raster_share;
  result.timings.sample = pass * (1 - raster_share);

  // Deferred texels (their order does not matter: each is independent).
  if (!deferred.empty()) {
    t0 = Clock::now();
    Expected<std::vector<Rgba>> vc = fill_colors_for();
    if (!vc) return vc.error();
    for (const Deferred& d : deferred) {
      for (Deferred::Texel texel : d.texels) {
        for (uint32_t i = texel.first; i < texel.first + texel.count; ++i) {
          const Deferred::Sample& ds = d.samples[i];
          add_interpolated(mesh, *vc, ds.triangle, ds.b1, ds.b2, texel.acc);
        }
        store_texel(ctx, texel.texel, texel.acc, static_cast<std::size_t>(options.samples));
      }
    }
    result.timings.fill = seconds_since(t0);
  }

  // 3. Pad.
  t0 = Clock::now();
  result.counts.padded = pad_atlas(result.atlas.pixels, result.baked, n, options.padding);
  result.timings.pad = seconds_since(t0);
  if (Status s = check_texels_read(image); !s) return s.error();
  return result;
}

}  // namespace texbake
