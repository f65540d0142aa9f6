#include "bake/layers/layers_bake.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/bake_atlas.h"
#include "bake/photo/segments.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "bake/vertex/occlusion_fill.h"
#include "mapping/sample.h"
#include "mapping/tiled_image.h"
#include "mesh_io/vertex_normals.h"

namespace texbake {

namespace {

constexpr std::size_t kGrain = 4096;  // vertices per parallel block

// A layer's texture as premultiplied linear RGBA (bilinear interpolation of
// premultiplied values keeps a transparent border from darkening the
// colour next to it).
// Precondition: image.data (in memory); a tiled texture is transformed as
// its tiles are loaded instead (transform_texel, the same bits).
std::vector<float> premultiplied_linear(const ImageView& image) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  std::vector<float> out(image.data, image.data + 4 * n);
  const bool srgb = image.color_space != ColorSpace::kLinear;
  parallel_for_chunks(n, 1 << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) transform_texel(&out[4 * i], srgb, true);
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
  double seconds = 0;  // thread time in the layer (the atlas target)
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

// Contributions of one layer for the points [begin, end): positions and
// normals (any length; a zero normal gives the angle fade cos 1).
template <class Map>
void layer_block(const Prepared& layer, const Map& map, const Vec3* points, const Vec3* normals,
                 const EmbreeScene* scene, double offset, std::size_t begin, std::size_t end,
                 Contribution* out, LayerCounts& counts) {
  const LayerInput& in = *layer.input;
  const std::size_t m = end - begin;
  std::vector<MapResult> maps(m);
  std::vector<uint8_t> seen(m, 1);
  for (std::size_t i = 0; i < m; ++i) {
    const Vec3& q = points[begin + i];
    maps[i] = map(q);
    if (maps[i].status == MapStatus::kUndefined) seen[i] = 0;
    if (layer.camera) {
      // A camera sees only surfaces facing it; behind it nothing is mapped.
      if (!(dot(normals[begin + i], maps[i].to_projector) > 0)) seen[i] = 0;
      if (maps[i].status == MapStatus::kOutside &&
          layer.camera->project(q).outside != CameraOutside::kOffPhoto) {
        seen[i] = 0;
      }
    }
  }
  if (scene && in.visibility == LayerVisibility::kFirst) {
    if (layer.camera) {
      std::vector<Vec3> ps;
      std::vector<std::size_t> slot;
      for (std::size_t i = 0; i < m; ++i) {
        if (seen[i]) ps.push_back(points[begin + i]), slot.push_back(i);
      }
      SegmentScratch scratch;
      std::vector<uint8_t> occluded(ps.size(), 0);
      occluded_segments(*scene, offset, ps, layer.camera->centre(), scratch, occluded.data());
      for (std::size_t k = 0; k < ps.size(); ++k) {
        if (occluded[k]) seen[slot[k]] = 0;
      }
    } else {
      VisibilityBatch batch;
      std::vector<std::size_t> slot;
      for (std::size_t i = 0; i < m; ++i) {
        if (!seen[i]) continue;
        batch.add(points[begin + i], maps[i].to_projector);
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
    const Vec3& nf = normals[begin + i];
    const double nlen = std::sqrt(nf.x * nf.x + nf.y * nf.y + nf.z * nf.z);
    const double cosine = nlen > 0 ? dot(nf, r.to_projector) / nlen : 1;
    float image_alpha = 1, mask = 1;
    if (r.status == MapStatus::kOutside && in.outside != LayerOutside::kClamp) {
      if (in.outside == LayerOutside::kTransparent) continue;
      c.rgb = layer.outside_rgb;
      image_alpha = in.outside_color[3];
    } else {
      const Rgba s = sample_bilinear(layer.view, r.uv, layer.wrap_u, layer.wrap_v);
      image_alpha = s[3];
      if (s[3] > 0) c.rgb = {s[0] / s[3], s[1] / s[3], s[2] / s[3]};
      if (in.mask.has_texels()) {
        const Rgba k = sample_bilinear(in.mask, r.uv, layer.wrap_u, layer.wrap_v);
        mask = in.mask_has_alpha ? k[3] : k[0];
      }
    }
    c.a = static_cast<float>(in.opacity) * image_alpha * mask * fade(layer, cosine);
    if (c.a > 0) ++counts.blended;
    counts.alpha_sum += c.a;
  }
}

// A "cameras" layer's contributions for the points [begin, end): the
// photo blend of point ids[i] (atlas samples) or i (vertices).
void photo_block(const Prepared& layer, const uint32_t* ids, std::size_t begin, std::size_t end,
                 Contribution* out, LayerCounts& counts) {
  const LayerInput& in = *layer.input;
  const PhotoPoints& points = ids ? in.photos->samples : in.photos->vertices;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t id = ids ? ids[i] : i;
    Contribution& c = out[i];
    c = {};
    const uint8_t state = points.state[id];
    if (state != PhotoPoints::kNoView) ++counts.in_domain;
    if (state != PhotoPoints::kSeen) continue;
    ++counts.visible;
    c.rgb = points.rgb[id];
    c.a = static_cast<float>(in.opacity) * fade(layer, points.cosine[id]);
    if (c.a > 0) ++counts.blended;
    counts.alpha_sum += c.a;
  }
}

// layer_block through the layer's projector (a camera or any analytic
// proxy), or photo_block for a "cameras" layer (sample_ids: the atlas
// samples' indices in its PhotoLayerPoints::samples; null for vertices).
void contributions(const Prepared& layer, const Vec3* points, const Vec3* normals,
                   const EmbreeScene* scene, double offset, std::size_t begin, std::size_t end,
                   Contribution* out, LayerCounts& counts, const uint32_t* sample_ids = nullptr) {
  if (layer.input->photos) {
    photo_block(layer, sample_ids, begin, end, out, counts);
  } else if (layer.camera) {
    const CameraProjector& cam = *layer.camera;
    layer_block(
        layer, [&](Vec3 p) { return cam.inverse_map(p); }, points, normals, scene, offset, begin,
        end, out, counts);
  } else {
    std::visit(
        [&](const auto& proxy) {
          layer_block(
              layer, [&](Vec3 p) { return proxy.inverse_map(p); }, points, normals, scene, offset,
              begin, end, out, counts);
        },
        std::get<Proxy>(layer.input->projector));
  }
}

// One layer's image and rules, ready for layer_block.
Expected<Prepared> prepare(const LayerInput& in, std::size_t vertex_count,
                           std::size_t sample_count = 0) {
  Prepared layer;
  layer.input = &in;
  if (in.angle_fade) {
    layer.cos_a0 = std::cos((*in.angle_fade)[0] * std::numbers::pi / 180);
    layer.cos_a1 = std::cos((*in.angle_fade)[1] * std::numbers::pi / 180);
  }
  if (in.photos) {
    const PhotoLayerPoints& p = *in.photos;
    const auto complete = [](const PhotoPoints& pts, std::size_t n) {
      return pts.state.size() == n && pts.rgb.size() == n && pts.cosine.size() == n;
    };
    if (!complete(p.vertices, vertex_count) ||
        (sample_count > 0 && !complete(p.samples, sample_count))) {
      return make_error(ErrorCode::kInvalidArgument,
                        in.name + ": the cameras layer's photo blend does not match the points");
    }
    return layer;
  }
  if (in.texture.width < 1 || in.texture.height < 1 || !in.texture.has_texels()) {
    return make_error(ErrorCode::kInvalidArgument, in.name + ": the layer's image is empty");
  }
  if (in.texture.data) {
    layer.texture = premultiplied_linear(in.texture);
    layer.view = {in.texture.width, in.texture.height, layer.texture.data(), ColorSpace::kLinear};
  } else {  // read through the cache (--cache-mb): transformed as tiles load
    layer.view = in.texture;
    layer.view.decode_srgb = in.texture.color_space != ColorSpace::kLinear;
    layer.view.premultiply = true;
    layer.view.color_space = ColorSpace::kLinear;
  }
  layer.camera = std::get_if<CameraProjector>(&in.projector);
  if (const Proxy* proxy = std::get_if<Proxy>(&in.projector)) {
    layer.wrap_u = wrap_u(*proxy);
    layer.wrap_v = wrap_v(*proxy);
  }
  const Rgba oc = srgb_to_linear(in.outside_color);
  layer.outside_rgb = {oc[0], oc[1], oc[2]};
  return layer;
}

// Composites one contribution onto the straight colour and coverage b, in
// linear light (the header's rules).
inline void composite(LayerMode mode, const Contribution& c, Rgba& b) {
  if (!(c.a > 0)) return;
  const float a = c.a, alpha = b[3];
  const float out_alpha = 1 - (1 - alpha) * (1 - a);
  for (int k = 0; k < 3; ++k) {
    switch (mode) {
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

Vec3 vec(Float3 f) {
  return {f.x, f.y, f.z};
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
    return !l.photos && l.visibility == LayerVisibility::kFirst;
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

  std::vector<Vec3> points(n), point_normals(n);
  for (std::size_t v = 0; v < n; ++v) {
    points[v] = vec(mesh.positions[v]);
    point_normals[v] = vec(normals[v]);
  }
  std::vector<Contribution> contribution(n);
  for (const LayerInput& in : layers) {
    const auto layer_start = Clock::now();
    Expected<Prepared> prepared = prepare(in, n);
    if (!prepared) return prepared.error();
    const Prepared& layer = *prepared;
    std::vector<LayerCounts> block_counts(block_count(n, kGrain));
    parallel_for_blocks(n, kGrain, [&](std::size_t block, std::size_t begin, std::size_t end) {
      contributions(layer, points.data(), point_normals.data(), scene ? &*scene : nullptr, offset,
                    begin, end, contribution.data(), block_counts[block]);
    });
    LayerStats stats;
    stats.name = in.name;
    stats.photos = in.photos != nullptr;
    double alpha_sum = 0;
    for (const LayerCounts& c : block_counts) {
      stats.in_domain += c.in_domain;
      stats.visible += c.visible;
      stats.blended += c.blended;
      alpha_sum += c.alpha_sum;
    }
    stats.mean_alpha = n ? alpha_sum / static_cast<double>(n) : 0;

    // Composite (straight colour B, coverage alpha), in linear light.
    parallel_for_chunks(n, kGrain, [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) composite(in.mode, contribution[v], colour[v]);
    });
    stats.seconds = seconds_since(layer_start);
    result.layers.push_back(stats);
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

// ---- The atlas target -------------------------------------------------------

namespace {

// One thread's working memory for a band of atlas samples.
struct AtlasWorker {
  AtlasRaster band;
  AtlasBandScratch scratch;
  std::vector<Vec3> points, normals;
  std::vector<Rgba> colour;  // straight linear colour and coverage per sample
  std::vector<Contribution> contribution;
  std::vector<uint32_t> ids;  // a "cameras" layer: the samples' indices in its blend
};

// The band's sample indices in a "cameras" layer's blend (false: the blend
// does not cover one of the band's texels).
bool photo_sample_ids(const PhotoLayerPoints& photos, const AtlasRaster& r, std::size_t spt,
                      std::vector<uint32_t>& ids) {
  ids.resize(r.texels.size() * spt);
  for (std::size_t k = 0; k < r.texels.size(); ++k) {
    const uint32_t first = photos.texel_first[r.texels[k]];
    if (first == PhotoLayerPoints::kNoTexel || first + spt > photos.samples.size()) return false;
    for (std::size_t j = 0; j < spt; ++j) ids[k * spt + j] = static_cast<uint32_t>(first + j);
  }
  return true;
}

}  // namespace

Expected<LayersAtlasResult> bake_atlas_layers(const MeshData& uv_mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersAtlasOptions& options,
                                              Progress* progress) {
  if (layers.empty()) return make_error(ErrorCode::kInvalidArgument, "no layers to bake");
  const bool constant_padding =
      options.padding == kPaddingDefault || options.padding == kPaddingInfinite;
  if (!constant_padding && (options.padding < 0 || options.padding > kMaxAtlasSize)) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--padding " + std::to_string(options.padding) + " is not a texel count");
  }
  const LayersBakeOptions& lo = options.layers;
  const bool base_texture = lo.base == LayerBase::kMesh && options.base_texture.data;
  const bool base_vertex = lo.base == LayerBase::kMesh && !base_texture;
  if (base_vertex && uv_mesh.vertex_colors.size() != uv_mesh.positions.size()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "base \"mesh\": the mesh has neither a texture nor vertex colours");
  }
  if (base_texture && (options.base_texture.width < 1 || options.base_texture.height < 1)) {
    return make_error(ErrorCode::kInvalidArgument, "base \"mesh\": the mesh's texture is empty");
  }
  Expected<AtlasBands> bands_or =
      AtlasBands::prepare(uv_mesh, AtlasRasterOptions{options.size, options.samples, false});
  if (!bands_or) return bands_or.error();
  const AtlasBands& bands = *bands_or;
  LayersAtlasResult result;

  // Layers ready (all at once: every band goes through every layer).
  std::vector<Prepared> prepared;
  prepared.reserve(layers.size());
  const std::size_t atlas_texels = static_cast<std::size_t>(options.size) * options.size;
  for (const LayerInput& in : layers) {
    Expected<Prepared> p = prepare(in, uv_mesh.positions.size());
    if (!p) return p.error();
    if (in.photos && (in.photos->texel_first.size() != atlas_texels ||
                      in.photos->samples.size() % static_cast<std::size_t>(options.samples))) {
      return make_error(ErrorCode::kInvalidArgument,
                        in.name + ": the cameras layer's photo blend is not this atlas's");
    }
    prepared.push_back(std::move(p).value());
  }

  // The fill's colours: the vertex target on the same mesh (linear RGB).
  auto start = Clock::now();
  const bool fill = lo.occluded != OccludedMode::kColor;
  std::vector<Rgba> fill_colors;
  std::vector<double> fill_seconds(layers.size(), 0.0);
  if (fill) {
    LayersBakeOptions vo = lo;
    if (base_texture) vo.base = LayerBase::kNone;
    Expected<LayersBakeResult> vertex = bake_vertex_layers(uv_mesh, layers, vo);
    if (!vertex) return vertex.error();
    for (std::size_t l = 0; l < layers.size(); ++l) fill_seconds[l] = vertex->layers[l].seconds;
    fill_colors = std::move(vertex->colors);
    for (Rgba& c : fill_colors) c = srgb_to_linear(c);
  }
  result.seconds_fill = seconds_since(start);

  start = Clock::now();
  const bool needs_scene = std::any_of(layers.begin(), layers.end(), [](const LayerInput& l) {
    return !l.photos && l.visibility == LayerVisibility::kFirst;
  });
  std::optional<EmbreeScene> scene;
  double offset = 0;
  if (needs_scene) {
    Expected<EmbreeScene> built = EmbreeScene::build(uv_mesh, BuildQuality::kLow);
    if (!built) return built.error();
    scene.emplace(std::move(built).value());
    offset = visibility_offset(*scene);
  }
  const std::vector<Float3> normals = smooth_vertex_normals(uv_mesh);
  std::vector<float> base_premultiplied;
  ImageView base_view;
  if (base_texture) {
    base_premultiplied = premultiplied_linear(options.base_texture);
    base_view = {options.base_texture.width, options.base_texture.height, base_premultiplied.data(),
                 ColorSpace::kLinear};
  }
  result.seconds_scene = seconds_since(start);

  start = Clock::now();
  const int n = options.size;
  const std::size_t spt = static_cast<std::size_t>(options.samples);
  result.atlas.width = result.atlas.height = n;
  result.atlas.pixels.assign(static_cast<std::size_t>(n) * n * 4, 0.f);
  result.atlas.color_space = ColorSpace::kSrgb;
  result.atlas.has_alpha = true;
  result.baked.assign(static_cast<std::size_t>(n) * n, 0);
  const Rgba base_linear = srgb_to_linear(lo.base_color);
  const std::size_t band_count = bands.band_count();
  // Per band and layer, so that the sums are taken in band order.
  std::vector<LayerCounts> counts(band_count * layers.size());
  std::vector<std::size_t> band_texels(band_count, 0), band_samples(band_count, 0),
      band_border(band_count, 0), band_uncovered(band_count, 0);
  std::vector<uint8_t> band_opaque(band_count, 1), band_mismatch(band_count, 0);
  if (progress) progress->start("sample", static_cast<std::size_t>(n));
  parallel_for_chunks(band_count, 1, [&](std::size_t band_begin, std::size_t band_end) {
    AtlasWorker w;
    for (std::size_t band = band_begin; band < band_end; ++band) {
      if (progress && progress->cancelled()) return;
      bands.rasterize(band, w.band, w.scratch);
      const AtlasRaster& r = w.band;
      const std::size_t m = r.sample_count();
      w.points.resize(m);
      w.normals.resize(m);
      w.colour.assign(m, Rgba{0, 0, 0, 0});
      w.contribution.resize(m);
      for (std::size_t s = 0; s < m; ++s) {
        const auto& tri = uv_mesh.triangles[r.sample_triangle[s]];
        const double b1 = r.sample_b1[s], b2 = r.sample_b2[s], b0 = 1 - b1 - b2;
        const Vec3 a = vec(uv_mesh.positions[tri[0]]), b = vec(uv_mesh.positions[tri[1]]),
                   c = vec(uv_mesh.positions[tri[2]]);
        w.points[s] = a * b0 + b * b1 + c * b2;
        const Vec3 nn =
            vec(normals[tri[0]]) * b0 + vec(normals[tri[1]]) * b1 + vec(normals[tri[2]]) * b2;
        const Vec3 face = cross(b - a, c - a);
        const double len = length(nn), face_len = length(face);
        // Opposite vertex normals can cancel: the face's direction then.
        w.normals[s] = len > 1e-12 ? nn / len : (face_len > 0 ? face / face_len : Vec3{0, 0, 0});
        if (lo.base == LayerBase::kColor) {
          w.colour[s] = base_linear;
        } else if (base_vertex) {
          Rgba v{0, 0, 0, 0};
          for (int k = 0; k < 3; ++k) {
            const auto& vc = uv_mesh.vertex_colors[tri[k]];
            const Rgba lin = srgb_to_linear(Rgba{vc[0], vc[1], vc[2], vc[3]});
            const double bk = k == 0 ? b0 : k == 1 ? b1 : b2;
            for (int ch = 0; ch < 4; ++ch) v[ch] += static_cast<float>(bk * lin[ch]);
          }
          w.colour[s] = v;
        }
      }
      if (base_texture) {
        // The texel centre's lookup, shared by the texel's samples.
        for (std::size_t k = 0; k < r.texels.size(); ++k) {
          const std::size_t t = r.texels[k];
          const double x = static_cast<double>(t % n), y = static_cast<double>(t / n);
          const UV uv{(x + 0.5) / n, 1 - (y + 0.5) / n};
          Rgba s = sample_bilinear(base_view, uv, WrapMode::kClamp, WrapMode::kClamp);
          if (s[3] > 0) {
            for (int ch = 0; ch < 3; ++ch) s[ch] /= s[3];
          } else {
            s = {0, 0, 0, 0};
          }
          for (std::size_t j = k * spt; j < (k + 1) * spt; ++j) w.colour[j] = s;
        }
      }
      for (std::size_t l = 0; l < prepared.size(); ++l) {
        const auto layer_start = Clock::now();
        LayerCounts& c = counts[band * layers.size() + l];
        if (layers[l].photos && !photo_sample_ids(*layers[l].photos, r, spt, w.ids)) {
          band_mismatch[band] = 1;
          return;
        }
        contributions(prepared[l], w.points.data(), w.normals.data(), scene ? &*scene : nullptr,
                      offset, 0, m, w.contribution.data(), c,
                      layers[l].photos ? w.ids.data() : nullptr);
        const LayerMode mode = layers[l].mode;
        for (std::size_t s = 0; s < m; ++s) composite(mode, w.contribution[s], w.colour[s]);
        c.seconds += seconds_since(layer_start);
      }
      // Texels: the mean in premultiplied linear light, straight sRGB out.
      std::size_t uncovered = 0;
      bool opaque = true;
      for (std::size_t k = 0; k < r.texels.size(); ++k) {
        std::array<double, 3> premultiplied{0, 0, 0}, filled{0, 0, 0};
        double alpha = 0;
        std::size_t empty = 0;
        for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
          const Rgba& c = w.colour[s];
          if (c[3] > 0) {
            for (int ch = 0; ch < 3; ++ch) premultiplied[ch] += double(c[3]) * c[ch];
            alpha += c[3];
          } else {
            ++empty;
            if (fill) {
              const auto& tri = uv_mesh.triangles[r.sample_triangle[s]];
              const double b1 = r.sample_b1[s], b2 = r.sample_b2[s], b0 = 1 - b1 - b2;
              for (int ch = 0; ch < 3; ++ch) {
                filled[ch] += b0 * fill_colors[tri[0]][ch] + b1 * fill_colors[tri[1]][ch] +
                              b2 * fill_colors[tri[2]][ch];
              }
            }
          }
        }
        uncovered += empty;
        Rgba out{0, 0, 0, 0};
        if (alpha > 0) {
          for (int ch = 0; ch < 3; ++ch) out[ch] = static_cast<float>(premultiplied[ch] / alpha);
          out[3] = static_cast<float>(std::min(1.0, alpha / static_cast<double>(spt)));
          out = linear_to_srgb(out);
        } else if (fill) {
          for (int ch = 0; ch < 3; ++ch) {
            out[ch] = static_cast<float>(filled[ch] / static_cast<double>(empty));
          }
          out = linear_to_srgb(out);
        } else {
          out = {lo.occluded_color[0], lo.occluded_color[1], lo.occluded_color[2], 0};
        }
        if (out[3] < 1) opaque = false;
        const std::size_t t = r.texels[k];
        std::copy(out.begin(), out.end(), result.atlas.pixels.begin() + 4 * t);
        result.baked[t] = 1;
      }
      band_texels[band] = r.texels.size();
      band_samples[band] = m;
      band_border[band] = r.border_samples;
      band_uncovered[band] = uncovered;
      band_opaque[band] = opaque ? 1 : 0;
      if (progress) progress->advance(bands.band_rows(band));
    }
  });
  if (progress && progress->cancelled()) return cancelled_error();
  if (std::any_of(band_mismatch.begin(), band_mismatch.end(), [](uint8_t b) { return b; })) {
    return make_error(ErrorCode::kInvalidArgument,
                      "a cameras layer's photo blend does not cover this atlas's texels");
  }
  if (progress) progress->finish();
  scene.reset();
  for (std::size_t band = 0; band < band_count; ++band) {
    result.texels += band_texels[band];
    result.samples += band_samples[band];
    result.border_samples += band_border[band];
    result.uncovered += band_uncovered[band];
    if (!band_opaque[band]) result.opaque = false;
  }
  result.seconds_layers = seconds_since(start);
  // Each layer's share of the stage's wall time, by the threads' time in it.
  std::vector<double> thread_seconds(layers.size(), 0.0);
  for (std::size_t l = 0; l < layers.size(); ++l) {
    for (std::size_t band = 0; band < band_count; ++band) {
      thread_seconds[l] += counts[band * layers.size() + l].seconds;
    }
  }
  double thread_total = 0;
  for (double t : thread_seconds) thread_total += t;
  for (std::size_t l = 0; l < layers.size(); ++l) {
    LayerStats stats;
    stats.name = layers[l].name;
    stats.photos = layers[l].photos != nullptr;
    double alpha_sum = 0;
    for (std::size_t band = 0; band < band_count; ++band) {
      const LayerCounts& c = counts[band * layers.size() + l];
      stats.in_domain += c.in_domain;
      stats.visible += c.visible;
      stats.blended += c.blended;
      alpha_sum += c.alpha_sum;
    }
    stats.mean_alpha = result.samples ? alpha_sum / static_cast<double>(result.samples) : 0;
    stats.seconds =
        fill_seconds[l] +
        (thread_total > 0 ? result.seconds_layers * thread_seconds[l] / thread_total : 0);
    result.layers.push_back(stats);
  }

  start = Clock::now();
  result.padded = pad_atlas(result.atlas.pixels, result.baked, n, options.padding);
  result.seconds_pad = seconds_since(start);
  return result;
}

}  // namespace texbake
