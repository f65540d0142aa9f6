#include "bake/layers/layers_bake.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "bake/photo/segments.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "bake/vertex/occlusion_fill.h"
#include "mapping/sample.h"
#include "mesh_io/vertex_normals.h"

namespace texbake {

namespace {

constexpr std::size_t kGrain = 4096;  // vertices per parallel block

// A layer's texture as premultiplied linear RGBA (bilinear interpolation of
// premultiplied values keeps a transparent border from darkening the
// colour next to it).
std::vector<float> premultiplied_linear(const ImageView& image) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  std::vector<float> out(image.data, image.data + 4 * n);
  const bool srgb = image.color_space != ColorSpace::kLinear;
  parallel_for_chunks(n, 1 << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      float* p = &out[4 * i];
      for (int c = 0; c < 3; ++c) p[c] = (srgb ? srgb_to_linear(p[c]) : p[c]) * p[3];
    }
  });
  return out;
}

// What one layer gives one point: its straight linear colour and a.
struct Contribution {
  std::array<float, 3> rgb{0, 0, 0};
  float a = 0;
};

struct LayerCounts {
  std::size_t in_domain = 0, visible = 0, blended = 0;
  double alpha_sum = 0;
};

// The prepared layer: working images and wrap rules.
struct Prepared {
  const LayerInput* input = nullptr;
  std::vector<float> texture;  // premultiplied linear RGBA
  ImageView view;
  WrapMode wrap_u = WrapMode::kClamp, wrap_v = WrapMode::kClamp;
  const CameraProjector* camera = nullptr;    // null: an analytic proxy
  double cos_a0 = 1, cos_a1 = 0;              // the angle fade's limits as cosines
  std::array<float, 3> outside_rgb{0, 0, 0};  // linear
};

float fade(const Prepared& layer, double cosine) {
  if (!layer.input->angle_fade) return 1;
  const auto [a0, a1] = *layer.input->angle_fade;
  if (cosine >= layer.cos_a0) return 1;
  if (cosine <= layer.cos_a1) return 0;
  const double theta = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / std::numbers::pi;
  return static_cast<float>(std::clamp((a1 - theta) / (a1 - a0), 0.0, 1.0));
}

// Contributions of one layer for the vertices [begin, end).
template <class Map>
void layer_block(const Prepared& layer, const Map& map, const MeshData& mesh,
                 const std::vector<Float3>& normals, const EmbreeScene* scene, double offset,
                 std::size_t begin, std::size_t end, Contribution* out, LayerCounts& counts) {
  const LayerInput& in = *layer.input;
  const std::size_t m = end - begin;
  std::vector<MapResult> maps(m);
  std::vector<uint8_t> seen(m, 1);
  for (std::size_t i = 0; i < m; ++i) {
    const Float3& q = mesh.positions[begin + i];
    maps[i] = map(Vec3{q.x, q.y, q.z});
    if (maps[i].status == MapStatus::kUndefined) seen[i] = 0;
    if (layer.camera) {
      // A camera sees only surfaces facing it; behind it nothing is mapped.
      const Float3& nf = normals[begin + i];
      if (!(dot(Vec3{nf.x, nf.y, nf.z}, maps[i].to_projector) > 0)) seen[i] = 0;
      if (maps[i].status == MapStatus::kOutside &&
          layer.camera->project(Vec3{q.x, q.y, q.z}).outside != CameraOutside::kOffPhoto) {
        seen[i] = 0;
      }
    }
  }
  if (scene && in.visibility == LayerVisibility::kFirst) {
    if (layer.camera) {
      std::vector<uint32_t> ids;
      std::vector<std::size_t> slot;
      for (std::size_t i = 0; i < m; ++i) {
        if (seen[i]) ids.push_back(static_cast<uint32_t>(begin + i)), slot.push_back(i);
      }
      SegmentScratch scratch;
      std::vector<uint8_t> occluded(ids.size(), 0);
      occluded_segments(*scene, offset, mesh, ids, layer.camera->centre(), scratch,
                        occluded.data());
      for (std::size_t k = 0; k < ids.size(); ++k) {
        if (occluded[k]) seen[slot[k]] = 0;
      }
    } else {
      VisibilityBatch batch;
      std::vector<std::size_t> slot;
      for (std::size_t i = 0; i < m; ++i) {
        if (!seen[i]) continue;
        const Float3& q = mesh.positions[begin + i];
        batch.add(Vec3{q.x, q.y, q.z}, maps[i].to_projector);
        slot.push_back(i);
      }
      std::vector<uint8_t> visible(slot.size(), 0);
      if (!slot.empty()) batch.trace(*scene, offset, visible.data());
      for (std::size_t k = 0; k < slot.size(); ++k) {
        if (!visible[k]) seen[slot[k]] = 0;
      }
    }
  }
  for (std::size_t i = 0; i < m; ++i) {
    Contribution& c = out[begin + i];
    c = {};
    const MapResult& r = maps[i];
    if (r.status == MapStatus::kOk) ++counts.in_domain;
    if (r.status == MapStatus::kUndefined) continue;
    if (seen[i]) ++counts.visible;
    if (!seen[i]) continue;
    const Float3& nf = normals[begin + i];
    const double nlen = std::sqrt(double(nf.x) * nf.x + double(nf.y) * nf.y + double(nf.z) * nf.z);
    const double cosine = nlen > 0 ? dot(Vec3{nf.x, nf.y, nf.z}, r.to_projector) / nlen : 1;
    float image_alpha = 1, mask = 1;
    if (r.status == MapStatus::kOutside && in.outside != LayerOutside::kClamp) {
      if (in.outside == LayerOutside::kTransparent) continue;
      c.rgb = layer.outside_rgb;
      image_alpha = in.outside_color[3];
    } else {
      const Rgba s = sample_bilinear(layer.view, r.uv, layer.wrap_u, layer.wrap_v);
      image_alpha = s[3];
      if (s[3] > 0) c.rgb = {s[0] / s[3], s[1] / s[3], s[2] / s[3]};
      if (in.mask.data) {
        const Rgba k = sample_bilinear(in.mask, r.uv, layer.wrap_u, layer.wrap_v);
        mask = in.mask_has_alpha ? k[3] : k[0];
      }
    }
    c.a = static_cast<float>(in.opacity) * image_alpha * mask * fade(layer, cosine);
    if (c.a > 0) ++counts.blended;
    counts.alpha_sum += c.a;
  }
}

}  // namespace

