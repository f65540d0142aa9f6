#include "bake/engine/photo_atlas.h"

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <optional>

#include "bake/atlas/atlas_raster.h"
#include "bake/atlas/atlas_samples.h"
#include "bake/engine/layers_bake.h"
#include "bake/photo/photo_view.h"
#include "bake/photo/segments.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "mapping/sample.h"
#include "mesh_io/vertex_normals.h"

namespace texbake {

namespace {

using photo_detail::blend_weight;
using photo_detail::CameraLook;

// Samples per parallel block: a multiple of 64, so that each word of a
// camera's bitset is written by one block only.
constexpr std::size_t kBlock = 4096;
static_assert(kBlock % 64 == 0);

// Sample s of the raster on the surface.
SurfaceSample surface_point(const MeshData& mesh, const std::vector<Float3>& normals,
                            const AtlasRaster& r, std::size_t s) {
  return surface_sample(mesh, normals, r.sample_triangle[s], r.sample_b1[s], r.sample_b2[s]);
}

// The camera's cull of a sample (see the file comment): the vertex bake's,
// and the face turned towards the camera.
bool candidate(const CameraLook& look, const SurfaceSample& sp, CameraProjection& proj) {
  // The face test first: the cheapest (the same conjunction).
  return dot(sp.face, look.centre() - sp.p) > 0 && look.candidate(sp.p, sp.n, proj);
}

// Per triangle of mesh, 0 where no point of it can pass candidate()'s face
// test for a camera at `centre`: dot(face, C - p) is the same for every
// point p of the triangle's plane (face . (p - a) = 0), so a triangle with
// dot(face, C - a) <= -tol is culled whole before any of its samples is
// placed on the surface (half of a closed mesh, per camera). tol is some
// 1e7 times the rounding error of the per-sample test (which still runs on
// the others), so no sample that test would keep is culled: the same result.
std::vector<uint8_t> facing_triangles(const MeshData& mesh, Vec3 centre) {
  std::vector<uint8_t> facing(mesh.triangles.size());
  parallel_for_chunks(facing.size(), 1 << 14, [&](std::size_t begin, std::size_t end) {
    const auto vec = [](Float3 f) { return Vec3{f.x, f.y, f.z}; };
    for (std::size_t t = begin; t < end; ++t) {
      const auto& tri = mesh.triangles[t];
      const Vec3 a = vec(mesh.positions[tri[0]]), b = vec(mesh.positions[tri[1]]),
                 c = vec(mesh.positions[tri[2]]);
      const Vec3 face = cross(b - a, c - a);
      const double tol = 1e-9 * length(face) *
                         (length(centre - a) + length(a) + length(b) + length(c) + length(centre));
      facing[t] = dot(face, centre - a) > -tol;
    }
  });
  return facing;
}

// Calls fn(s) for the samples s in [begin, end) whose bit is set.
template <class Fn>
void for_each_seen(const std::vector<uint64_t>& bits, std::size_t begin, std::size_t end, Fn fn) {
  for (std::size_t word = begin >> 6; word < (end + 63) >> 6; ++word) {
    uint64_t b = bits[word];
    while (b) {
      const std::size_t s = (word << 6) + static_cast<std::size_t>(std::countr_zero(b));
      b &= b - 1;
      if (s >= begin && s < end) fn(s);
    }
  }
}

// A masked photo's mask (its alpha as loaded), kept from stage 1 for stages
// 3 and 4 at one byte a pixel: only when every alpha value is one an 8-bit
// file decodes to (b * (1 / 255) for every pixel, or b / 255 for every
// pixel), so that it is given back exactly. Otherwise not kept, and those
// stages read the photo again.
struct KeptMask {
  int width = 0, height = 0;
  bool divided = false;  // b / 255 (else b * (1 / 255))
  std::vector<uint8_t> alpha;
};

// An 8-bit alpha as the file's decoding gave it: b / 255 when `divided`,
// else b * (1 / 255) (the two differ in the last bit for some bytes).
float alpha_of_byte(uint8_t b, bool divided) {
  return divided ? static_cast<float>(b) / 255.0f : static_cast<float>(b) * (1.0f / 255.0f);
}

std::optional<KeptMask> keep_mask(const PhotoImage& image) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  KeptMask kept{image.width, image.height, false, std::vector<uint8_t>(n)};
  const auto byte_of = [](float a) {
    return a >= 0 && a <= 1 ? static_cast<uint8_t>(a * 255.0f + 0.5f) : uint8_t{0};
  };
  for (const bool divided : {false, true}) {
    std::vector<uint8_t> ok(block_count(n, 1 << 16), 1);
    parallel_for_blocks(n, 1 << 16, [&](std::size_t block, std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        const float a = image.pixels[4 * i + 3];
        kept.alpha[i] = byte_of(a);
        if (alpha_of_byte(kept.alpha[i], divided) != a) ok[block] = 0;
      }
    });
    if (std::all_of(ok.begin(), ok.end(), [](uint8_t v) { return v != 0; })) {
      kept.divided = divided;
      return kept;
    }
  }
  return std::nullopt;
}

