#include "bake/engine/layers_bake.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/atlas_samples.h"
#include "bake/engine/bake_atlas.h"
#include "bake/photo/segments.h"
#include "bake/shade/footprint.h"
#include "bake/shade/shade.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "bake/vertex/vertex_filter.h"
#include "bake/vertex/vertex_resolve.h"
#include "bake/vertex/vertex_share.h"
#include "mapping/derivatives.h"
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

// What a layer decided for a point.
enum PointState : uint8_t {
  kSeen = 0,      // mapped and seen
  kHidden = 1,    // mapped, not seen (a blocked ray, a camera facing away)
  kUnmapped = 2,  // no mapping (or the area filter found none)
};

// What one layer gives one point: its straight colour (the stack's working
// space) and a; `coloured` when rgb and a hold a lookup (under
// ResultAlpha::kImage a hidden point's too, for --occluded project).
struct Contribution {
  std::array<float, 3> rgb{0, 0, 0};
  float a = 0;
  uint8_t state = kUnmapped;
  bool coloured = false;
};

struct LayerCounts {
  std::size_t in_domain = 0, visible = 0, blended = 0;
  std::size_t hidden = 0, unmapped = 0;  // points (LayerStats)
  FilterCounts filter;                   // the vertex filter's lookups
  double alpha_sum = 0;
  double seconds = 0;  // thread time in the layer (the atlas target)
};

// True when the layer's lookups are in linear light: a linear layer, or a
// stored-encoding layer whose image is linear (stored as linear values, as
// the single-proxy bake samples an EXR).
bool works_linear(const LayerInput& l) {
  return l.linear || (!l.photos && l.texture.color_space == ColorSpace::kLinear);
}

// The working space of a stack: linear light unless every layer's lookups
// are in the sRGB encoding (LayerInput::linear).
bool stack_linear(const std::vector<LayerInput>& layers) {
  return std::any_of(layers.begin(), layers.end(), works_linear);
}

// An sRGB-encoded colour in the stack's working space, and back.
Rgba to_work(const Rgba& c, bool linear) {
  return linear ? srgb_to_linear(c) : c;
}
Rgba from_work(const Rgba& c, bool linear) {
  return linear ? linear_to_srgb(c) : c;
}

// The prepared layer: working image, its lookup (the shading rule's:
// wraps, MIP pyramid) and constants.
struct Prepared {
  const LayerInput* input = nullptr;
  std::vector<float> texture;       // premultiplied linear RGBA (a linear layer in memory)
  ImageView view;                   // the working image
  ShadeRule rule;                   // image = view; wraps, has_outside, mip
  std::unique_ptr<MipPyramid> mip;  // kEwa
  bool linearise = false;           // an sRGB-encoded stored-encoding layer in a linear stack
  const CameraProjector* camera = nullptr;    // null: an analytic proxy
  double cos_a0 = 1, cos_a1 = 0;              // the angle fade's limits as cosines
  std::array<float, 3> outside_rgb{0, 0, 0};  // the stack's working space
  Rgba outside_sample{0, 0, 0, 0};            // the outside colour as a lookup (area filter)
  WorkingImage straight;                      // LayerInput::straight: the linear copy
  bool image_alpha = false;                   // ResultAlpha::kImage
  bool project_hidden = false;                // kImage under OccludedMode::kProject
};

// Where the points come from, for the area and EWA filters: the vertex
// target's vertices (point i is vertex(i)), or the atlas's supersamples.
struct PointFrame {
  const MeshData* mesh = nullptr;
  bool vertices = false;                 // the vertex target
  std::size_t first_vertex = 0;          // point i is vertex first_vertex + i ...
  const uint32_t* vertex_ids = nullptr;  // ... or vertex_ids[i] (a visit order)
  const Adjacency* adjacency = nullptr;  // the vertex target (area, EWA)
  const uint32_t* triangles = nullptr;   // the atlas target: each point's triangle
  double cell = 0;                       // the atlas target under EWA (ewa_cell)

  std::size_t vertex(std::size_t point) const {
    return vertex_ids ? vertex_ids[point] : first_vertex + point;
  }
};

// The straight colour (the stack's working space) of a lookup in the
// layer's working space.
std::array<float, 3> straight_rgb(const Prepared& layer, const Rgba& s) {
  if (!layer.input->linear || layer.input->straight) {
    if (!layer.linearise) return {s[0], s[1], s[2]};
    const Rgba l = srgb_to_linear(s);
    return {l[0], l[1], l[2]};
  }
  if (!(s[3] > 0)) return {0, 0, 0};
  return {s[0] / s[3], s[1] / s[3], s[2] / s[3]};
}

