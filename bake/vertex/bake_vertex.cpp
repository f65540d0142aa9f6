#include "bake/vertex/bake_vertex.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <optional>
#include <variant>

#include "bake/shade/shade.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "bake/vertex/occlusion_fill.h"
#include "bake/vertex/vertex_filter.h"
#include "bake/vertex/vertex_share.h"
#include "mapping/derivatives.h"
#include "mapping/mipmap.h"
#include "mapping/sample.h"
#include "mapping/tiled_image.h"

namespace texbake {

namespace {

// The 2D Morton (Z-order) code of (x, y) < 2^24 each: blocks near in the
// image are near in the order.
uint64_t morton2(uint32_t x, uint32_t y) {
  auto spread = [](uint64_t v) {
    v &= 0xFFFFFF;
    v = (v | (v << 16)) & 0x0000FFFF0000FFFFull;
    v = (v | (v << 8)) & 0x00FF00FF00FF00FFull;
    v = (v | (v << 4)) & 0x0F0F0F0F0F0F0F0Full;
    v = (v | (v << 2)) & 0x3333333333333333ull;
    v = (v | (v << 1)) & 0x5555555555555555ull;
    return v;
  };
  return spread(x) | (spread(y) << 1);
}

// Vertices per parallel chunk: one std::visit, one visibility batch and one
// progress update each. Small enough to balance the area filter's uneven cost.
constexpr std::size_t kVertexGrain = 1024;

enum VertexState : uint8_t { kVisible = 0, kOccluded = 1, kUndefined = 2 };

Vec3 to_vec(const Float3& p) {
  return {p.x, p.y, p.z};
}

// Everything a chunk reads, shared by all chunks.
struct BakeContext {
  const MeshData* mesh = nullptr;
  const VertexBakeOptions* options = nullptr;
  ShadeRule shade;  // image and constants in the working encoding
  const Adjacency* adjacency = nullptr;
  const EmbreeScene* scene = nullptr;  // null: no visibility test
  double ray_offset = 0;
  // The order in which the chunks visit the vertices (null: index order).
  const std::vector<uint32_t>* order = nullptr;
};

// The projected colour of vertex v (no visibility), or nullopt if no sample
// has a mapping: the shared vertex filter (bake/vertex/vertex_filter.h).
// vertex_map is proxy.inverse_map(position of v).
template <class P>
std::optional<Rgba> vertex_color(const P& proxy, const BakeContext& ctx, uint32_t v,
                                 const MapResult& vertex_map, VertexShare& share,
                                 FilterCounts& counts) {
  return filter_vertex(
      ctx.shade, ctx.options->filter, ctx.options->samples,
      [&proxy](const Vec3& p) { return proxy.inverse_map(p); },
      [&proxy](const Vec3& p) { return inverse_map_jacobian(proxy, p); }, *ctx.mesh, ctx.adjacency,
      v, vertex_map, share, counts);
}

// Per-chunk scratch, allocated once per chunk (never per sample).
struct ChunkScratch {
  std::vector<MapResult> maps;
  std::vector<uint32_t> ray_vertex;
  std::vector<uint8_t> visible;
  VertexShare share;
  VisibilityBatch batch;
};

template <class P>
void bake_chunk(const P& proxy, const BakeContext& ctx, std::size_t begin, std::size_t end,
                std::vector<Rgba>& colors, std::vector<uint8_t>& state, FilterCounts& counts) {
  const MeshData& mesh = *ctx.mesh;
  ChunkScratch scratch;
  scratch.maps.resize(end - begin);
  if (ctx.scene) {
    scratch.batch.reserve(end - begin);
    scratch.ray_vertex.reserve(end - begin);
  }
  const auto vertex = [&ctx](std::size_t i) -> std::size_t {
    return ctx.order ? (*ctx.order)[i] : i;
  };
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t v = vertex(i);
    const Vec3 p = to_vec(mesh.positions[v]);
    const MapResult m = proxy.inverse_map(p);
    scratch.maps[i - begin] = m;
    state[v] = kVisible;
    if (m.status == MapStatus::kUndefined) {
      state[v] = kUndefined;
    } else if (ctx.scene) {
      scratch.batch.add(p, m.to_projector);
      scratch.ray_vertex.push_back(static_cast<uint32_t>(v));
    }
  }
  if (ctx.scene && scratch.batch.size() > 0) {
    scratch.visible.resize(scratch.batch.size());
    scratch.batch.trace(*ctx.scene, ctx.ray_offset, scratch.visible.data());
    for (std::size_t i = 0; i < scratch.ray_vertex.size(); ++i) {
      if (!scratch.visible[i]) state[scratch.ray_vertex[i]] = kOccluded;
    }
  }
  const bool need_occluded_colors = ctx.options->occluded == OccludedMode::kProject;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t v = vertex(i);
    if (state[v] == kUndefined) continue;
    if (state[v] == kOccluded && !need_occluded_colors) continue;
    const std::optional<Rgba> c = vertex_color(proxy, ctx, static_cast<uint32_t>(v),
                                               scratch.maps[i - begin], scratch.share, counts);
    if (c) {
      colors[v] = *c;
    } else {
      state[v] = kUndefined;
    }
  }
}