// The kept mask as an image whose alpha is the photo's (R, G, B 0: only
// alpha is sampled, and bilinear interpolation treats channels apart).
PhotoImage mask_image(const KeptMask& kept) {
  PhotoImage image;
  image.width = kept.width;
  image.height = kept.height;
  image.color_space = ColorSpace::kLinear;
  const std::size_t n = kept.alpha.size();
  image.pixels.resize(4 * n);
  parallel_for_chunks(n, 1 << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      float* px = &image.pixels[4 * i];
      px[0] = px[1] = px[2] = 0;
      px[3] = alpha_of_byte(kept.alpha[i], kept.divided);
    }
  });
  return image;
}

// A masked photo read again for its mask (stages 3 and 4), or none for an
// unmasked one (whose mask is 1 everywhere). Errors: load_photo's (an
// unreadable photo: stage 1 read it, so now an error).
Expected<std::optional<PhotoImage>> read_for_mask(const Photo& photo, const PhotoReader& read,
                                                  bool masked,
                                                  const std::optional<KeptMask>& kept) {
  if (!masked) return std::optional<PhotoImage>();
  if (kept) return std::optional<PhotoImage>(mask_image(*kept));
  PhotoCameraStats scratch_stats;
  std::vector<std::string> scratch_warnings;  // the vertex bake gave them
  bool unreadable = false;
  Expected<PhotoImage> image =
      photo_detail::load_photo(photo, read, scratch_stats, scratch_warnings, unreadable);
  if (!image) {
    return unreadable ? photo_detail::unreadable_photo_error(photo, image.error()) : image.error();
  }
  return std::optional<PhotoImage>(std::move(image).value());
}

ImageView view_of(const std::optional<PhotoImage>& image) {
  return image ? ImageView{image->width, image->height, image->pixels.data()} : ImageView{};
}

// What the passes of one blend share.
struct BlendContext {
  const MeshData& mesh;
  const std::vector<Float3>& normals;
  const AtlasRaster& raster;
  const std::vector<Photo>& photos;
  const PhotoBakeOptions& options;
  const PhotoReader& read;
  const std::vector<std::optional<KeptMask>>& kept_masks;  // per photo
  const std::vector<PhotoCameraStats>& cameras;            // per photo (masked)
};

// The per-sample state of stages 3 to 5.
struct SampleWeights {
  std::vector<float> q_max, total;
  std::vector<uint32_t> best;                  // kBest: the best camera
  std::vector<std::vector<uint64_t>> seen_by;  // per camera, one bit per sample
};