// The layer's filtered lookup for point `point` at q (mapped to r, not
// kUndefined, and not outside unless the layer clamps or, under
// ResultAlpha::kImage, takes a colour): nullopt when the area filter found
// no mapped sample. The vertex target is the shared vertex filter
// (bake/vertex/vertex_filter.h; the rule's outside constant is the layer's
// outside lookup, so the area filter's outside samples follow the layer's
// `outside`); an atlas supersample is one lookup, under EWA with the
// footprint of its cell.
template <class Map, class Jacobian>
std::optional<Rgba> filtered(const Prepared& layer, const Map& map, const Jacobian& jacobian,
                             const PointFrame& frame, std::size_t point, const Vec3& q,
                             const MapResult& r, VertexShare& share, FilterCounts& counts) {
  const LayerInput& in = *layer.input;
  if (frame.vertices) {
    return filter_vertex(layer.rule, in.filter, in.samples, map, jacobian, *frame.mesh,
                         frame.adjacency, static_cast<uint32_t>(frame.vertex(point)), r, share,
                         counts);
  }
  if (in.filter == VertexFilter::kEwa && frame.triangles && frame.cell > 0) {
    Vec3 t1, t2;
    cell_tangents(*frame.mesh, frame.triangles[point], frame.cell, t1, t2);
    return layer.rule.lookup(r.uv, uv_footprint(jacobian(q), t1, t2));
  }
  return layer.rule.lookup(r.uv, {});
}

float fade(const Prepared& layer, double cosine) {
  if (!layer.input->angle_fade) return 1;
  const auto [a0, a1] = *layer.input->angle_fade;
  if (cosine >= layer.cos_a0) return 1;
  if (cosine <= layer.cos_a1) return 0;
  const double theta = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / std::numbers::pi;
  return static_cast<float>(std::clamp((a1 - theta) / (a1 - a0), 0.0, 1.0));
}

// Clears seen[i] for the points whose way to the layer's projector is
// blocked: the segment to a camera's centre, or the ray towards a proxy
// (points: the block's m = seen.size() points; maps: their mappings).
void trace_seen(const Prepared& layer, const Vec3* points, const std::vector<MapResult>& maps,
                const EmbreeScene& scene, double offset, std::vector<uint8_t>& seen) {
  const std::size_t m = seen.size();
  if (layer.camera) {
    std::vector<Vec3> ps;
    std::vector<std::size_t> slot;
    for (std::size_t i = 0; i < m; ++i) {
      if (seen[i]) ps.push_back(points[i]), slot.push_back(i);
    }
    SegmentScratch scratch;
    std::vector<uint8_t> occluded(ps.size(), 0);
    occluded_segments(scene, offset, ps, layer.camera->centre(), scratch, occluded.data());
    for (std::size_t k = 0; k < ps.size(); ++k) {
      if (occluded[k]) seen[slot[k]] = 0;
    }
  } else {
    VisibilityBatch batch;
    std::vector<std::size_t> slot;
    for (std::size_t i = 0; i < m; ++i) {
      if (!seen[i]) continue;
      batch.add(points[i], maps[i].to_projector);
      slot.push_back(i);
    }
    std::vector<uint8_t> visible(slot.size(), 0);
    if (!slot.empty()) batch.trace(scene, offset, visible.data());
    for (std::size_t k = 0; k < slot.size(); ++k) {
      if (!visible[k]) seen[slot[k]] = 0;
    }
  }
}

// Contributions of one layer for the points [begin, end): positions and
// normals (any length; a zero normal gives the angle fade cos 1).
template <class Map, class Jacobian>
void layer_block(const Prepared& layer, const Map& map, const Jacobian& jacobian,
                 const PointFrame& frame, const Vec3* points, const Vec3* normals,
                 const EmbreeScene* scene, double offset, std::size_t begin, std::size_t end,
                 Contribution* out, LayerCounts& counts) {
  const LayerInput& in = *layer.input;
  VertexShare share;
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
    trace_seen(layer, points + begin, maps, *scene, offset, seen);
  }
  for (std::size_t i = 0; i < m; ++i) {
    Contribution& c = out[begin + i];
    c = {};
    const MapResult& r = maps[i];
    if (r.status == MapStatus::kOk) ++counts.in_domain;
    if (r.status == MapStatus::kUndefined) {
      ++counts.unmapped;
      continue;
    }
    c.state = seen[i] ? kSeen : kHidden;
    if (seen[i]) ++counts.visible;
    if (layer.image_alpha) {
      // The single projection: the filtered lookup is the RGBA (outside
      // points follow the rule: the constant or the clamped lookup).
      if (seen[i] || layer.project_hidden) {
        const std::optional<Rgba> s = filtered(layer, map, jacobian, frame, begin + i,
                                               points[begin + i], r, share, counts.filter);
        if (s) {
          c.rgb = {(*s)[0], (*s)[1], (*s)[2]};
          c.a = (*s)[3];
          c.coloured = true;
          if (c.a > 0) ++counts.blended;
          counts.alpha_sum += c.a;
        } else {
          c.state = kUnmapped;
        }
      }
      if (c.state == kHidden) ++counts.hidden;
      if (c.state == kUnmapped) ++counts.unmapped;
      continue;
    }
    if (!seen[i]) {
      ++counts.hidden;
      continue;
    }
    const Vec3& nf = normals[begin + i];
    const double nlen = std::sqrt(nf.x * nf.x + nf.y * nf.y + nf.z * nf.z);
    const double cosine = nlen > 0 ? dot(nf, r.to_projector) / nlen : 1;
    float image_alpha = 1, mask = 1;
    if (r.status == MapStatus::kOutside && layer.rule.has_outside &&
        in.outside != LayerOutside::kClamp) {
      if (in.outside == LayerOutside::kTransparent) continue;
      c.rgb = layer.outside_rgb;
      image_alpha = in.outside_color[3];
    } else {
      const std::optional<Rgba> s = filtered(layer, map, jacobian, frame, begin + i,
                                             points[begin + i], r, share, counts.filter);
      if (!s) {  // the area filter: no sample has a mapping
        c.state = kUnmapped;
        ++counts.unmapped;
        continue;
      }
      image_alpha = (*s)[3];
      c.rgb = straight_rgb(layer, *s);
      if (in.mask.has_texels()) {
        const Rgba k = sample_bilinear(in.mask, r.uv, layer.rule.wrap_u, layer.rule.wrap_v);
        mask = in.mask_has_alpha ? k[3] : k[0];
      }
    }
    c.a = static_cast<float>(in.opacity) * image_alpha * mask * fade(layer, cosine);
    c.coloured = true;
    if (c.a > 0) ++counts.blended;
    counts.alpha_sum += c.a;
  }
}