// The vertices sorted by the Morton code of the 256-texel block of the
// image their inverse mapping lands in (unmapped ones last), ties by index.
std::vector<uint32_t> image_order(const MeshData& mesh, const Proxy& proxy,
                                  const ImageView& image) {
  const std::size_t n = mesh.positions.size();
  std::vector<uint64_t> keys(n);
  parallel_for_chunks(n, 16384, [&](std::size_t begin, std::size_t end) {
    std::visit(
        [&](const auto& p) {
          for (std::size_t v = begin; v < end; ++v) {
            const MapResult m = p.inverse_map(to_vec(mesh.positions[v]));
            uint64_t key = ~uint64_t{0};
            if (m.status != MapStatus::kUndefined) {
              const PixelPos px = pixel_from_uv(m.uv, image.width, image.height);
              const auto block = [](double c, int size) {
                return static_cast<uint32_t>(std::clamp(c, 0.0, size - 1.0)) >> 8;
              };
              key = morton2(block(px.x, image.width), block(px.y, image.height));
            }
            keys[v] = key;
          }
        },
        proxy);
  });
  std::vector<uint32_t> order(n);
  for (std::size_t v = 0; v < n; ++v) order[v] = static_cast<uint32_t>(v);
  std::stable_sort(order.begin(), order.end(),
                   [&keys](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
  return order;
}

// In bands of rows (read_rows), so a tiled image (mapping/tiled_image.h)
// is summed without being held whole; the same sums in the same order either way.
Rgba image_mean(const ImageView& image) {
  double sum[4] = {0, 0, 0, 0};
  constexpr int kBand = 64;
  std::vector<float> band(static_cast<std::size_t>(image.width) * kBand * 4);
  for (int y0 = 0; y0 < image.height; y0 += kBand) {
    const int y1 = std::min(image.height, y0 + kBand);
    read_rows(image, y0, y1, band.data());
    const std::size_t n = static_cast<std::size_t>(image.width) * (y1 - y0);
    for (std::size_t i = 0; i < n; ++i) {
      for (int k = 0; k < 4; ++k) sum[k] += band[4 * i + k];
    }
  }
  const double pixels = static_cast<double>(image.width) * image.height;
  Rgba mean;
  for (int k = 0; k < 4; ++k) mean[k] = static_cast<float>(sum[k] / pixels);
  return mean;
}

}  // namespace

Expected<VertexBakeStage> bake_vertex_sample(const MeshData& mesh, const ImageView& image,
                                             const Proxy& proxy, const VertexBakeOptions& options,
                                             Progress* progress, const EmbreeScene* shared_scene) {
  using Clock = std::chrono::steady_clock;
  VertexBakeStage stage;
  VertexBakeResult& result = stage.result;
  const std::size_t n = mesh.positions.size();
  result.counts.vertices = n;
  result.counts.triangles = mesh.triangles.size();
  result.colors.assign(n, Rgba{0, 0, 0, 1});

  // Scene (SPEC section 3): built once, LOW quality since every ray is traced
  // once; only when the visibility test is on.
  std::optional<EmbreeScene> scene;
  if (options.visibility == Visibility::kFirst && !shared_scene) {
    const auto start = Clock::now();
    Expected<EmbreeScene> built = EmbreeScene::build(mesh, BuildQuality::kLow);
    if (!built) return built.error();
    scene.emplace(std::move(built).value());
    result.timings.scene_build = seconds_since(start);
  }

  const auto bake_start = Clock::now();
  const WorkingImage working = working_image(image, options.linear);
  BakeContext ctx;
  ctx.mesh = &mesh;
  ctx.options = &options;
  ctx.shade = make_shade_rule(working.view, proxy, options);
  // --filter ewa: the pyramid of the working image (its encoding, as the
  // bilinear lookup's), built once per job.
  std::optional<MipPyramid> mip;
  if (options.filter == VertexFilter::kEwa) {
    mip.emplace(working.view, pyramid_rows);
    ctx.shade.mip = &*mip;
  }
  Adjacency adjacency;
  if (options.filter == VertexFilter::kArea || options.filter == VertexFilter::kEwa) {
    adjacency = build_adjacency(mesh);
    ctx.adjacency = &adjacency;
  }
  if (scene) {
    ctx.scene = &*scene;
    ctx.ray_offset = visibility_offset(*scene);
  } else if (shared_scene && options.visibility == Visibility::kFirst) {
    ctx.scene = shared_scene;
    ctx.ray_offset = visibility_offset(*shared_scene);
  }

  // A texture read in tiles (--cache-mb): visit the vertices in the order
  // of their place in the image, so that neighbouring lookups share tiles
  // and each tile of the file is read about once, not once per visit of a
  // scattered vertex order (a subdivided mesh appends its new vertices
  // level by level). Every vertex's colour is its own: the same result.
  std::vector<uint32_t> order;
  if (!working.view.data) {
    order = image_order(mesh, proxy, working.view);
    ctx.order = &order;
  }
  std::vector<uint8_t> state(n, kVisible);
  std::atomic<std::size_t> samples{0}, outside{0};
  if (progress) progress->start("bake", n);
  parallel_for_chunks(n, kVertexGrain, [&](std::size_t begin, std::size_t end) {
    if (is_cancelled(progress)) return;
    FilterCounts counts;
    std::visit([&](const auto& p) { bake_chunk(p, ctx, begin, end, result.colors, state, counts); },
               proxy);
    samples += counts.samples;
    outside += counts.outside;
    if (progress) progress->advance(end - begin);
  });
  if (is_cancelled(progress)) return cancelled_error();
  if (progress) progress->finish();
  scene.reset();  // the BVH is not needed any more: free it before the fill
  result.timings.bake = seconds_since(bake_start);

  // Occluded and undefined vertices (SPEC section 3): under --occluded fill
  // both are filled, under project only the undefined ones, under a colour
  // both take it.
  const auto fill_start = Clock::now();
  std::vector<uint8_t> unknown(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    if (state[v] == kOccluded) ++result.counts.occluded;
    if (state[v] == kUndefined) ++result.counts.undefined;
    unknown[v] = state[v] == kUndefined ||
                 (state[v] == kOccluded && options.occluded != OccludedMode::kProject);
  }
  FilterCounts fallback_counts;
  std::optional<Rgba> mean;
  VertexShare share;
  VertexResolve how;
  how.fill = options.occluded != OccludedMode::kColor;
  how.constant = options.occluded_color;
  how.linear = ctx.shade.linear;
  // Unanchored components take the projected colour; vertices without any
  // mapping take the image's mean colour (never black, never arbitrary).
  how.fallback = [&](uint32_t v) -> Rgba {
    if (state[v] == kOccluded) {
      return std::visit(
          [&](const auto& p) -> Rgba {
            const MapResult m = p.inverse_map(to_vec(mesh.positions[v]));
            if (auto c = vertex_color(p, ctx, v, m, share, fallback_counts)) return *c;
            if (!mean) mean = image_mean(ctx.shade.image);
            return *mean;
          },
          proxy);
    }
    if (!mean) mean = image_mean(ctx.shade.image);
    return *mean;
  };
  stage.plan = plan_resolve(mesh, result.colors, unknown, std::move(how));
  stage.plan.how.fallback = nullptr;  // it refers to this frame: not past it
  result.counts.filled = stage.plan.plan.result.filled;
  result.counts.unfilled = stage.plan.plan.result.unfilled;
  samples += fallback_counts.samples;
  outside += fallback_counts.outside;
  result.counts.samples = samples.load();
  result.counts.outside = outside.load();
  result.timings.fill = seconds_since(fill_start);
  if (Status s = check_texels_read(image); !s) return s.error();
  return stage;
}

Expected<VertexBakeResult> bake_vertex_finish(const MeshData& mesh, VertexBakeStage stage) {
  const auto fill_start = std::chrono::steady_clock::now();
  VertexBakeResult& result = stage.result;
  Expected<FillResult> filled = finish_resolve(mesh, result.colors, std::move(stage.plan));
  if (!filled) return filled.error();
  result.timings.fill += seconds_since(fill_start);
  return std::move(result);
}

Expected<VertexBakeResult> bake_vertex(const MeshData& mesh, const ImageView& image,
                                       const Proxy& proxy, const VertexBakeOptions& options,
                                       Progress* progress) {
  Expected<VertexBakeStage> stage = bake_vertex_sample(mesh, image, proxy, options, progress);
  if (!stage) return stage.error();
  return bake_vertex_finish(mesh, std::move(stage).value());
}

}  // namespace texbake