// Stage 3, per camera: the cull, the segments to the camera traced, q_max
// and (kBest, kMean) the weight sums; `state` kInView for the culled-in
// samples; the cameras' in_view and visible.
Status geometry_pass(const BlendContext& ctx, const EmbreeScene& scene, SampleWeights& w,
                     std::vector<uint8_t>& state, std::vector<PhotoCameraStats>& cameras) {
  const AtlasRaster& raster = ctx.raster;
  const PhotoBakeOptions& po = ctx.options;
  const std::size_t ns = raster.sample_count();
  const std::size_t blocks = block_count(ns, kBlock);
  const double offset = visibility_offset(scene);
  for (std::size_t c = 0; c < ctx.photos.size(); ++c) {
    const CameraLook look(ctx.photos[c].camera, po.max_view_angle_deg);
    const bool masked = ctx.cameras[c].masked;
    Expected<std::optional<PhotoImage>> mask_image =
        read_for_mask(ctx.photos[c], ctx.read, masked, ctx.kept_masks[c]);
    if (!mask_image) return mask_image.error();
    const ImageView mask_view = view_of(*mask_image);
    std::vector<uint64_t>& bits = w.seen_by[c];
    bits.assign((ns + 63) / 64, 0);
    std::vector<std::size_t> in_view(blocks, 0), visible(blocks, 0);
    const std::vector<uint8_t> facing = facing_triangles(ctx.mesh, look.centre());
    parallel_for_blocks(ns, kBlock, [&](std::size_t block, std::size_t begin, std::size_t end) {
      std::vector<uint32_t> candidates;
      std::vector<Vec3> points;
      std::vector<SurfaceSample> surface;
      std::vector<CameraProjection> projections;
      std::vector<float> mask;  // masked photos: the mask value per candidate
      SegmentScratch scratch;
      std::vector<uint8_t> occluded;
      for (std::size_t s = begin; s < end; ++s) {
        if (!facing[raster.sample_triangle[s]]) continue;  // candidate() would say no
        const SurfaceSample sp = surface_point(ctx.mesh, ctx.normals, raster, s);
        CameraProjection proj;
        if (!candidate(look, sp, proj)) continue;
        const float m = photo_detail::mask_at(mask_view, masked, proj.uv);
        if (!(m > 0)) continue;  // masked out: as if outside the photo
        state[s] = PhotoPoints::kInView;
        candidates.push_back(static_cast<uint32_t>(s));
        points.push_back(sp.p);
        surface.push_back(sp);
        projections.push_back(proj);
        mask.push_back(m);
      }
      const std::size_t m = candidates.size();
      occluded.assign(m, 0);
      occluded_segments(scene, offset, points, look.centre(), scratch, occluded.data());
      std::size_t seen = 0;
      for (std::size_t i = 0; i < m; ++i) {
        if (occluded[i]) continue;
        ++seen;
        const std::size_t s = candidates[i];
        bits[s >> 6] |= uint64_t{1} << (s & 63);
        const float q = look.quality(surface[i].p, surface[i].n, projections[i]);
        if (q > w.q_max[s]) {
          w.q_max[s] = q;
          if (!w.best.empty()) {
            w.best[s] = static_cast<uint32_t>(c);
            w.total[s] = mask[i];  // kBest: the weight sum is the best view's mask
          }
        }
        if (po.blend == PhotoBlend::kMean) w.total[s] += mask[i];
      }
      in_view[block] = m;
      visible[block] = seen;
    });
    for (std::size_t b = 0; b < blocks; ++b) {
      cameras[c].in_view += in_view[b];
      cameras[c].visible += visible[b];
    }
  }
  return ok_status();
}

// Stage 4 (kSoft): the weight sums, a masked photo read again.
Status weight_pass(const BlendContext& ctx, SampleWeights& w) {
  const std::size_t ns = ctx.raster.sample_count();
  for (std::size_t c = 0; c < ctx.photos.size(); ++c) {
    const Photo& photo = ctx.photos[c];
    const CameraLook look(photo.camera, ctx.options.max_view_angle_deg);
    const bool masked = ctx.cameras[c].masked;
    Expected<std::optional<PhotoImage>> mask_image =
        read_for_mask(photo, ctx.read, masked, ctx.kept_masks[c]);
    if (!mask_image) return mask_image.error();
    const ImageView mask_view = view_of(*mask_image);
    parallel_for_blocks(ns, kBlock, [&](std::size_t, std::size_t begin, std::size_t end) {
      for_each_seen(w.seen_by[c], begin, end, [&](std::size_t s) {
        const SurfaceSample sp = surface_point(ctx.mesh, ctx.normals, ctx.raster, s);
        const CameraProjection proj = photo.camera.project(sp.p);
        w.total[s] += static_cast<float>(
            blend_weight(PhotoBlend::kSoft, look.quality(sp.p, sp.n, proj), w.q_max[s], false) *
            photo_detail::mask_at(mask_view, masked, proj.uv));
      });
    });
  }
  return ok_status();
}