// A "cameras" layer's contributions for the points [begin, end): the
// photo blend of point ids[i] (atlas samples) or of the frame's vertex i.
void photo_block(const Prepared& layer, const uint32_t* ids, const PointFrame& frame,
                 std::size_t begin, std::size_t end, Contribution* out, LayerCounts& counts) {
  const LayerInput& in = *layer.input;
  const PhotoPoints& points = ids ? in.photos->samples : in.photos->vertices;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t id = ids ? ids[i] : frame.vertex(i);
    Contribution& c = out[i];
    c = {};
    const uint8_t state = points.state[id];
    if (state != PhotoPoints::kNoView) ++counts.in_domain;
    if (state != PhotoPoints::kSeen) {
      c.state = state == PhotoPoints::kNoView ? kUnmapped : kHidden;
      ++(state == PhotoPoints::kNoView ? counts.unmapped : counts.hidden);
      continue;
    }
    ++counts.visible;
    c.state = kSeen;
    c.coloured = true;
    c.rgb = points.rgb[id];
    c.a = static_cast<float>(in.opacity) * fade(layer, points.cosine[id]);
    if (c.a > 0) ++counts.blended;
    counts.alpha_sum += c.a;
  }
}

// f(map, jacobian) with the layer's projector's inverse mapping and its
// Jacobian (a camera or any analytic proxy; not a "cameras" layer).
template <class F>
void with_projector(const Prepared& layer, F&& f) {
  if (layer.camera) {
    const CameraProjector& cam = *layer.camera;
    // No EWA through a camera (prepare refuses it): no Jacobian needed.
    f([&cam](Vec3 p) { return cam.inverse_map(p); }, [](Vec3) { return UvJacobian{}; });
    return;
  }
  std::visit(
      [&](const auto& proxy) {
        f([&proxy](Vec3 p) { return proxy.inverse_map(p); },
          [&proxy](Vec3 p) { return inverse_map_jacobian(proxy, p); });
      },
      std::get<Proxy>(layer.input->projector));
}

// layer_block through the layer's projector (a camera or any analytic
// proxy), or photo_block for a "cameras" layer (sample_ids: the atlas
// samples' indices in its PhotoLayerPoints::samples; null for vertices).
void contributions(const Prepared& layer, const PointFrame& frame, const Vec3* points,
                   const Vec3* normals, const EmbreeScene* scene, double offset, std::size_t begin,
                   std::size_t end, Contribution* out, LayerCounts& counts,
                   const uint32_t* sample_ids = nullptr) {
  if (layer.input->photos) {
    photo_block(layer, sample_ids, frame, begin, end, out, counts);
    return;
  }
  with_projector(layer, [&](const auto& map, const auto& jacobian) {
    layer_block(layer, map, jacobian, frame, points, normals, scene, offset, begin, end, out,
                counts);
  });
}

