#include "bake/engine/layers_bake.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
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
  bool seen = false;       // the projector sees it (even if a lookup then found nothing)
  bool in_domain = false;  // mapped inside the (u, v) domain
  bool outside = false;    // mapped outside it (a domain with an outside)
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
  if (r.status == MapStatus::kOutside && layer.rule.has_outside && layer.rule.outside_constant) {
    return layer.rule.outside_color;  // the single projection's --outside R,G,B[,A]
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

// One thread's buffers for layer_block, reused from block to block so that
// the pass allocates only while they grow.
struct LayerScratch {
  std::vector<MapResult> maps;
  std::vector<uint8_t> seen, blocked;
  std::vector<std::size_t> slot;
  std::vector<Vec3> points;
  VisibilityBatch batch;
  SegmentScratch segments;
  VertexShare share;
};

// Clears seen[i] for the points whose way to the layer's projector is
// blocked: the segment to a camera's centre, or the ray towards a proxy
// (points: the block's m = seen.size() points; maps: their mappings).
void trace_seen(const Prepared& layer, const Vec3* points, const std::vector<MapResult>& maps,
                const EmbreeScene& scene, double offset, std::vector<uint8_t>& seen,
                LayerScratch& scratch) {
  const std::size_t m = seen.size();
  std::vector<std::size_t>& slot = scratch.slot;
  slot.clear();
  if (layer.camera) {
    scratch.points.clear();
    for (std::size_t i = 0; i < m; ++i) {
      if (seen[i]) scratch.points.push_back(points[i]), slot.push_back(i);
    }
    scratch.blocked.assign(slot.size(), 0);
    occluded_segments(scene, offset, scratch.points, layer.camera->centre(), scratch.segments,
                      scratch.blocked.data());
    for (std::size_t k = 0; k < slot.size(); ++k) {
      if (scratch.blocked[k]) seen[slot[k]] = 0;
    }
  } else {
    VisibilityBatch& batch = scratch.batch;
    batch.clear();
    for (std::size_t i = 0; i < m; ++i) {
      if (!seen[i]) continue;
      batch.add(points[i], maps[i].to_projector);
      slot.push_back(i);
    }
    std::vector<uint8_t>& visible = scratch.blocked;  // here: 1 where the ray is free
    visible.assign(slot.size(), 0);
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
                 Contribution* out, LayerCounts& counts, LayerScratch& scratch) {
  const LayerInput& in = *layer.input;
  VertexShare& share = scratch.share;
  const std::size_t m = end - begin;
  std::vector<MapResult>& maps = scratch.maps;
  std::vector<uint8_t>& seen = scratch.seen;
  maps.resize(m);
  seen.assign(m, 1);
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
    trace_seen(layer, points + begin, maps, *scene, offset, seen, scratch);
  }
  for (std::size_t i = 0; i < m; ++i) {
    Contribution& c = out[begin + i];
    c = {};
    const MapResult& r = maps[i];
    c.in_domain = r.status == MapStatus::kOk;
    c.outside = r.status == MapStatus::kOutside && layer.rule.has_outside;
    if (r.status == MapStatus::kUndefined) continue;
    c.seen = seen[i] != 0;
    c.state = seen[i] ? kSeen : kHidden;
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
        } else {
          c.state = kUnmapped;
        }
      }
      continue;
    }
    if (!seen[i]) continue;
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
  }
}

// A "cameras" layer's contributions for the points [begin, end): the
// photo blend of point ids[i] (atlas samples) or of the frame's vertex i.
void photo_block(const Prepared& layer, const uint32_t* ids, const PointFrame& frame,
                 std::size_t begin, std::size_t end, Contribution* out) {
  const LayerInput& in = *layer.input;
  const PhotoPoints& points = ids ? in.photos->samples : in.photos->vertices;
  for (std::size_t i = begin; i < end; ++i) {
    const std::size_t id = ids ? ids[i] : frame.vertex(i);
    Contribution& c = out[i];
    c = {};
    const uint8_t state = points.state[id];
    c.in_domain = state != PhotoPoints::kNoView;
    if (state != PhotoPoints::kSeen) {
      c.state = state == PhotoPoints::kNoView ? kUnmapped : kHidden;
      continue;
    }
    c.state = kSeen;
    c.seen = true;
    c.coloured = true;
    c.rgb = points.rgb[id];
    // Cosines are needed by an angle fade only (prepare checks them).
    c.a = static_cast<float>(in.opacity) * (in.angle_fade ? fade(layer, points.cosine[id]) : 1.f);
  }
}