// Stage 5, one photo at a time (the next one decoded meanwhile): the
// colours (and with `cosine` not empty the cosines) of the samples; the
// cameras' weight shares (unnormalised).
Status colour_pass(const BlendContext& ctx, SampleWeights& w, PhotoPoints& points,
                   std::vector<PhotoCameraStats>& cameras) {
  const PhotoBakeOptions& po = ctx.options;
  const std::size_t ns = ctx.raster.sample_count();
  const std::size_t blocks = block_count(ns, kBlock);
  const PhotoReader read_in_order = photo_detail::prefetching_reader(ctx.read, ctx.photos);
  std::vector<std::array<float, 3>>& rgb = points.rgb;
  std::vector<float>& cosine = points.cosine;
  for (std::size_t c = 0; c < ctx.photos.size(); ++c) {
    const Photo& photo = ctx.photos[c];
    PhotoCameraStats scratch_stats;
    std::vector<std::string> scratch_warnings;  // the vertex bake gave them
    bool unreadable = false;                    // read by stage 1 already: now an error
    Expected<PhotoImage> image =
        photo_detail::load_photo(photo, read_in_order, scratch_stats, scratch_warnings, unreadable);
    if (!image) {
      return unreadable ? photo_detail::unreadable_photo_error(photo, image.error())
                        : image.error();
    }
    const ImageView view{image->width, image->height, image->pixels.data()};
    const bool masked = cameras[c].masked;
    const CameraLook look(photo.camera, po.max_view_angle_deg);
    const std::vector<uint64_t>& bits = w.seen_by[c];
    const std::array<double, 3> gain = cameras[c].gain;
    std::vector<double> share(blocks, 0.0);
    parallel_for_blocks(ns, kBlock, [&](std::size_t block, std::size_t begin, std::size_t end) {
      double block_share = 0;
      for_each_seen(bits, begin, end, [&](std::size_t s) {
        const SurfaceSample sp = surface_point(ctx.mesh, ctx.normals, ctx.raster, s);
        const CameraProjection proj = photo.camera.project(sp.p);
        const bool is_best = !w.best.empty() && w.best[s] == c;
        // x: the colour and the mask value m (photo_view.h's sample_masked).
        const Rgba x = photo_detail::sample_masked(view, masked, proj.uv);
        const double weight =
            blend_weight(po.blend, look.quality(sp.p, sp.n, proj), w.q_max[s], is_best) * x[3] /
            w.total[s];
        if (!(weight > 0)) return;
        for (int ch = 0; ch < 3; ++ch) {
          rgb[s][ch] += static_cast<float>(weight * gain[ch] * x[ch]);
        }
        if (!cosine.empty()) {
          cosine[s] += static_cast<float>(weight * dot(sp.n, normalize(look.centre() - sp.p)));
        }
        block_share += weight;
      });
      share[block] = block_share;
    });
    double sum = 0;
    for (double v : share) sum += v;
    cameras[c].weight_share = sum;
    w.seen_by[c] = {};  // no pass needs this camera's bits any more
  }
  return ok_status();
}

// The photos stage 1 read (all_photos less `skipped`, in order).
std::vector<Photo> readable_photos(const std::vector<Photo>& all_photos,
                                   const std::vector<SkippedPhoto>& skipped) {
  std::vector<Photo> readable;
  for (std::size_t p = 0, k = 0; p < all_photos.size(); ++p) {
    if (k < skipped.size() && skipped[k].path == all_photos[p].path &&
        skipped[k].name == all_photos[p].name) {
      ++k;
      continue;
    }
    readable.push_back(all_photos[p]);
  }
  return readable;
}