// One layer's image and rules, ready for layer_block, in a stack whose
// working space is linear light (`linear`) or the stored encoding. Held by
// pointer (its rule points at its own pyramid).
Expected<std::unique_ptr<Prepared>> prepare(const LayerInput& in, bool linear,
                                            std::size_t vertex_count,
                                            std::size_t sample_count = 0) {
  auto prepared = std::make_unique<Prepared>();
  Prepared& layer = *prepared;
  layer.input = &in;
  if (in.filter != VertexFilter::kBilinear && in.photos) {
    return make_error(ErrorCode::kInvalidArgument,
                      in.name +
                          ": a cameras layer takes the photo bake's bilinear lookup (filter "
                          "\"bilinear\")");
  }
  if (in.filter == VertexFilter::kEwa && std::holds_alternative<CameraProjector>(in.projector) &&
      !in.photos) {
    return make_error(ErrorCode::kInvalidArgument,
                      in.name + ": EWA needs an analytic proxy's Jacobian, a camera has none");
  }
  if (in.filter == VertexFilter::kArea && in.samples < 1) {
    return make_error(ErrorCode::kInvalidArgument,
                      in.name + ": the area filter needs samples >= 1");
  }
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
    return prepared;
  }
  if (in.texture.width < 1 || in.texture.height < 1 || !in.texture.has_texels()) {
    return make_error(ErrorCode::kInvalidArgument, in.name + ": the layer's image is empty");
  }
  if (!in.linear) {
    layer.view = in.texture;  // as stored, straight alpha
    layer.linearise = linear && !works_linear(in);
  } else if (in.straight) {  // linear light, straight alpha
    layer.straight = working_image(in.texture, true);
    layer.view = layer.straight.view;
  } else if (in.texture.data) {
    layer.texture = premultiplied_linear(in.texture);
    layer.view = {in.texture.width, in.texture.height, layer.texture.data(), ColorSpace::kLinear};
  } else {  // read through the cache (--cache-mb): transformed as tiles load
    layer.view = in.texture;
    layer.view.decode_srgb = in.texture.color_space != ColorSpace::kLinear;
    layer.view.premultiply = true;
    layer.view.color_space = ColorSpace::kLinear;
  }
  if (in.linear && !in.straight) {
    // The file's MIP levels average stored values, not premultiplied linear light.
    layer.view.mip_levels = nullptr;
    layer.view.mip_level_count = 0;
  }
  layer.camera = std::get_if<CameraProjector>(&in.projector);
  VertexBakeOptions shading;
  shading.plane_wrap = in.plane_wrap;
  layer.rule = layer.camera ? make_camera_shade_rule(layer.view, shading)
                            : make_shade_rule(layer.view, std::get<Proxy>(in.projector), shading);
  if (in.filter == VertexFilter::kEwa) {
    layer.mip = std::make_unique<MipPyramid>(layer.view, pyramid_rows);
    layer.rule.mip = layer.mip.get();
    layer.rule.max_anisotropy = in.max_anisotropy;
  }
  const Rgba oc = to_work(in.outside_color, linear);
  layer.outside_rgb = {oc[0], oc[1], oc[2]};
  if (in.outside == LayerOutside::kColor) {
    // As a lookup: the rule's working encoding, premultiplied for a linear layer.
    const Rgba c = layer.rule.working(in.outside_color);
    const bool premultiplied = in.linear && !in.straight;
    layer.outside_sample = premultiplied ? Rgba{c[0] * c[3], c[1] * c[3], c[2] * c[3], c[3]} : c;
  }
  // The area filter's outside samples (ShadeRule::project): the outside
  // lookup (transparent: 0) unless the layer clamps.
  layer.rule.outside_constant = in.outside != LayerOutside::kClamp;
  layer.rule.outside_color = layer.outside_sample;
  return prepared;
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

// A layer that traces visibility rays (a "cameras" layer's photo bake has
// its own scene).
bool needs_scene(const LayerInput& l) {
  return !l.photos && l.visibility == LayerVisibility::kFirst;
}

// A layer that reads the points' smooth normals: a camera's facing test,
// an angle fade ("cameras" layers carry their own cosine).
bool needs_normals(const LayerInput& l) {
  return !l.photos && (l.angle_fade || std::holds_alternative<CameraProjector>(l.projector));
}

// The layers' stats from per-block counts (block-major: counts[block *
// layers + l]), summed in block order: mean alpha over `points`; seconds,
// each layer's `own` seconds plus its share of the pass's wall time
// `pass_seconds` by the threads' time in it.
std::vector<LayerStats> layer_stats(const std::vector<LayerInput>& layers,
                                    const std::vector<LayerCounts>& counts, std::size_t points,
                                    const std::vector<double>& own, double pass_seconds) {
  const std::size_t layer_count = layers.size();
  const std::size_t blocks = layer_count ? counts.size() / layer_count : 0;
  std::vector<double> thread_seconds(layer_count, 0.0);
  double thread_total = 0;
  std::vector<LayerStats> out;
  for (std::size_t l = 0; l < layer_count; ++l) {
    LayerStats stats;
    stats.name = layers[l].name;
    stats.photos = layers[l].photos != nullptr;
    double alpha_sum = 0;
    for (std::size_t block = 0; block < blocks; ++block) {
      const LayerCounts& c = counts[block * layer_count + l];
      stats.in_domain += c.in_domain;
      stats.visible += c.visible;
      stats.blended += c.blended;
      stats.hidden += c.hidden;
      stats.unmapped += c.unmapped;
      stats.lookups += c.filter.samples;
      stats.outside += c.filter.outside;
      alpha_sum += c.alpha_sum;
      thread_seconds[l] += c.seconds;
    }
    thread_total += thread_seconds[l];
    stats.mean_alpha = points ? alpha_sum / static_cast<double>(points) : 0;
    out.push_back(std::move(stats));
  }
  for (std::size_t l = 0; l < layer_count; ++l) {
    out[l].seconds =
        own[l] + (thread_total > 0 ? pass_seconds * thread_seconds[l] / thread_total : 0);
  }
  return out;
}

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