Expected<LayersBakeResult> bake_vertex_layers(const MeshData& mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersBakeOptions& options) {
  if (layers.empty()) return make_error(ErrorCode::kInvalidArgument, "no layers to bake");
  const std::size_t n = mesh.positions.size();
  if (options.base == LayerBase::kMesh && mesh.vertex_colors.size() != n) {
    return make_error(ErrorCode::kInvalidArgument, "base \"mesh\": the mesh has no vertex colours");
  }
  LayersBakeResult result;
  auto start = Clock::now();
  const bool needs_scene = std::any_of(layers.begin(), layers.end(), [](const LayerInput& l) {
    return l.visibility == LayerVisibility::kFirst;
  });
  std::optional<EmbreeScene> scene;
  double offset = 0;
  if (needs_scene) {
    Expected<EmbreeScene> built = EmbreeScene::build(mesh, BuildQuality::kLow);
    if (!built) return built.error();
    scene.emplace(std::move(built).value());
    offset = visibility_offset(*scene);
  }
  const std::vector<Float3> normals = smooth_vertex_normals(mesh);
  result.seconds_scene = seconds_since(start);

  // The base: straight linear colour and coverage.
  start = Clock::now();
  std::vector<Rgba> colour(n, Rgba{0, 0, 0, 0});
  if (options.base == LayerBase::kColor) {
    std::fill(colour.begin(), colour.end(), srgb_to_linear(options.base_color));
  } else if (options.base == LayerBase::kMesh) {
    for (std::size_t v = 0; v < n; ++v) {
      const auto& c = mesh.vertex_colors[v];
      colour[v] = srgb_to_linear(Rgba{c[0], c[1], c[2], c[3]});
    }
  }

  std::vector<Contribution> contribution(n);
  for (const LayerInput& in : layers) {
    if (in.texture.width < 1 || in.texture.height < 1 || !in.texture.data) {
      return make_error(ErrorCode::kInvalidArgument, in.name + ": the layer's image is empty");
    }
    Prepared layer;
    layer.input = &in;
    layer.texture = premultiplied_linear(in.texture);
    layer.view = {in.texture.width, in.texture.height, layer.texture.data(), ColorSpace::kLinear};
    layer.camera = std::get_if<CameraProjector>(&in.projector);
    if (const Proxy* proxy = std::get_if<Proxy>(&in.projector)) {
      layer.wrap_u = wrap_u(*proxy);
      layer.wrap_v = wrap_v(*proxy);
    }
    if (in.angle_fade) {
      layer.cos_a0 = std::cos((*in.angle_fade)[0] * std::numbers::pi / 180);
      layer.cos_a1 = std::cos((*in.angle_fade)[1] * std::numbers::pi / 180);
    }
    const Rgba oc = srgb_to_linear(in.outside_color);
    layer.outside_rgb = {oc[0], oc[1], oc[2]};

    std::vector<LayerCounts> block_counts(block_count(n, kGrain));
    parallel_for_blocks(n, kGrain, [&](std::size_t block, std::size_t begin, std::size_t end) {
      LayerCounts& counts = block_counts[block];
      const EmbreeScene* s = scene ? &*scene : nullptr;
      if (layer.camera) {
        const CameraProjector& cam = *layer.camera;
        layer_block(
            layer, [&](Vec3 p) { return cam.inverse_map(p); }, mesh, normals, s, offset, begin, end,
            contribution.data(), counts);
      } else {
        std::visit(
            [&](const auto& proxy) {
              layer_block(
                  layer, [&](Vec3 p) { return proxy.inverse_map(p); }, mesh, normals, s, offset,
                  begin, end, contribution.data(), counts);
            },
            std::get<Proxy>(in.projector));
      }
    });
    LayerStats stats;
    stats.name = in.name;
    double alpha_sum = 0;
    for (const LayerCounts& c : block_counts) {
      stats.in_domain += c.in_domain;
      stats.visible += c.visible;
      stats.blended += c.blended;
      alpha_sum += c.alpha_sum;
    }
    stats.mean_alpha = n ? alpha_sum / static_cast<double>(n) : 0;
    result.layers.push_back(stats);

    // Composite (straight colour B, coverage alpha), in linear light.
    parallel_for_chunks(n, kGrain, [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) {
        const Contribution& c = contribution[v];
        if (!(c.a > 0)) continue;
        Rgba& b = colour[v];
        const float a = c.a, alpha = b[3];
        const float out_alpha = 1 - (1 - alpha) * (1 - a);
        for (int k = 0; k < 3; ++k) {
          switch (in.mode) {
            case LayerMode::kOver:
              b[k] = (a * c.rgb[k] + (1 - a) * alpha * b[k]) / out_alpha;
              break;
            case LayerMode::kMultiply:
              b[k] = b[k] * (1 - a + a * c.rgb[k]);
              break;
            case LayerMode::kAdd:
              b[k] = b[k] + a * c.rgb[k];
              break;
            case LayerMode::kReplace:
              b[k] = c.rgb[k];
              break;
          }
        }
        b[3] = out_alpha;
      }
    });
  }
  result.seconds_layers = seconds_since(start);

  // Uncovered vertices: the fill over their RGB (alpha stays 0), or a constant.
  start = Clock::now();
  std::vector<uint8_t> unknown(n, 0);
  for (std::size_t v = 0; v < n; ++v) unknown[v] = colour[v][3] > 0 ? 0 : 1;
  result.uncovered = static_cast<std::size_t>(std::count(unknown.begin(), unknown.end(), 1));
  std::vector<uint32_t> constant;
  if (options.occluded == OccludedMode::kColor) {
    for (std::size_t v = 0; v < n; ++v) {
      if (unknown[v]) constant.push_back(static_cast<uint32_t>(v));
    }
  } else if (result.uncovered > 0 && result.uncovered < n) {
    std::vector<Rgba> rgb(n);
    for (std::size_t v = 0; v < n; ++v) rgb[v] = {colour[v][0], colour[v][1], colour[v][2], 1};
    Expected<FillResult> fill = fill_harmonic(mesh, rgb, unknown, [&](uint32_t v) {
      constant.push_back(v);  // a component no layer covers
      return Rgba{0, 0, 0, 1};
    });
    if (!fill) return fill.error();
    result.filled = fill->filled;
    for (std::size_t v = 0; v < n; ++v) {
      if (unknown[v]) colour[v] = {rgb[v][0], rgb[v][1], rgb[v][2], 0};
    }
  } else if (result.uncovered == n) {
    for (std::size_t v = 0; v < n; ++v) constant.push_back(static_cast<uint32_t>(v));
  }
  for (Rgba& c : colour) c = linear_to_srgb(c);
  for (uint32_t v : constant) {
    const Rgba& k =
        options.occluded == OccludedMode::kColor ? options.occluded_color : Rgba{0, 0, 0, 0};
    colour[v] = {k[0], k[1], k[2], 0};
  }
  result.colors = std::move(colour);
  result.seconds_fill = seconds_since(start);
  return result;
}

}  // namespace texbake