// The samples' states (kSeen where some photo sees them; without one,
// cosine 1), the count seen, the cameras' weight shares normalised by it,
// and where each texel's samples start.
void finish_blend(const AtlasRaster& raster, int size, const SampleWeights& weights,
                  PhotoAtlasBlend& result) {
  PhotoPoints& points = result.points.samples;
  for (std::size_t s = 0; s < raster.sample_count(); ++s) {
    if (weights.q_max[s] > 0) {
      points.state[s] = PhotoPoints::kSeen;
      ++result.seen;
    } else if (!points.cosine.empty()) {
      points.cosine[s] = 1;
    }
  }
  for (PhotoCameraStats& s : result.cameras) {
    s.weight_share = result.seen ? s.weight_share / static_cast<double>(result.seen) : 0;
  }
  const auto spt = static_cast<std::size_t>(raster.samples_per_texel);
  result.points.texel_first.assign(static_cast<std::size_t>(size) * size,
                                   PhotoLayerPoints::kNoTexel);
  for (std::size_t k = 0; k < raster.texels.size(); ++k) {
    result.points.texel_first[raster.texels[k]] = static_cast<uint32_t>(k * spt);
  }
}

}  // namespace

Expected<PhotoAtlasBlend> blend_atlas_photos(const MeshData& uv_mesh,
                                             const std::vector<Photo>& all_photos,
                                             const PhotoAtlasBakeOptions& options,
                                             const PhotoReader& reader) {
  if (all_photos.empty()) return make_error(ErrorCode::kInvalidArgument, "no photos to bake from");
  const PhotoReader read = reader ? reader : PhotoReader(photo_detail::read_photo_file);
  const PhotoBakeOptions& po = options.photo;
  PhotoAtlasBlend result;

  // 2 first (cheap, and its errors are the layout's): rasterise.
  auto t0 = Clock::now();
  Expected<AtlasRaster> raster_or =
      rasterize_atlas(uv_mesh, AtlasRasterOptions{options.size, options.samples, false});
  if (!raster_or) return raster_or.error();
  const AtlasRaster& raster = *raster_or;
  const std::size_t ns = raster.sample_count();
  result.texels = raster.texels.size();
  result.samples = ns;
  result.border_samples = raster.border_samples;
  result.seconds_rasterize = seconds_since(t0);

  // 1. The vertex blend: the gains, and the per-vertex blend of the fill.
  t0 = Clock::now();
  // Its photos' masks kept for stages 3 and 4 (indexed as result.cameras).
  std::vector<std::optional<KeptMask>> kept_masks;
  PhotoBakeOptions vertex_options = po;
  vertex_options.on_photo = [&kept_masks](std::size_t c, const PhotoImage& image, bool masked) {
    if (kept_masks.size() <= c) kept_masks.resize(c + 1);
    if (masked) kept_masks[c] = keep_mask(image);
  };
  Expected<PhotoBakeResult> vertex = blend_vertex_photos(uv_mesh, all_photos, vertex_options, read);
  if (!vertex) return vertex.error();
  // The photos stage 1 could read (it left the others out, with warnings).
  result.skipped = std::move(vertex->skipped);
  std::vector<Photo> readable;
  if (!result.skipped.empty()) readable = readable_photos(all_photos, result.skipped);
  const std::vector<Photo>& photos = result.skipped.empty() ? all_photos : readable;
  kept_masks.resize(photos.size());
  result.cameras = std::move(vertex->cameras);
  result.consistency = vertex->consistency;
  result.warnings = std::move(vertex->warnings);
  result.vertices_seen = vertex->seen;
  result.points.vertices = std::move(vertex->points);
  vertex = PhotoBakeResult{};
  for (PhotoCameraStats& s : result.cameras) s.in_view = s.visible = 0, s.weight_share = 0;
  result.seconds_vertex = seconds_since(t0);

  t0 = Clock::now();
  std::optional<EmbreeScene> scene;
  {
    Expected<EmbreeScene> built = EmbreeScene::build(uv_mesh, BuildQuality::kLow);
    if (!built) return built.error();
    scene.emplace(std::move(*built));
  }
  const std::vector<Float3> normals = smooth_vertex_normals(uv_mesh);
  result.seconds_scene = seconds_since(t0);

  // 3. Geometry pass.
  t0 = Clock::now();
  const BlendContext ctx{uv_mesh, normals, raster, photos, po, read, kept_masks, result.cameras};
  SampleWeights weights;
  weights.q_max.assign(ns, 0.f);
  weights.total.assign(ns, 0.f);
  if (po.blend == PhotoBlend::kBest) weights.best.assign(ns, 0);
  weights.seen_by.resize(photos.size());
  PhotoPoints& points = result.points.samples;
  points.state.assign(ns, PhotoPoints::kNoView);
  if (Status s = geometry_pass(ctx, *scene, weights, points.state, result.cameras); !s) {
    return s.error();
  }
  scene.reset();  // the BVH is not needed any more
  result.seconds_geometry = seconds_since(t0);

  // 4. and 5.
  t0 = Clock::now();
  if (po.blend == PhotoBlend::kSoft) {
    if (Status s = weight_pass(ctx, weights); !s) return s.error();
  }
  points.rgb.assign(ns, {0.f, 0.f, 0.f});
  if (po.keep_points) points.cosine.assign(ns, 0.f);
  if (Status s = colour_pass(ctx, weights, points, result.cameras); !s) return s.error();
  result.seconds_photos = seconds_since(t0);

  finish_blend(raster, options.size, weights, result);
  return result;
}