// A texture read in tiles (--cache-mb): the single projection's vertex
// target (ResultAlpha::kImage; a stack's mean alphas are sums in block
// order, kept as they are) visits the vertices in the order of their place
// in the layer's image, so
// that neighbouring lookups share tiles and each tile of the file is read
// about once, not once per visit of a scattered vertex order (a subdivided
// mesh appends its new vertices level by level). Every vertex's colour is
// its own: the same result. Empty when no layer's image is tiled.
// The order: by the Morton code of the 256-texel block the vertex's mapping
// lands in (unmapped vertices last), ties by index.
std::vector<uint32_t> visit_order(const MeshData& mesh,
                                  const std::vector<std::unique_ptr<Prepared>>& layers) {
  const Prepared* tiled = nullptr;
  for (const auto& l : layers) {
    if (!l->input->photos && !l->view.data) {
      tiled = l.get();
      break;
    }
  }
  if (!tiled) return {};
  const ImageView& image = tiled->view;
  const std::size_t n = mesh.positions.size();
  std::vector<uint64_t> keys(n);
  with_projector(*tiled, [&](const auto& map, const auto&) {
    parallel_for_chunks(n, 16384, [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) {
        const Float3& f = mesh.positions[v];
        const MapResult m = map(Vec3{f.x, f.y, f.z});
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
    });
  });
  std::vector<uint32_t> order(n);
  for (std::size_t v = 0; v < n; ++v) order[v] = static_cast<uint32_t>(v);
  std::stable_sort(order.begin(), order.end(),
                   [&keys](uint32_t a, uint32_t b) { return keys[a] < keys[b]; });
  return order;
}

// The mean of an image's texels. In bands of rows (read_rows), so a tiled
// image (mapping/tiled_image.h) is summed without being held whole; the
// same sums in the same order either way.
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

// ResultAlpha::kImage takes one layer that is the projection alone.
Status check_single_projection(const std::vector<LayerInput>& layers,
                               const LayersBakeOptions& options) {
  const auto refuse = [](const std::string& why) -> Status {
    return make_error(ErrorCode::kInvalidArgument, "the single-projection bake " + why);
  };
  if (layers.size() != 1) return refuse("takes exactly one layer");
  const LayerInput& l = layers[0];
  if (l.photos) return refuse("takes a proxy or a camera, not a set of photos");
  if (l.linear && !l.straight) {
    return refuse("takes the stored encoding or straight linear light, not premultiplied alpha");
  }
  if (l.opacity != 1 || l.mask.has_texels() || l.angle_fade || l.mode != LayerMode::kOver) {
    return refuse("takes no opacity, mask, angle fade or blend mode");
  }
  if (l.outside == LayerOutside::kTransparent) {
    return refuse("takes outside \"clamp\" or a colour, not \"transparent\"");
  }
  if (options.base != LayerBase::kNone) return refuse("takes no base");
  return ok_status();
}

// The scene the layers' visibility rays go through: `shared` when given,
// else one built over the mesh when some layer traces rays; none otherwise.
struct StackScene {
  std::optional<EmbreeScene> own;
  const EmbreeScene* shared = nullptr;
  double offset = 0;
  // Not a stored pointer: the struct is moved, and `own` with it.
  const EmbreeScene* scene() const { return own ? &*own : shared; }
};
Expected<StackScene> stack_scene(const MeshData& mesh, const std::vector<LayerInput>& layers,
                                 const EmbreeScene* shared) {
  StackScene out;
  if (std::none_of(layers.begin(), layers.end(), needs_scene)) return out;
  if (shared) {
    out.shared = shared;
  } else {
    Expected<EmbreeScene> built = EmbreeScene::build(mesh, BuildQuality::kLow);
    if (!built) return built.error();
    out.own.emplace(std::move(built).value());
  }
  out.offset = visibility_offset(*out.scene());
  return out;
}

// Every layer prepared (prepare) in the stack's working space, and the
// seconds each took.
Expected<std::vector<std::unique_ptr<Prepared>>> prepare_stack(
    const std::vector<LayerInput>& layers, bool linear, std::size_t vertex_count,
    const LayersBakeOptions& options, std::vector<double>& seconds) {
  const bool image_alpha = options.alpha == ResultAlpha::kImage;
  std::vector<std::unique_ptr<Prepared>> prepared;
  for (const LayerInput& in : layers) {
    const auto layer_start = Clock::now();
    Expected<std::unique_ptr<Prepared>> p = prepare(in, linear, vertex_count);
    if (!p) return p.error();
    prepared.push_back(std::move(p).value());
    prepared.back()->image_alpha = image_alpha;
    prepared.back()->project_hidden = image_alpha && options.occluded == OccludedMode::kProject;
    seconds.push_back(seconds_since(layer_start));
  }
  return prepared;
}

// The vertex target's base per vertex: straight colour (the stack's working
// space) and coverage; ResultAlpha::kImage starts from opaque black.
std::vector<Rgba> vertex_base(const MeshData& mesh, const LayersBakeOptions& options, bool linear) {
  const std::size_t n = mesh.positions.size();
  std::vector<Rgba> colour(n, Rgba{0, 0, 0, options.alpha == ResultAlpha::kImage ? 1.f : 0.f});
  if (options.base == LayerBase::kColor) {
    std::fill(colour.begin(), colour.end(), to_work(options.base_color, linear));
  } else if (options.base == LayerBase::kMesh) {
    for (std::size_t v = 0; v < n; ++v) {
      const auto& c = mesh.vertex_colors[v];
      colour[v] = to_work(Rgba{c[0], c[1], c[2], c[3]}, linear);
    }
  }
  return colour;
}

// What the vertex target's blocks read and write.
struct VertexPass {
  const MeshData* mesh = nullptr;
  const std::vector<LayerInput>* layers = nullptr;
  const std::vector<std::unique_ptr<Prepared>>* prepared = nullptr;
  const StackScene* scene = nullptr;
  const std::vector<Float3>* normals = nullptr;  // empty: no layer reads them
  PointFrame frame;                              // mesh, adjacency
  const std::vector<uint32_t>* order = nullptr;  // empty: index order
  bool image_alpha = false;
  std::vector<Rgba>* colour = nullptr;
  std::vector<uint8_t>* state = nullptr;       // ResultAlpha::kImage: PointState per vertex
  std::vector<LayerCounts>* counts = nullptr;  // per block and layer
};