// A layer's counts of the contributions [0, m), in point order (so the
// alpha sums do not depend on the thread count). The atlas target counts
// its lookups here too (one per coloured supersample, and the outside ones
// among them); the vertex target's are its filter's.
void tally(const Contribution* c, std::size_t m, LayerCounts& counts, bool atlas) {
  for (std::size_t i = 0; i < m; ++i) {
    const Contribution& k = c[i];
    if (k.in_domain) ++counts.in_domain;
    if (k.seen) ++counts.visible;
    if (k.state == kHidden) ++counts.hidden;
    if (k.state == kUnmapped) ++counts.unmapped;
    if (!k.coloured) continue;
    if (k.a > 0) ++counts.blended;
    counts.alpha_sum += k.a;
    if (atlas) {
      ++counts.filter.samples;
      if (k.outside) ++counts.filter.outside;
    }
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
                   std::size_t end, Contribution* out, LayerCounts& counts, LayerScratch& scratch,
                   const uint32_t* sample_ids = nullptr) {
  if (layer.input->photos) {
    photo_block(layer, sample_ids, frame, begin, end, out);
    return;
  }
  with_projector(layer, [&](const auto& map, const auto& jacobian) {
    layer_block(layer, map, jacobian, frame, points, normals, scene, offset, begin, end, out,
                counts, scratch);
  });
}

// Whether a "cameras" layer's blend holds every array for n points: the
// states and colours, and the cosines unless the layer has no angle fade
// (which alone reads them) and they were not computed.
bool photo_points_complete(const PhotoPoints& points, std::size_t n, const LayerInput& in) {
  return points.state.size() == n && points.rgb.size() == n &&
         (points.cosine.size() == n || (points.cosine.empty() && !in.angle_fade));
}

// One layer's image and rules, ready for layer_block, in a stack whose
// working space is linear light (`linear`) or the stored encoding. Held by
// pointer (its rule points at its own pyramid). A "cameras" layer's vertex
// blend is checked here; its atlas samples by check_atlas_stack.
Expected<std::unique_ptr<Prepared>> prepare(const LayerInput& in, bool linear,
                                            std::size_t vertex_count) {
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
    if (!photo_points_complete(in.photos->vertices, vertex_count, in)) {
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
  if (l.opacity != 1 || l.mask.has_texels() || l.angle_fade || l.mode != LayerMode::kOver) {
    return refuse("takes no opacity, mask, angle fade or blend mode");
  }
  if (options.base != LayerBase::kNone) return refuse("takes no base");
  if (l.photos) return ok_status();  // the photo bake's blend: straight linear light
  if (l.linear && !l.straight) {
    return refuse("takes the stored encoding or straight linear light, not premultiplied alpha");
  }
  if (l.outside == LayerOutside::kTransparent) {
    return refuse("takes outside \"clamp\" or a colour, not \"transparent\"");
  }
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

// What both targets' passes read: the stack, ready.
struct StackPass {
  const MeshData* mesh = nullptr;
  const std::vector<LayerInput>* layers = nullptr;
  const std::vector<std::unique_ptr<Prepared>>* prepared = nullptr;
  const StackScene* scene = nullptr;
  const std::vector<Float3>* normals = nullptr;  // empty: no layer reads them
  PointFrame frame;          // mesh; the vertex target's adjacency, the atlas's EWA cell
  bool image_alpha = false;  // ResultAlpha::kImage
};

// The stack's fields of a pass.
void set_stack(StackPass& pass, const MeshData& mesh, const std::vector<LayerInput>& layers,
               const std::vector<std::unique_ptr<Prepared>>& prepared, const StackScene& scene,
               const std::vector<Float3>& normals, bool image_alpha) {
  pass.mesh = &mesh;
  pass.layers = &layers;
  pass.prepared = &prepared;
  pass.scene = &scene;
  pass.normals = &normals;
  pass.frame.mesh = &mesh;
  pass.image_alpha = image_alpha;
}

// What the vertex target's blocks read and write.
struct VertexPass : StackPass {
  const std::vector<uint32_t>* order = nullptr;  // empty: index order
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
  LayerScratch scratch;
  for (std::size_t l = 0; l < layer_count; ++l) {
    const auto layer_start = Clock::now();
    LayerCounts& c = (*pass.counts)[block * layer_count + l];
    contributions(*(*pass.prepared)[l], frame, points.data(), point_normals.data(),
                  pass.scene->scene(), pass.scene->offset, 0, m, contribution.data(), c, scratch);
    tally(contribution.data(), m, c, false);
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
    const Prepared& layer = *pass.prepared->front();
    // A photo blend has nothing to project: kProject acts as kFill, and an
    // unanchored component takes the constant.
    const bool photos = layer.input->photos != nullptr;
    const bool project = options.occluded == OccludedMode::kProject && !photos;
    for (std::size_t v = 0; v < n; ++v) {
      unknown[v] = state[v] == kUnmapped || (state[v] == kHidden && !project);
    }
    how.constant = options.occluded_color;
    if (!photos)
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

LayersAtlasOptions single_projection_atlas(int size, int samples, int padding,
                                           OccludedMode occluded, const Rgba& occluded_color) {
  LayersAtlasOptions atlas;
  atlas.size = size;
  atlas.samples = samples;
  atlas.padding = padding;
  atlas.layers.alpha = ResultAlpha::kImage;
  atlas.layers.occluded = occluded;
  atlas.layers.occluded_color = occluded_color;
  return atlas;
}

LayerInput single_projection_layer(const ImageView& image, const Proxy& proxy,
                                   const VertexBakeOptions& options) {
  LayerInput in;
  in.name = "image";
  in.projector = proxy;
  in.texture = image;
  in.visibility =
      options.visibility == Visibility::kFirst ? LayerVisibility::kFirst : LayerVisibility::kAll;
  in.outside = options.outside == OutsideMode::kColor ? LayerOutside::kColor : LayerOutside::kClamp;
  in.outside_color = options.outside_color;
  in.filter = options.filter;
  in.samples = options.samples;
  in.plane_wrap = options.plane_wrap;
  in.linear = options.linear;
  in.straight = options.linear;
  return in;
}

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
  set_stack(pass, mesh, layers, *prepared, *scene, normals, image_alpha);
  pass.frame.vertices = true;
  pass.frame.adjacency = shares ? &adjacency : nullptr;
  pass.order = &order;
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

// Covered texels per batch within a band: large enough to amortise a ray
// batch, small enough that the batch's points stay in cache.
constexpr std::size_t kTexelBatch = 1024;

// The single projection's texels with samples to fill when the fill is not
// computed before the pass: their coloured sum so far and the fill
// samples' (triangle, b1, b2), finished after it (finish_deferred).
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

// What the atlas pass reads (and the atlas it writes: bands write disjoint
// rows).
struct AtlasPass : StackPass {
  bool linear = false;
  bool overlaps = false;  // the raster lists overlap candidates: choose among them
  std::size_t spt = 1;
  int size = 0;
  // kCoverage: the base.
  LayerBase base = LayerBase::kNone;
  Rgba base_working{0, 0, 0, 0};
  bool base_vertex = false;
  ImageView base_view;  // the mesh's texture (data null: none)
  // The fill's per-vertex colours (working space); null under kImage when
  // they are computed after the pass (Deferred); null under kCoverage
  // when the result takes the constant.
  const std::vector<Rgba>* fill_colors = nullptr;
  bool fill = false;                // samples without colour take the fill (else the constant)
  Rgba occluded_color{0, 0, 0, 1};  // sRGB-encoded, as given
  Rgba occluded_working{0, 0, 0, 1};
  float* atlas = nullptr;
  uint8_t* baked = nullptr;
};

// One band's totals.
struct BandTotals {
  std::size_t uncovered = 0;
  bool opaque = true;
};

// One thread's working memory, reused across bands and batches: the pass
// allocates only while the buffers grow.
struct AtlasWorker {
  AtlasRaster band;
  AtlasBandScratch scratch;
  // Per point of a batch: its samples, then (an overlapping layout) the
  // further triangles that contain them.
  std::vector<uint32_t> triangles;
  std::vector<Vec3> points, normals;
  std::vector<Rgba> colour;                // kCoverage: straight colour and coverage
  std::vector<Contribution> contribution;  // per layer and point, layer-major
  std::vector<uint32_t> ids;               // a "cameras" layer: the samples' indices in its blend
  LayerScratch layer;
  Deferred deferred;
};

// The band's sample indices [s0, s1) in a "cameras" layer's blend (false:
// the blend does not cover one of their texels).
bool photo_sample_ids(const PhotoLayerPoints& photos, const AtlasRaster& r, std::size_t spt,
                      std::size_t k0, std::size_t k1, std::vector<uint32_t>& ids) {
  ids.resize((k1 - k0) * spt);
  for (std::size_t k = k0; k < k1; ++k) {
    const uint32_t first = photos.texel_first[r.texels[k]];
    if (first == PhotoLayerPoints::kNoTexel || first + spt > photos.samples.size()) return false;
    for (std::size_t j = 0; j < spt; ++j)
      ids[(k - k0) * spt + j] = static_cast<uint32_t>(first + j);
  }
  return true;
}

// The base under a point of texel t on triangle tri at (b1, b2) (kCoverage).
Rgba atlas_base(const AtlasPass& pass, std::size_t t, uint32_t tri, double b1, double b2) {
  if (pass.base == LayerBase::kColor) return pass.base_working;
  if (pass.base_vertex) {
    const auto& corners = pass.mesh->triangles[tri];
    const double w[3] = {1 - b1 - b2, b1, b2};
    Rgba v{0, 0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const auto& vc = pass.mesh->vertex_colors[corners[k]];
      const Rgba c = to_work(Rgba{vc[0], vc[1], vc[2], vc[3]}, pass.linear);
      for (int ch = 0; ch < 4; ++ch) v[ch] += static_cast<float>(w[k] * c[ch]);
    }
    return v;
  }
  if (!pass.base_view.data) return {0, 0, 0, 0};
  // The texel centre's lookup, shared by the texel's samples.
  const int n = pass.size;
  const double x = static_cast<double>(t % n), y = static_cast<double>(t / n);
  const UV uv{(x + 0.5) / n, 1 - (y + 0.5) / n};
  Rgba s = sample_bilinear(pass.base_view, uv, WrapMode::kClamp, WrapMode::kClamp);
  if (pass.linear && s[3] > 0) {  // premultiplied: straight (else stored straight)
    for (int ch = 0; ch < 3; ++ch) s[ch] /= s[3];
  } else if (pass.linear) {
    s = {0, 0, 0, 0};
  } else if (pass.base_view.color_space == ColorSpace::kLinear) {
    s = linear_to_srgb(s);  // a linear texture in an sRGB-encoded stack
  }
  return s;
}

// The batch's points: samples [s0, s1) of w.band, then the candidate
// entries [a0, a1); their triangles, positions, normals (where a layer
// reads them) and, under kCoverage, bases.
void batch_points(const AtlasPass& pass, AtlasWorker& w, std::size_t s0, std::size_t s1,
                  std::size_t a0, std::size_t a1) {
  const AtlasRaster& r = w.band;
  const std::size_t own = s1 - s0, count = own + (a1 - a0);
  w.triangles.resize(count);
  w.points.resize(count);
  w.normals.resize(count);
  if (!pass.image_alpha) w.colour.resize(count);
  const bool with_normals = !pass.normals->empty();
  for (std::size_t i = 0; i < count; ++i) {
    const bool alt = i >= own;
    const std::size_t s = alt ? r.alt_sample[a0 + i - own] : s0 + i;
    const uint32_t tri = alt ? r.alt_triangle[a0 + i - own] : r.sample_triangle[s];
    const double b1 = alt ? r.alt_b1[a0 + i - own] : r.sample_b1[s];
    const double b2 = alt ? r.alt_b2[a0 + i - own] : r.sample_b2[s];
    w.triangles[i] = tri;
    if (with_normals) {
      const SurfaceSample sp = surface_sample(*pass.mesh, *pass.normals, tri, b1, b2);
      w.points[i] = sp.p;
      w.normals[i] = sp.n;
    } else {
      w.points[i] = surface_point(*pass.mesh, tri, b1, b2);
      w.normals[i] = {0, 0, 0};
    }
    if (!pass.image_alpha) {
      const std::size_t t = r.texels[s / pass.spt];
      if (pass.base_view.data && i > 0 && !alt && (s - s0) % pass.spt != 0) {
        w.colour[i] = w.colour[i - 1];  // the texel's base texture lookup, shared
      } else {
        w.colour[i] = atlas_base(pass, t, tri, b1, b2);
      }
    }
  }
}

// A point some layer sees (the overlap choice's test).
bool seen_by_some_layer(const AtlasWorker& w, std::size_t layers, std::size_t count,
                        std::size_t i) {
  for (std::size_t l = 0; l < layers; ++l) {
    if (w.contribution[l * count + i].state == kSeen) return true;
  }
  return false;
}

// An overlapping layout: a sample whose own (lowest-index) triangle no
// layer sees moves to the first candidate, in ascending triangle index, that
// some layer sees, if any (its point, every layer's contribution, its
// colour), so a texel shared by visible and hidden surfaces takes the
// visible ones' colour. The choice depends only on the sample, never on
// the thread count.
void choose_overlaps(const AtlasPass& pass, AtlasWorker& w, std::size_t s0, std::size_t s1,
                     std::size_t a0, std::size_t a1) {
  AtlasRaster& r = w.band;
  const std::size_t own = s1 - s0, count = own + (a1 - a0);
  const std::size_t layers = pass.layers->size();
  for (std::size_t a = a0; a < a1;) {
    const std::size_t s = r.alt_sample[a];
    std::size_t a_end = a;
    while (a_end < a1 && r.alt_sample[a_end] == s) ++a_end;
    if (!seen_by_some_layer(w, layers, count, s - s0)) {
      for (std::size_t b = a; b < a_end; ++b) {
        const std::size_t i = own + (b - a0);
        if (!seen_by_some_layer(w, layers, count, i)) continue;
        for (std::size_t l = 0; l < layers; ++l) {
          w.contribution[l * count + (s - s0)] = w.contribution[l * count + i];
        }
        if (!pass.image_alpha) w.colour[s - s0] = w.colour[i];
        w.triangles[s - s0] = w.triangles[i];
        r.sample_triangle[s] = r.alt_triangle[b];
        r.sample_b1[s] = r.alt_b1[b];
        r.sample_b2[s] = r.alt_b2[b];
        break;
      }
    }
    a = a_end;
  }
}

// The single projection's texel (ResultAlpha::kImage, SPEC section 4): the
// plain mean of its samples in the working encoding, alpha a colour
// channel: a sample's lookup, the --occluded constant (a texel all of whose
// samples take it stores it exactly), or the fill interpolated over the
// sample's triangle, summed after the coloured samples (or deferred).
void image_texel(const AtlasPass& pass, AtlasWorker& w, std::size_t k, std::size_t s0) {
  const AtlasRaster& r = w.band;
  const std::size_t spt = pass.spt;
  const uint32_t t = r.texels[k];
  std::array<double, 4> acc{0, 0, 0, 0};
  std::size_t constants = 0;
  bool any_fill = false;
  for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
    const Contribution& c = w.contribution[s - s0];
    if (c.coloured) {
      for (int ch = 0; ch < 3; ++ch) acc[ch] += c.rgb[ch];
      acc[3] += c.a;
    } else if (!pass.fill) {
      for (int ch = 0; ch < 4; ++ch) acc[ch] += pass.occluded_working[ch];
      ++constants;
    } else {
      any_fill = true;
    }
  }
  Deferred::Texel* later = nullptr;
  if (any_fill && !pass.fill_colors) {
    w.deferred.texels.push_back({t, acc, static_cast<uint32_t>(w.deferred.samples.size()), 0});
    later = &w.deferred.texels.back();
  }
  for (std::size_t s = k * spt; any_fill && s < (k + 1) * spt; ++s) {
    if (w.contribution[s - s0].coloured) continue;
    if (later) {
      w.deferred.samples.push_back({r.sample_triangle[s], r.sample_b1[s], r.sample_b2[s]});
      ++later->count;
    } else {
      add_interpolated(*pass.mesh, *pass.fill_colors, r.sample_triangle[s], r.sample_b1[s],
                       r.sample_b2[s], acc);
    }
  }
  if (later) return;
  const Rgba out = plain_texel(acc, spt, constants, pass.occluded_color,
                               [&](const Rgba& c) { return from_work(c, pass.linear); });
  std::copy(out.begin(), out.end(), pass.atlas + 4 * static_cast<std::size_t>(t));
  pass.baked[t] = 1;
}

// A stack's texel (ResultAlpha::kCoverage): the mean of its samples in
// premultiplied light (the stack's working space), straight and
// sRGB-encoded out; a texel none of whose samples is covered takes the
// mean of their fill colours, or the constant's RGB, alpha 0.
void coverage_texel(const AtlasPass& pass, AtlasWorker& w, std::size_t k, std::size_t s0,
                    BandTotals& totals) {
  const AtlasRaster& r = w.band;
  const std::size_t spt = pass.spt;
  std::array<double, 3> premultiplied{0, 0, 0}, filled{0, 0, 0};
  double alpha = 0;
  std::size_t empty = 0;
  for (std::size_t s = k * spt; s < (k + 1) * spt; ++s) {
    const Rgba& c = w.colour[s - s0];
    if (c[3] > 0) {
      for (int ch = 0; ch < 3; ++ch) premultiplied[ch] += double(c[3]) * c[ch];
      alpha += c[3];
    } else {
      ++empty;
      if (pass.fill) {
        add_interpolated(*pass.mesh, *pass.fill_colors, r.sample_triangle[s], r.sample_b1[s],
                         r.sample_b2[s], filled);
      }
    }
  }
  totals.uncovered += empty;
  Rgba out{0, 0, 0, 0};
  if (alpha > 0) {
    for (int ch = 0; ch < 3; ++ch) out[ch] = static_cast<float>(premultiplied[ch] / alpha);
    out[3] = static_cast<float>(std::min(1.0, alpha / static_cast<double>(spt)));
    out = from_work(out, pass.linear);
  } else if (pass.fill) {
    for (int ch = 0; ch < 3; ++ch) {
      out[ch] = static_cast<float>(filled[ch] / static_cast<double>(empty));
    }
    out = from_work(out, pass.linear);
  } else {
    out = {pass.occluded_color[0], pass.occluded_color[1], pass.occluded_color[2], 0};
  }
  if (out[3] < 1) totals.opaque = false;
  const std::size_t t = r.texels[k];
  std::copy(out.begin(), out.end(), pass.atlas + 4 * t);
  pass.baked[t] = 1;
}

// Texels [k0, k1) of w.band through every layer (counts: the band's, one
// per layer), into the atlas. False: a "cameras" layer's blend does not
// cover them.
bool atlas_batch(const AtlasPass& pass, AtlasWorker& w, std::size_t k0, std::size_t k1,
                 LayerCounts* counts, BandTotals& totals) {
  const AtlasRaster& r = w.band;
  const std::size_t spt = pass.spt, s0 = k0 * spt, s1 = k1 * spt, own = s1 - s0;
  std::size_t a0 = 0, a1 = 0;  // r.alt_* entries of samples [s0, s1)
  if (pass.overlaps) {
    a0 = std::lower_bound(r.alt_sample.begin(), r.alt_sample.end(), s0) - r.alt_sample.begin();
    a1 = std::lower_bound(r.alt_sample.begin(), r.alt_sample.end(), s1) - r.alt_sample.begin();
  }
  const std::size_t count = own + (a1 - a0);
  batch_points(pass, w, s0, s1, a0, a1);
  const std::vector<LayerInput>& layers = *pass.layers;
  w.contribution.resize(layers.size() * count);
  PointFrame frame = pass.frame;
  frame.triangles = w.triangles.data();
  for (std::size_t l = 0; l < layers.size(); ++l) {
    const auto layer_start = Clock::now();
    if (layers[l].photos && !photo_sample_ids(*layers[l].photos, r, spt, k0, k1, w.ids)) {
      return false;
    }
    Contribution* out = w.contribution.data() + l * count;
    contributions(*(*pass.prepared)[l], frame, w.points.data(), w.normals.data(),
                  pass.scene->scene(), pass.scene->offset, 0, count, out, counts[l], w.layer,
                  layers[l].photos ? w.ids.data() : nullptr);
    if (!pass.image_alpha) {
      for (std::size_t i = 0; i < count; ++i) composite(layers[l].mode, out[i], w.colour[i]);
    }
    counts[l].seconds += seconds_since(layer_start);
  }
  if (a1 > a0) choose_overlaps(pass, w, s0, s1, a0, a1);
  for (std::size_t l = 0; l < layers.size(); ++l) {
    tally(w.contribution.data() + l * count, own, counts[l], true);
  }
  for (std::size_t k = k0; k < k1; ++k) {
    if (pass.image_alpha) {
      image_texel(pass, w, k, s0);
    } else {
      coverage_texel(pass, w, k, s0, totals);
    }
  }
  return true;
}

// The fill's per-vertex colours in the stack's working space: the vertex
// target on uv_mesh over the same scene, with the bilinear lookup (as the
// atlas samples take it); the single projection's fill (kImage: every
// hidden or unmapped vertex filled), a stack's with its base (but the
// mesh's texture, which vertices cannot look up). `seconds`: per layer.
Expected<std::vector<Rgba>> atlas_fill_colors(const MeshData& uv_mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersAtlasOptions& options,
                                              const EmbreeScene* scene, bool linear,
                                              std::vector<double>& seconds,
                                              LayersAtlasResult& counts) {
  LayersBakeOptions vo = options.layers;
  vo.scene = scene;
  if (vo.alpha == ResultAlpha::kImage) vo.occluded = OccludedMode::kFill;
  if (vo.base == LayerBase::kMesh && options.base_texture.data) vo.base = LayerBase::kNone;
  std::vector<LayerInput> bilinear = layers;
  for (LayerInput& l : bilinear) l.filter = VertexFilter::kBilinear;
  Expected<LayersBakeResult> vertex = bake_vertex_layers(uv_mesh, bilinear, vo);
  if (!vertex) return vertex.error();
  for (std::size_t l = 0; l < layers.size(); ++l) seconds[l] += vertex->layers[l].seconds;
  counts.vertices_filled = vertex->filled;
  counts.vertices_unfilled = vertex->unfilled;
  std::vector<Rgba> colors = std::move(vertex->colors);
  for (Rgba& c : colors) c = to_work(c, linear);
  return colors;
}

// The deferred texels (kImage), their fill samples added to their sums.
void finish_deferred(const AtlasPass& pass, const std::vector<Deferred>& deferred,
                     const std::vector<Rgba>& fill_colors) {
  for (const Deferred& d : deferred) {
    for (Deferred::Texel texel : d.texels) {
      for (uint32_t i = texel.first; i < texel.first + texel.count; ++i) {
        const Deferred::Sample& ds = d.samples[i];
        add_interpolated(*pass.mesh, fill_colors, ds.triangle, ds.b1, ds.b2, texel.acc);
      }
      const Rgba out = plain_texel(texel.acc, pass.spt, 0, pass.occluded_color,
                                   [&](const Rgba& c) { return from_work(c, pass.linear); });
      std::copy(out.begin(), out.end(), pass.atlas + 4 * static_cast<std::size_t>(texel.texel));
      pass.baked[texel.texel] = 1;
    }
  }
}

// The input checks of bake_atlas_layers.
Status check_atlas_stack(const MeshData& uv_mesh, const std::vector<LayerInput>& layers,
                         const LayersAtlasOptions& options) {
  if (layers.empty()) return make_error(ErrorCode::kInvalidArgument, "no layers to bake");
  if (Status s = check_padding(options.padding); !s) return s;
  const LayersBakeOptions& lo = options.layers;
  if (lo.alpha == ResultAlpha::kImage) {
    if (Status s = check_single_projection(layers, lo); !s) return s;
  }
  const bool base_texture = lo.base == LayerBase::kMesh && options.base_texture.data;
  if (lo.base == LayerBase::kMesh && !base_texture &&
      uv_mesh.vertex_colors.size() != uv_mesh.positions.size()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "base \"mesh\": the mesh has neither a texture nor vertex colours");
  }
  if (base_texture && (options.base_texture.width < 1 || options.base_texture.height < 1)) {
    return make_error(ErrorCode::kInvalidArgument, "base \"mesh\": the mesh's texture is empty");
  }
  const std::size_t atlas_texels = static_cast<std::size_t>(options.size) * options.size;
  for (const LayerInput& in : layers) {
    if (!in.photos) continue;
    const std::size_t n = in.photos->samples.size();
    if (!photo_points_complete(in.photos->samples, n, in) ||
        in.photos->texel_first.size() != atlas_texels ||
        n % static_cast<std::size_t>(options.samples)) {
      return make_error(ErrorCode::kInvalidArgument,
                        in.name + ": the cameras layer's photo blend is not this atlas's");
    }
  }
  return ok_status();
}

int64_t nanoseconds(Clock::duration d) {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(d).count();
}

// What the band pass leaves besides the atlas: the counts per band and
// layer (band-major), the deferred texels, and the threads' time in
// rasterising and in the layers.
struct BandPass {
  std::vector<LayerCounts> counts;
  std::vector<Deferred> deferred;
  int64_t raster_ns = 0, sample_ns = 0;
};

// Every band of `bands` rasterised and its texels through the stack into
// the atlas (pass); the texel, border-sample and coverage totals into
// `result`. Progress: "sample", per atlas row (`rows`). Errors:
// kCancelled, kInvalidArgument (a cameras layer's blend does not cover the
// texels).
Expected<BandPass> band_pass(const AtlasBands& bands, const AtlasPass& pass,
                             std::size_t layer_count, int rows, Progress* progress,
                             LayersAtlasResult& result) {
  // Bands write disjoint rows of the atlas, and each texel's value depends
  // only on its own samples: the result is independent of the thread count.
  // Counts are kept per band and layer and summed in band order.
  const std::size_t band_count = bands.band_count();
  BandPass out;
  out.counts.resize(band_count * layer_count);
  std::vector<LayerCounts>& counts = out.counts;
  std::vector<std::size_t> band_texels(band_count, 0), band_border(band_count, 0);
  std::vector<BandTotals> totals(band_count);
  std::vector<uint8_t> band_mismatch(band_count, 0);
  std::atomic<int64_t> raster_ns{0}, sample_ns{0};
  std::mutex deferred_mutex;
  if (progress) progress->start("sample", static_cast<std::size_t>(rows));
  parallel_for_chunks(band_count, 1, [&](std::size_t band_begin, std::size_t band_end) {
    AtlasWorker w;
    int64_t r_ns = 0, s_ns = 0;
    for (std::size_t band = band_begin; band < band_end; ++band) {
      if (is_cancelled(progress)) break;
      const auto ta = Clock::now();
      bands.rasterize(band, w.band, w.scratch);
      const auto tb = Clock::now();
      const std::size_t texels = w.band.texels.size();
      for (std::size_t k = 0; k < texels && !band_mismatch[band]; k += kTexelBatch) {
        if (!atlas_batch(pass, w, k, std::min(texels, k + kTexelBatch),
                         counts.data() + band * layer_count, totals[band])) {
          band_mismatch[band] = 1;
        }
      }
      r_ns += nanoseconds(tb - ta);
      s_ns += nanoseconds(Clock::now() - tb);
      band_texels[band] = texels;
      band_border[band] = w.band.border_samples;
      if (progress) progress->advance(bands.band_rows(band));
    }
    raster_ns += r_ns;
    sample_ns += s_ns;
    if (!w.deferred.texels.empty()) {
      std::lock_guard<std::mutex> lock(deferred_mutex);
      out.deferred.push_back(std::move(w.deferred));
    }
  });
  if (is_cancelled(progress)) return cancelled_error();
  if (std::any_of(band_mismatch.begin(), band_mismatch.end(), [](uint8_t b) { return b; })) {
    return make_error(ErrorCode::kInvalidArgument,
                      "a cameras layer's photo blend does not cover this atlas's texels");
  }
  if (progress) progress->finish();
  for (std::size_t band = 0; band < band_count; ++band) {
    result.texels += band_texels[band];
    result.border_samples += band_border[band];
    result.uncovered += totals[band].uncovered;
    if (!totals[band].opaque) result.opaque = false;
  }
  out.raster_ns = raster_ns.load();
  out.sample_ns = sample_ns.load();
  return out;
}

}  // namespace

Expected<LayersAtlasResult> bake_atlas_layers(const MeshData& uv_mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersAtlasOptions& options,
                                              Progress* progress) {
  if (Status s = check_atlas_stack(uv_mesh, layers, options); !s) return s.error();
  const LayersBakeOptions& lo = options.layers;
  const bool image_alpha = lo.alpha == ResultAlpha::kImage;
  // Candidate triangles of overlapping samples matter only when rays
  // choose; a "cameras" layer's blend is per sample (no candidates).
  const bool overlaps = options.resolve_overlaps &&
                        std::any_of(layers.begin(), layers.end(), needs_scene) &&
                        std::none_of(layers.begin(), layers.end(),
                                     [](const LayerInput& l) { return l.photos != nullptr; });
  const AtlasRasterOptions raster_options{options.size, options.samples, overlaps};
  LayersAtlasResult result;

  // The input checked first; the bands (48 bytes a triangle) are made after
  // the fill, whose solver then does not hold its memory beside them (the
  // 13.3M-triangle bake of bench/scale peaked during the fill).
  auto start = Clock::now();
  bool covers = false;  // some triangle reaches the atlas' rows: the bands are not empty
  if (Status s = AtlasBands::check(uv_mesh, raster_options, &covers); !s) return s.error();
  double raster_seconds = seconds_since(start);

  // The scene, shared by the samples' rays and the fill's vertex target;
  // the smooth normals where a layer reads them.
  start = Clock::now();
  Expected<StackScene> scene =
      covers ? stack_scene(uv_mesh, layers, lo.scene) : Expected<StackScene>(StackScene{});
  if (!scene) return scene.error();
  const bool with_normals = std::any_of(layers.begin(), layers.end(), needs_normals);
  std::vector<Float3> normals;
  if (with_normals && covers) normals = smooth_vertex_normals(uv_mesh);
  result.seconds_scene = seconds_since(start);

  // The fill before the pass, so each streamed texel is final once written:
  // a stack's (its uncovered samples), or the single projection's with
  // visibility and --occluded fill (nearly every mesh then has hidden
  // samples), or with a "cameras" layer (its unseen samples: most meshes
  // have some; kProject acts as kFill). Otherwise the single projection's samples to fill are only
  // those no lookup colours (unmapped ones: a proxy's singular points; a
  // camera's points facing away): their texels wait for the pass's end, if
  // there are any. The fill runs before the layers are prepared, so that
  // their working images (a linear copy, a MIP pyramid) are not held beside
  // the fill's own.
  const bool linear = stack_linear(layers);
  std::vector<double> own_seconds(layers.size(), 0.0);  // per layer: its fill, its preparation
  const bool fill = lo.occluded != OccludedMode::kColor;
  const bool fill_first = covers && fill &&
                          (!image_alpha || layers[0].photos != nullptr ||
                           (lo.occluded == OccludedMode::kFill && scene->scene() != nullptr));
  std::vector<Rgba> fill_colors;
  if (fill_first) {
    if (is_cancelled(progress)) return cancelled_error();
    start = Clock::now();
    Expected<std::vector<Rgba>> colors =
        atlas_fill_colors(uv_mesh, layers, options, scene->scene(), linear, own_seconds, result);
    if (!colors) return colors.error();
    fill_colors = std::move(colors).value();
    result.seconds_fill = seconds_since(start);
  }

  // The layers ready, all at once (every band goes through every layer).
  std::vector<double> prepare_seconds;
  Expected<std::vector<std::unique_ptr<Prepared>>> prepared =
      prepare_stack(layers, linear, uv_mesh.positions.size(), lo, prepare_seconds);
  if (!prepared) return prepared.error();
  double prepare_total = 0;
  for (std::size_t l = 0; l < layers.size(); ++l) {
    own_seconds[l] += prepare_seconds[l];
    prepare_total += prepare_seconds[l];
  }

  start = Clock::now();
  Expected<AtlasBands> bands_or = AtlasBands::prepare(uv_mesh, raster_options);
  if (!bands_or) return bands_or.error();
  const AtlasBands& bands = *bands_or;
  raster_seconds += seconds_since(start);

  start = Clock::now();
  const int n = options.size;
  result.atlas.width = result.atlas.height = n;
  result.atlas.pixels.assign(static_cast<std::size_t>(n) * n * 4, 0.f);
  result.atlas.color_space = ColorSpace::kSrgb;
  result.atlas.has_alpha = true;
  result.baked.assign(static_cast<std::size_t>(n) * n, 0);
  std::vector<float> base_premultiplied;
  AtlasPass pass;
  set_stack(pass, uv_mesh, layers, *prepared, *scene, normals, image_alpha);
  pass.frame.cell = ewa_cell(options.size, options.samples);
  pass.linear = linear;
  pass.overlaps = overlaps;
  pass.spt = static_cast<std::size_t>(options.samples);
  pass.size = n;
  pass.base = lo.base;
  pass.base_working = to_work(lo.base_color, linear);
  pass.base_vertex = lo.base == LayerBase::kMesh && !options.base_texture.data;
  if (lo.base == LayerBase::kMesh && options.base_texture.data) {
    if (linear) {
      base_premultiplied = premultiplied_linear(options.base_texture);
      pass.base_view = {options.base_texture.width, options.base_texture.height,
                        base_premultiplied.data(), ColorSpace::kLinear};
    } else {
      pass.base_view = options.base_texture;  // as stored, straight alpha
    }
  }
  pass.fill = fill;
  pass.fill_colors = fill_first ? &fill_colors : nullptr;
  pass.occluded_color = lo.occluded_color;
  pass.occluded_working = to_work(lo.occluded_color, linear);
  pass.atlas = result.atlas.pixels.data();
  pass.baked = result.baked.data();

  Expected<BandPass> swept = band_pass(bands, pass, layers.size(), n, progress, result);
  if (!swept) return swept.error();
  result.samples = result.texels * pass.spt;
  // Rasterising and sampling interleave per band: the pass's wall time is
  // split between the two in proportion to the thread time each took.
  const double pass_seconds = seconds_since(start);
  const double busy = static_cast<double>(swept->raster_ns + swept->sample_ns);
  const double raster_share = busy > 0 ? swept->raster_ns / busy : 0;
  result.seconds_raster = raster_seconds + pass_seconds * raster_share;
  result.seconds_layers = prepare_total + pass_seconds * (1 - raster_share);

  // The deferred texels (each independent: their order does not matter).
  if (!swept->deferred.empty()) {
    start = Clock::now();
    Expected<std::vector<Rgba>> colors =
        atlas_fill_colors(uv_mesh, layers, options, scene->scene(), linear, own_seconds, result);
    if (!colors) return colors.error();
    finish_deferred(pass, swept->deferred, *colors);
    result.seconds_fill += seconds_since(start);
  }
  scene->own.reset();
  result.layers = layer_stats(layers, swept->counts, result.samples, own_seconds,
                              result.seconds_layers - prepare_total);

  start = Clock::now();
  result.padded = pad_atlas(result.atlas.pixels, result.baked, n, options.padding);
  result.seconds_pad = seconds_since(start);
  for (const LayerInput& in : layers) {
    if (Status s = check_texels_read(in.texture); !s) return s.error();
  }
  return result;
}

}  // namespace texbake