Expected<PhotoAtlasBakeResult> bake_atlas_from_photos(const MeshData& uv_mesh,
                                                      const std::vector<Photo>& photos,
                                                      const PhotoAtlasBakeOptions& options,
                                                      const PhotoReader& reader) {
  if (photos.empty()) return make_error(ErrorCode::kInvalidArgument, "no photos to bake from");
  if (Status s = check_padding(options.padding); !s) return s.error();
  PhotoAtlasBakeOptions blend_options = options;
  blend_options.photo.keep_points = false;  // no angle fade: no cosines
  Expected<PhotoAtlasBlend> blend = blend_atlas_photos(uv_mesh, photos, blend_options, reader);
  if (!blend) return blend.error();

  // 6. and 7.: the blend as one "cameras" layer under the single
  // projection's rule, through the engine's atlas target.
  LayerInput layer;
  layer.name = "photos";
  layer.photos = &blend->points;
  const LayersAtlasOptions atlas =
      single_projection_atlas(options.size, options.samples, options.padding,
                              options.photo.occluded, options.photo.occluded_color);
  Expected<LayersAtlasResult> baked = bake_atlas_layers(uv_mesh, {layer}, atlas);
  if (!baked) return baked.error();

  PhotoAtlasBakeResult result;
  result.atlas = std::move(baked->atlas);
  result.atlas.has_alpha = false;  // alpha 1, or the --occluded colour's
  result.baked = std::move(baked->baked);
  result.cameras = std::move(blend->cameras);
  result.consistency = blend->consistency;
  result.texels = blend->texels;
  result.samples = blend->samples;
  result.border_samples = blend->border_samples;
  result.seen = blend->seen;
  result.filled = options.photo.occluded == OccludedMode::kColor ? 0 : blend->samples - blend->seen;
  result.padded = baked->padded;
  result.vertices_seen = blend->vertices_seen;
  result.vertices_filled = baked->vertices_filled;
  result.vertices_unfilled = baked->vertices_unfilled;
  result.warnings = std::move(blend->warnings);
  result.skipped = std::move(blend->skipped);
  result.seconds_vertex = blend->seconds_vertex;
  result.seconds_rasterize = blend->seconds_rasterize + baked->seconds_raster;
  result.seconds_scene = blend->seconds_scene + baked->seconds_scene;
  result.seconds_geometry = blend->seconds_geometry;
  result.seconds_photos = blend->seconds_photos;
  result.seconds_fill = baked->seconds_fill;
  result.seconds_texels = baked->seconds_layers + baked->seconds_pad;
  return result;
}

}  // namespace texbake