// One block of vertices through every layer: composited (coverage), or
// the single projection's lookup and state (ResultAlpha::kImage).
void vertex_block(const VertexPass& pass, std::size_t block, std::size_t begin, std::size_t end) {
  const MeshData& mesh = *pass.mesh;
  const std::size_t m = end - begin, layer_count = pass.layers->size();
  PointFrame frame = pass.frame;
  frame.first_vertex = begin;
  if (!pass.order->empty()) frame.vertex_ids = pass.order->data() + begin;
  const bool with_normals = !pass.normals->empty();
  std::vector<Vec3> points(m), point_normals(m);
  std::vector<Contribution> contribution(m);
  for (std::size_t i = 0; i < m; ++i) {
    const std::size_t v = frame.vertex(i);
    points[i] = vec(mesh.positions[v]);
    if (with_normals) point_normals[i] = vec((*pass.normals)[v]);
  }
  std::vector<Rgba>& colour = *pass.colour;
  for (std::size_t l = 0; l < layer_count; ++l) {
    const auto layer_start = Clock::now();
    LayerCounts& c = (*pass.counts)[block * layer_count + l];
    contributions(*(*pass.prepared)[l], frame, points.data(), point_normals.data(),
                  pass.scene->scene(), pass.scene->offset, 0, m, contribution.data(), c);
    if (pass.image_alpha) {  // the lookup itself, alpha included
      for (std::size_t i = 0; i < m; ++i) {
        const std::size_t v = frame.vertex(i);
        const Contribution& k = contribution[i];
        (*pass.state)[v] = k.state;
        if (k.coloured) colour[v] = {k.rgb[0], k.rgb[1], k.rgb[2], k.a};
      }
    } else {
      // Composite (straight colour B, coverage alpha) in the stack's working space.
      const LayerMode mode = (*pass.layers)[l].mode;
      for (std::size_t i = 0; i < m; ++i) composite(mode, contribution[i], colour[frame.vertex(i)]);
    }
    c.seconds += seconds_since(layer_start);
  }
}

// The unknown vertices and how they are resolved (bake/vertex/vertex_resolve.h):
// under ResultAlpha::kImage the hidden ones unless projected and those
// without a mapping, alpha a colour channel, unanchored components taking
// the projected colour or the image's mean (never black, never arbitrary;
// `fallback` counts the lookups); otherwise the uncovered ones, the fill
// over their RGB (alpha stays 0) or a constant's RGB (a component no
// layer covers: transparent black under the fill).
VertexResolvePlan plan_unknown(const VertexPass& pass, const LayersBakeOptions& options,
                               bool linear, LayerCounts& fallback, std::size_t& unknown_count) {
  const MeshData& mesh = *pass.mesh;
  const std::size_t n = mesh.positions.size();
  std::vector<Rgba>& colour = *pass.colour;
  std::vector<uint8_t> unknown(n, 0);
  VertexResolve how;
  how.fill = options.occluded != OccludedMode::kColor;
  how.linear = linear;
  std::optional<Rgba> mean;
  VertexShare share;
  if (pass.image_alpha) {
    const std::vector<uint8_t>& state = *pass.state;
    const bool project = options.occluded == OccludedMode::kProject;
    for (std::size_t v = 0; v < n; ++v) {
      unknown[v] = state[v] == kUnmapped || (state[v] == kHidden && !project);
    }
    how.constant = options.occluded_color;
    const Prepared& layer = *pass.prepared->front();
    how.fallback = [&](uint32_t v) -> Rgba {
      if (state[v] == kHidden) {
        std::optional<Rgba> c;
        with_projector(layer, [&](const auto& map, const auto& jacobian) {
          const Vec3 p = vec(mesh.positions[v]);
          const MapResult r = map(p);
          if (r.status == MapStatus::kUndefined) return;
          PointFrame one = pass.frame;
          one.first_vertex = v;
          c = filtered(layer, map, jacobian, one, 0, p, r, share, fallback.filter);
        });
        if (c) return *c;
      }
      if (!mean) mean = image_mean(layer.view);
      return *mean;
    };
  } else {
    for (std::size_t v = 0; v < n; ++v) unknown[v] = colour[v][3] > 0 ? 0 : 1;
    how.constant = how.fill ? Rgba{0, 0, 0, 0} : options.occluded_color;
    how.coverage = true;
  }
  unknown_count = static_cast<std::size_t>(std::count(unknown.begin(), unknown.end(), 1));
  VertexResolvePlan plan = plan_resolve(mesh, colour, unknown, std::move(how));
  plan.how.fallback = nullptr;  // it refers to this frame: not past it
  return plan;
}

}  // namespace

