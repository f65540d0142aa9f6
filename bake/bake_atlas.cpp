#include "bake/bake_atlas.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <optional>
#include <string>

#include "bake/atlas_raster.h"
#include "bake/bake_vertex.h"
#include "bake/dilate.h"
#include "bake/embree_scene.h"
#include "bake/parallel.h"
#include "bake/visibility.h"
#include "mapping/sample.h"

namespace texbake {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// Covered texels per parallel work item: large enough to amortise a ray
// batch, small enough to balance.
constexpr std::size_t kTexelGrain = 1024;

// Per-sample outcome of the sampling pass.
enum : uint8_t { kSampleColoured = 0, kSampleNeedsFill = 1 };

struct SampleContext {
  const MeshData* mesh = nullptr;
  const AtlasRaster* raster = nullptr;
  ImageView image;  // linear copy with shading.linear
  WrapMode wrap_u = WrapMode::kClamp, wrap_v = WrapMode::kClamp;
  bool no_outside = false;
  bool outside_constant = false;
  Rgba outside_color{};   // working encoding
  Rgba occluded_color{};  // working encoding
  OccludedMode occluded = OccludedMode::kFill;
  const EmbreeScene* scene = nullptr;
  double ray_offset = 0;
};

struct ChunkCounts {
  std::size_t occluded = 0, undefined = 0, outside = 0;
};

Vec3 sample_point(const MeshData& mesh, uint32_t t, float b1, float b2) {
  const auto& tri = mesh.triangles[t];
  const Float3 a = mesh.positions[tri[0]], b = mesh.positions[tri[1]], c = mesh.positions[tri[2]];
  const double w0 = 1.0 - b1 - b2;
  return {w0 * a.x + b1 * b.x + b2 * c.x, w0 * a.y + b1 * b.y + b2 * c.y,
          w0 * a.z + b1 * b.z + b2 * c.z};
}

// One chunk of covered texels [begin, end): writes sums[texel k] (RGBA,
// double) for coloured samples and flags the samples still to fill.
template <class P>
void sample_chunk(const P& proxy, const SampleContext& ctx, std::size_t begin, std::size_t end,
                  std::vector<std::array<double, 4>>& sums, std::vector<uint8_t>& needs_fill,
                  VisibilityBatch& batch, std::vector<MapResult>& maps,
                  std::vector<uint8_t>& visible, ChunkCounts& counts) {
  const AtlasRaster& r = *ctx.raster;
  const std::size_t spt = r.samples_per_texel;
  const std::size_t s0 = begin * spt, s1 = end * spt;
  maps.resize(s1 - s0);
  batch.clear();
  for (std::size_t s = s0; s < s1; ++s) {
    const Vec3 p = sample_point(*ctx.mesh, r.sample_triangle[s], r.sample_b1[s], r.sample_b2[s]);
    maps[s - s0] = proxy.inverse_map(p);
    if (ctx.scene) {
      // Undefined samples get a dummy ray (their result is ignored) so that
      // batch index == sample index.
      const MapResult& m = maps[s - s0];
      batch.add(p, m.status == MapStatus::kUndefined ? Vec3{0, 0, 1} : m.to_projector);
    }
  }
  visible.assign(s1 - s0, 1);
  if (ctx.scene) batch.trace(*ctx.scene, ctx.ray_offset, visible.data());

  for (std::size_t k = begin; k < end; ++k) {
    std::array<double, 4> acc{0, 0, 0, 0};
    for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
      const MapResult& m = maps[s - s0];
      Rgba c;
      if (m.status == MapStatus::kUndefined) {
        ++counts.undefined;
        if (ctx.occluded == OccludedMode::kColor) {
          c = ctx.occluded_color;
        } else {
          needs_fill[s] = kSampleNeedsFill;
          continue;
        }
      } else if (!visible[s - s0] && ctx.occluded != OccludedMode::kProject) {
        ++counts.occluded;
        if (ctx.occluded == OccludedMode::kColor) {
          c = ctx.occluded_color;
        } else {
          needs_fill[s] = kSampleNeedsFill;
          continue;
        }
      } else {
        if (!visible[s - s0]) ++counts.occluded;
        if (m.status == MapStatus::kOutside && !ctx.no_outside) {
          ++counts.outside;
          c = ctx.outside_constant ? ctx.outside_color
                                   : sample_bilinear(ctx.image, m.uv, ctx.wrap_u, ctx.wrap_v);
        } else {
          c = sample_bilinear(ctx.image, m.uv, ctx.wrap_u, ctx.wrap_v);
        }
      }
      for (int ch = 0; ch < 4; ++ch) acc[ch] += c[ch];
    }
    sums[k] = acc;
  }
}

}  // namespace