Expected<LayersVertexStage> bake_vertex_layers_sample(const MeshData& mesh,
                                                      const std::vector<LayerInput>& layers,
                                                      const LayersBakeOptions& options,
                                                      Progress* progress) {
  if (layers.empty()) return make_error(ErrorCode::kInvalidArgument, "no layers to bake");
  const bool image_alpha = options.alpha == ResultAlpha::kImage;
  if (image_alpha) {
    if (Status s = check_single_projection(layers, options); !s) return s.error();
  }
  const std::size_t n = mesh.positions.size();
  if (options.base == LayerBase::kMesh && mesh.vertex_colors.size() != n) {
    return make_error(ErrorCode::kInvalidArgument, "base \"mesh\": the mesh has no vertex colours");
  }
  LayersVertexStage stage;
  LayersBakeResult& result = stage.result;
  auto start = Clock::now();
  Expected<StackScene> scene = stack_scene(mesh, layers, options.scene);
  if (!scene) return scene.error();
  // The smooth normals, where a layer reads them (a camera's facing test,
  // an angle fade); otherwise every point's normal is zero (cosine 1).
  const bool with_normals = std::any_of(layers.begin(), layers.end(), needs_normals);
  std::vector<Float3> normals;
  if (with_normals) normals = smooth_vertex_normals(mesh);
  if (scene->own || with_normals) result.seconds_scene = seconds_since(start);

  // The layers ready, all at once: every block of vertices goes through
  // every layer, so no per-vertex array beyond the colours is held.
  start = Clock::now();
  const bool linear = stack_linear(layers);
  std::vector<double> prepare_seconds;
  Expected<std::vector<std::unique_ptr<Prepared>>> prepared =
      prepare_stack(layers, linear, n, options, prepare_seconds);
  if (!prepared) return prepared.error();
  std::vector<Rgba> colour = vertex_base(mesh, options, linear);
  std::vector<uint8_t> state;
  if (image_alpha) state.assign(n, kUnmapped);
  // The area and EWA filters' vertex shares.
  const bool shares = std::any_of(layers.begin(), layers.end(), [](const LayerInput& l) {
    return !l.photos && l.filter != VertexFilter::kBilinear;
  });
  Adjacency adjacency;
  if (shares) adjacency = build_adjacency(mesh);
  const std::vector<uint32_t> order =
      image_alpha ? visit_order(mesh, *prepared) : std::vector<uint32_t>{};
  // Per block and layer, so that the sums are taken in block order.
  std::vector<LayerCounts> counts(block_count(n, kGrain) * layers.size());
  VertexPass pass;
  pass.mesh = &mesh;
  pass.layers = &layers;
  pass.prepared = &*prepared;
  pass.scene = &*scene;
  pass.normals = &normals;
  pass.frame.mesh = &mesh;
  pass.frame.vertices = true;
  pass.frame.adjacency = shares ? &adjacency : nullptr;
  pass.order = &order;
  pass.image_alpha = image_alpha;
  pass.colour = &colour;
  pass.state = &state;
  pass.counts = &counts;
  const double pass_start = seconds_since(start);
  if (progress) progress->start("bake", n);
  parallel_for_blocks(n, kGrain, [&](std::size_t block, std::size_t begin, std::size_t end) {
    if (is_cancelled(progress)) return;
    vertex_block(pass, block, begin, end);
    if (progress) progress->advance(end - begin);
  });
  if (is_cancelled(progress)) return cancelled_error();
  if (progress) progress->finish();
  scene->own.reset();  // the BVH is not needed any more: free it before the fill
  result.seconds_layers = seconds_since(start);

  start = Clock::now();
  LayerCounts fallback;
  stage.plan = plan_unknown(pass, options, linear, fallback, result.uncovered);
  result.filled = stage.plan.plan.result.filled;
  result.unfilled = stage.plan.plan.result.unfilled;
  result.layers =
      layer_stats(layers, counts, n, prepare_seconds, result.seconds_layers - pass_start);
  result.layers[0].lookups += fallback.filter.samples;  // the fallbacks' (kImage: one layer)
  result.layers[0].outside += fallback.filter.outside;
  for (const LayerInput& in : layers) {
    if (Status s = check_texels_read(in.texture); !s) return s.error();
  }
  result.colors = std::move(colour);
  result.seconds_fill = seconds_since(start);
  return stage;
}

Expected<LayersBakeResult> bake_vertex_layers_finish(const MeshData& mesh,
                                                     LayersVertexStage stage) {
  const auto start = Clock::now();
  LayersBakeResult& result = stage.result;
  Expected<FillResult> fill = finish_resolve(mesh, result.colors, std::move(stage.plan));
  if (!fill) return fill.error();
  result.seconds_fill += seconds_since(start);
  return std::move(result);
}

Expected<LayersBakeResult> bake_vertex_layers(const MeshData& mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersBakeOptions& options,
                                              Progress* progress) {
  Expected<LayersVertexStage> stage = bake_vertex_layers_sample(mesh, layers, options, progress);
  if (!stage) return stage.error();
  if (progress) progress->start("fill", 1);
  Expected<LayersBakeResult> result = bake_vertex_layers_finish(mesh, std::move(stage).value());
  if (!result) return result.error();
  if (progress) progress->finish();
  if (is_cancelled(progress)) return cancelled_error();
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
  if (Status s = check_padding(options.padding); !s) return s.error();
  const LayersBakeOptions& lo = options.layers;
  if (lo.alpha != ResultAlpha::kCoverage) {
    return make_error(ErrorCode::kInvalidArgument,
                      "the layers atlas takes the coverage as alpha (ResultAlpha::kCoverage)");
  }
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
  const bool linear = stack_linear(layers);
  std::vector<std::unique_ptr<Prepared>> prepared;
  prepared.reserve(layers.size());
  const std::size_t atlas_texels = static_cast<std::size_t>(options.size) * options.size;
  for (const LayerInput& in : layers) {
    Expected<std::unique_ptr<Prepared>> p = prepare(in, linear, uv_mesh.positions.size());
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
    vo.scene = nullptr;  // the vertex target's own, over uv_mesh
    if (base_texture) vo.base = LayerBase::kNone;
    // The fill's per-vertex colours take the bilinear lookup, as the proxy atlas's.
    std::vector<LayerInput> bilinear = layers;
    for (LayerInput& l : bilinear) l.filter = VertexFilter::kBilinear;
    Expected<LayersBakeResult> vertex = bake_vertex_layers(uv_mesh, bilinear, vo);
    if (!vertex) return vertex.error();
    for (std::size_t l = 0; l < layers.size(); ++l) fill_seconds[l] = vertex->layers[l].seconds;
    fill_colors = std::move(vertex->colors);
    for (Rgba& c : fill_colors) c = to_work(c, linear);
  }
  result.seconds_fill = seconds_since(start);

  start = Clock::now();
  Expected<StackScene> scene = stack_scene(uv_mesh, layers, nullptr);
  if (!scene) return scene.error();
  const std::vector<Float3> normals = smooth_vertex_normals(uv_mesh);
  std::vector<float> base_premultiplied;
  ImageView base_view;
  if (base_texture && linear) {
    base_premultiplied = premultiplied_linear(options.base_texture);
    base_view = {options.base_texture.width, options.base_texture.height, base_premultiplied.data(),
                 ColorSpace::kLinear};
  } else if (base_texture) {
    base_view = options.base_texture;  // as stored, straight alpha
  }
  PointFrame frame;
  frame.mesh = &uv_mesh;
  frame.cell = ewa_cell(options.size, options.samples);
  result.seconds_scene = seconds_since(start);

  start = Clock::now();
  const int n = options.size;
  const std::size_t spt = static_cast<std::size_t>(options.samples);
  result.atlas.width = result.atlas.height = n;
  result.atlas.pixels.assign(static_cast<std::size_t>(n) * n * 4, 0.f);
  result.atlas.color_space = ColorSpace::kSrgb;
  result.atlas.has_alpha = true;
  result.baked.assign(static_cast<std::size_t>(n) * n, 0);
  const Rgba base_working = to_work(lo.base_color, linear);
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
        const SurfaceSample sp = surface_sample(uv_mesh, normals, r.sample_triangle[s], b1, b2);
        w.points[s] = sp.p;
        w.normals[s] = sp.n;
        if (lo.base == LayerBase::kColor) {
          w.colour[s] = base_working;
        } else if (base_vertex) {
          Rgba v{0, 0, 0, 0};
          for (int k = 0; k < 3; ++k) {
            const auto& vc = uv_mesh.vertex_colors[tri[k]];
            const Rgba lin = to_work(Rgba{vc[0], vc[1], vc[2], vc[3]}, linear);
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
          if (linear && s[3] > 0) {  // premultiplied: straight (else stored straight)
            for (int ch = 0; ch < 3; ++ch) s[ch] /= s[3];
          } else if (linear) {
            s = {0, 0, 0, 0};
          } else if (base_view.color_space == ColorSpace::kLinear) {
            s = linear_to_srgb(s);  // a linear texture in an sRGB-encoded stack
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
        PointFrame band_frame = frame;
        band_frame.triangles = r.sample_triangle.data();
        contributions(*prepared[l], band_frame, w.points.data(), w.normals.data(), scene->scene(),
                      scene->offset, 0, m, w.contribution.data(), c,
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
              add_interpolated(uv_mesh, fill_colors, r.sample_triangle[s], r.sample_b1[s],
                               r.sample_b2[s], filled);
            }
          }
        }
        uncovered += empty;
        Rgba out{0, 0, 0, 0};
        if (alpha > 0) {
          for (int ch = 0; ch < 3; ++ch) out[ch] = static_cast<float>(premultiplied[ch] / alpha);
          out[3] = static_cast<float>(std::min(1.0, alpha / static_cast<double>(spt)));
          out = from_work(out, linear);
        } else if (fill) {
          for (int ch = 0; ch < 3; ++ch) {
            out[ch] = static_cast<float>(filled[ch] / static_cast<double>(empty));
          }
          out = from_work(out, linear);
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
  scene->own.reset();
  for (std::size_t band = 0; band < band_count; ++band) {
    result.texels += band_texels[band];
    result.samples += band_samples[band];
    result.border_samples += band_border[band];
    result.uncovered += band_uncovered[band];
    if (!band_opaque[band]) result.opaque = false;
  }
  result.seconds_layers = seconds_since(start);
  result.layers = layer_stats(layers, counts, result.samples, fill_seconds, result.seconds_layers);

  start = Clock::now();
  result.padded = pad_atlas(result.atlas.pixels, result.baked, n, options.padding);
  result.seconds_pad = seconds_since(start);
  return result;
}

}  // namespace texbake