Expected<AtlasBakeResult> bake_atlas(const MeshData& mesh, const ImageView& image,
                                     const Proxy& proxy, const AtlasBakeOptions& options,
                                     Progress* progress) {
  if (options.padding < 0 && options.padding != kPaddingDefault &&
      options.padding != kPaddingInfinite) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--padding " + std::to_string(options.padding) + " is negative");
  }
  const VertexBakeOptions& sh = options.shading;
  AtlasBakeResult result;

  // 1. Rasterise.
  auto t0 = Clock::now();
  Expected<AtlasRaster> raster_or = rasterize_atlas(mesh, {options.size, options.samples});
  if (!raster_or) return raster_or.error();
  const AtlasRaster& raster = *raster_or;
  result.timings.rasterize = seconds_since(t0);
  const std::size_t n_texels = raster.texels.size();
  const std::size_t spt = raster.samples_per_texel;
  result.counts.texels = n_texels;
  result.counts.samples = raster.sample_count();
  result.counts.border_samples = raster.border_samples;

  // 2. Sample.
  std::optional<EmbreeScene> scene;
  if (sh.visibility == Visibility::kFirst && n_texels > 0) {
    t0 = Clock::now();
    Expected<EmbreeScene> built = EmbreeScene::build(mesh, BuildQuality::kLow);
    if (!built) return built.error();
    scene.emplace(std::move(*built));
    result.timings.scene_build = seconds_since(t0);
  }
  t0 = Clock::now();
  std::vector<float> linear_pixels;
  SampleContext ctx;
  ctx.mesh = &mesh;
  ctx.raster = &raster;
  ctx.image = image;
  if (sh.linear) {
    linear_pixels.assign(image.data,
                         image.data + static_cast<std::size_t>(image.width) * image.height * 4);
    for (std::size_t i = 0; i < linear_pixels.size(); i += 4) {
      for (int c = 0; c < 3; ++c) linear_pixels[i + c] = srgb_to_linear(linear_pixels[i + c]);
    }
    ctx.image.data = linear_pixels.data();
  }
  ctx.wrap_u = wrap_u(proxy);
  ctx.wrap_v = wrap_v(proxy);
  if (std::holds_alternative<Plane>(proxy) && sh.plane_wrap == WrapMode::kRepeat) {
    ctx.wrap_u = ctx.wrap_v = WrapMode::kRepeat;
    ctx.no_outside = true;
  }
  ctx.outside_constant = sh.outside == OutsideMode::kColor;
  ctx.outside_color = sh.outside_color;
  ctx.occluded_color = sh.occluded_color;
  if (sh.linear) {
    for (int c = 0; c < 3; ++c) {
      ctx.outside_color[c] = srgb_to_linear(ctx.outside_color[c]);
      ctx.occluded_color[c] = srgb_to_linear(ctx.occluded_color[c]);
    }
  }
  ctx.occluded = sh.occluded;
  if (scene) {
    ctx.scene = &*scene;
    ctx.ray_offset = visibility_offset(*scene);
  }

  std::vector<std::array<double, 4>> sums(n_texels);
  std::vector<uint8_t> needs_fill(raster.sample_count(), kSampleColoured);
  std::atomic<std::size_t> occluded{0}, undefined{0}, outside{0};
  if (progress) progress->start("atlas", n_texels);
  parallel_for_chunks(n_texels, kTexelGrain, [&](std::size_t begin, std::size_t end) {
    VisibilityBatch batch;
    std::vector<MapResult> maps;
    std::vector<uint8_t> visible;
    ChunkCounts counts;
    std::visit(
        [&](const auto& p) {
          sample_chunk(p, ctx, begin, end, sums, needs_fill, batch, maps, visible, counts);
        },
        proxy);
    occluded += counts.occluded;
    undefined += counts.undefined;
    outside += counts.outside;
    if (progress) progress->advance(end - begin);
  });
  if (progress) progress->finish();
  scene.reset();
  result.counts.occluded = occluded.load();
  result.counts.undefined = undefined.load();
  result.counts.outside = outside.load();
  result.timings.sample = seconds_since(t0);

  // Occluded / undefined samples under --occluded fill: the per-vertex
  // inpainting, interpolated over the sample's triangle.
  const bool any_fill =
      std::any_of(needs_fill.begin(), needs_fill.end(), [](uint8_t f) { return f != 0; });
  if (any_fill) {
    t0 = Clock::now();
    VertexBakeOptions vo = sh;
    vo.filter = VertexFilter::kBilinear;
    vo.occluded = OccludedMode::kFill;
    Expected<VertexBakeResult> vertex = bake_vertex(mesh, image, proxy, vo, nullptr);
    if (!vertex) return vertex.error();
    std::vector<Rgba>& vc = vertex->colors;  // sRGB-encoded
    if (sh.linear) {
      for (Rgba& c : vc)
        for (int k = 0; k < 3; ++k) c[k] = srgb_to_linear(c[k]);
    }
    parallel_for_chunks(n_texels, kTexelGrain * 4, [&](std::size_t begin, std::size_t end) {
      for (std::size_t k = begin; k < end; ++k) {
        for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
          if (!needs_fill[s]) continue;
          const auto& tri = mesh.triangles[raster.sample_triangle[s]];
          const double b1 = raster.sample_b1[s], b2 = raster.sample_b2[s], b0 = 1 - b1 - b2;
          for (int ch = 0; ch < 4; ++ch) {
            sums[k][ch] += b0 * vc[tri[0]][ch] + b1 * vc[tri[1]][ch] + b2 * vc[tri[2]][ch];
          }
        }
      }
    });
    result.timings.fill = seconds_since(t0);
  }

  // Texel means into the atlas.
  const int n = options.size;
  result.atlas.width = n;
  result.atlas.height = n;
  result.atlas.pixels.assign(static_cast<std::size_t>(n) * n * 4, 0.f);
  result.baked.assign(static_cast<std::size_t>(n) * n, 0);
  parallel_for_chunks(n_texels, kTexelGrain * 4, [&](std::size_t begin, std::size_t end) {
    for (std::size_t k = begin; k < end; ++k) {
      const std::size_t t = raster.texels[k];
      float* px = &result.atlas.pixels[t * 4];
      for (int ch = 0; ch < 4; ++ch) {
        float v = static_cast<float>(sums[k][ch] / spt);
        if (sh.linear && ch < 3) v = linear_to_srgb(v);
        px[ch] = v;
      }
      result.baked[t] = 1;
    }
  });

  // 3. Pad.
  t0 = Clock::now();
  if (options.padding == kPaddingInfinite) {
    result.counts.padded = push_pull_fill(result.atlas.pixels, result.baked, n, n);
  } else {
    const int rings = options.padding == kPaddingDefault ? default_padding(n) : options.padding;
    std::vector<uint8_t> mask = result.baked;
    result.counts.padded = dilate(result.atlas.pixels, mask, n, n, rings);
  }
  result.timings.pad = seconds_since(t0);
  return result;
}

MeshData mesh_with_triangle_uvs(const MeshData& mesh, const std::vector<Float2>& uvs,
                                const std::vector<std::array<uint32_t, 3>>& triangle_uvs) {
  MeshData out;
  out.positions = mesh.positions;
  out.uvs = uvs;
  const bool normals = !mesh.corner_normal.empty();
  if (normals) out.normals = mesh.normals;
  out.face_offsets.push_back(0);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const uint32_t base = static_cast<uint32_t>(out.face_vertices.size());
    for (int k = 0; k < 3; ++k) {
      out.face_vertices.push_back(mesh.triangles[t][k]);
      out.corner_uv.push_back(triangle_uvs[t][k]);
      if (normals) out.corner_normal.push_back(mesh.corner_normal[mesh.triangle_corners[t][k]]);
    }
    out.face_offsets.push_back(base + 3);
    out.triangles.push_back(mesh.triangles[t]);
    out.triangle_corners.push_back({base, base + 1, base + 2});
    out.triangle_face.push_back(static_cast<uint32_t>(t));
  }
  return out;
}

}  // namespace texbake
