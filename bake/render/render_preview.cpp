#include "bake/render/render_preview.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <numbers>
#include <string>

#include "bake/shade/sample_pattern.h"
#include "bake/shade/shade.h"
#include "bake/util/parallel.h"
#include "mapping/sample.h"
#include "mesh_io/vertex_normals.h"

namespace texbake {
namespace {

constexpr int kTile = 16;  // tile edge in pixels: 256 pixels per Embree batch and sample
constexpr double kDegToRad = std::numbers::pi / 180.0;
// Shadow-ray origins move off the surface by this fraction of the scene's
// bounding-box diagonal (SPEC section 3: offsets relative to the diagonal,
// never an absolute epsilon).
constexpr double kShadowOffset = 1e-5;

Vec3 to_vec(Float3 f) {
  return {f.x, f.y, f.z};
}

// Rodrigues rotation taking +Z onto the unit vector `up` by the smallest
// angle; for up = -Z (no unique axis) a half turn about +X.
Vec3 rotate_z_to(Vec3 up, Vec3 v) {
  const Vec3 z{0, 0, 1};
  const Vec3 k = cross(z, up);
  const double s = length(k);
  const double c = dot(z, up);
  if (s < 1e-12) return c > 0 ? v : Vec3{v.x, -v.y, -v.z};
  const Vec3 axis = k / s;
  return v * c + cross(axis, v) * s + axis * (dot(axis, v) * (1 - c));
}

// 24-bit uniform in [0, 1).
double unit_from_bits(uint64_t bits) {
  return static_cast<double>(bits >> 40) * 0x1p-24;
}

// ---- Colour source functors: one concrete type per tile, no virtual call
// per sample. Each returns the albedo at a hit (triangle, barycentrics, point).

struct GreyColor {
  Rgba operator()(const Hit&, Vec3) const { return {kGreyAlbedo, kGreyAlbedo, kGreyAlbedo, 1}; }
};

struct VertexColor {
  const MeshData* mesh;
  Rgba operator()(const Hit& hit, Vec3) const {
    const auto& tri = mesh->triangles[hit.triangle];
    const auto& c0 = mesh->vertex_colors[tri[0]];
    const auto& c1 = mesh->vertex_colors[tri[1]];
    const auto& c2 = mesh->vertex_colors[tri[2]];
    const float b0 = 1.0f - hit.b1 - hit.b2;
    Rgba out;
    for (int c = 0; c < 4; ++c) out[c] = b0 * c0[c] + hit.b1 * c1[c] + hit.b2 * c2[c];
    return out;
  }
};

struct AtlasColor {
  const MeshData* mesh;
  ImageView texture;
  Rgba operator()(const Hit& hit, Vec3) const {
    const auto& corners = mesh->triangle_corners[hit.triangle];
    const Float2 t0 = mesh->uvs[mesh->corner_uv[corners[0]]];
    const Float2 t1 = mesh->uvs[mesh->corner_uv[corners[1]]];
    const Float2 t2 = mesh->uvs[mesh->corner_uv[corners[2]]];
    const double b1 = hit.b1, b2 = hit.b2, b0 = 1.0 - b1 - b2;
    const UV uv{b0 * t0.u + b1 * t1.u + b2 * t2.u, b0 * t0.v + b1 * t1.v + b2 * t2.v};
    const Rgba c = sample_bilinear(texture, uv, WrapMode::kClamp, WrapMode::kClamp);
    // A linear texture (an EXR atlas) is interpolated in linear light, then
    // sRGB-encoded like every other albedo.
    return texture.color_space == ColorSpace::kLinear ? linear_to_srgb(c) : c;
  }
};

// The bake's shading rule (bake/shade/shade.h) at the hit point, in the
// texture's stored encoding; points without a mapping are grey.
template <class ConcreteProxy>
struct ProjectedColor {
  const ConcreteProxy* proxy;
  const ShadeRule* rule;
  Rgba operator()(const Hit&, Vec3 p) const {
    const Shaded s = rule->project(proxy->inverse_map(p));
    if (s.kind == Shade::kNone) return GreyColor{}({}, p);
    return rule->stored(s.color);
  }
};

// Per-thread scratch for one tile, reused across tiles (no allocation per
// sample; the vectors grow once per thread).
struct TileScratch {
  RayArrays primary, shadow;
  std::vector<Hit> hits;
  std::vector<uint8_t> shadow_blocked;  // per shadow ray
  std::vector<uint32_t> shadow_sample;  // sample index of each shadow ray
  std::vector<uint8_t> in_shadow;       // per sample
  std::vector<Vec3> normal, point;      // per sample: shading normal, hit point
  std::vector<Rgba> albedo;

  void resize(std::size_t n) {
    primary.resize(n);
    shadow.resize(n);
    hits.resize(n);
    shadow_blocked.resize(n);
    shadow_sample.resize(n);
    in_shadow.resize(n);
    normal.resize(n);
    point.resize(n);
    albedo.resize(n);
  }
};

struct Light {
  Vec3 direction;  // unit, world space, towards the light
  double diffuse, specular;
};

// Everything a tile needs, fixed for the whole render.
struct RenderContext {
  const MeshData* mesh;
  const EmbreeScene* scene;
  const RenderOptions* options;
  const std::vector<Float3>* vertex_normals;  // empty: use corner normals or geometric
  double shadow_offset;
  int sheet_width;
};

struct TileJob {
  const Camera* camera;
  int view;
  int x0, y0, x1, y1;    // pixel range in the view
  int sheet_x, sheet_y;  // the view's cell origin in the sheet
};

// The shading normal at a hit: interpolated corner (OBJ vn) or vertex
// normals when smooth, else (and for degenerate normal data) the geometric one.
Vec3 shading_normal(const RenderContext& ctx, const Hit& hit, Vec3 geometric) {
  if (!ctx.options->smooth_normals) return geometric;
  const MeshData& mesh = *ctx.mesh;
  Float3 n[3];
  if (!mesh.corner_normal.empty()) {
    const auto& corners = mesh.triangle_corners[hit.triangle];
    for (int k = 0; k < 3; ++k) n[k] = mesh.normals[mesh.corner_normal[corners[k]]];
  } else if (!ctx.vertex_normals->empty()) {
    const auto& tri = mesh.triangles[hit.triangle];
    for (int k = 0; k < 3; ++k) n[k] = (*ctx.vertex_normals)[tri[k]];
  } else {
    return geometric;
  }
  const double b1 = hit.b1, b2 = hit.b2, b0 = 1.0 - b1 - b2;
  const Vec3 s = to_vec(n[0]) * b0 + to_vec(n[1]) * b1 + to_vec(n[2]) * b2;
  const double len = length(s);
  if (!(len > 1e-12)) return geometric;
  const Vec3 unit = s / len;
  // Keep the shading normal on the viewer's side of the surface (two-sided).
  return dot(unit, geometric) < 0 ? -unit : unit;
}

template <class ColorFn>
void render_tile(const RenderContext& ctx, const TileJob& job, const ColorFn& color,
                 const std::array<Light, 2>& lights, TileScratch& s, float* sheet,
                 std::atomic<uint64_t>& shadow_count) {
  const RenderOptions& opt = *ctx.options;
  const int spp = opt.samples_per_pixel;
  const int strata = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(spp))));
  const int tw = job.x1 - job.x0, th = job.y1 - job.y0;
  const std::size_t n = static_cast<std::size_t>(tw) * th * spp;
  s.resize(n);

  // 1. Primary rays, sample-major within each pixel.
  std::size_t i = 0;
  for (int y = job.y0; y < job.y1; ++y) {
    for (int x = job.x0; x < job.x1; ++x) {
      const uint64_t pixel_seed =
          (static_cast<uint64_t>(job.view) << 48) ^ (static_cast<uint64_t>(y) << 24) ^ x;
      for (int k = 0; k < spp; ++k, ++i) {
        double jx = 0.5, jy = 0.5;
        if (spp > 1) {
          const int cell = k % (strata * strata);
          const uint64_t h = hash_pair(pixel_seed, static_cast<uint64_t>(k));
          jx = ((cell % strata) + unit_from_bits(h)) / strata;
          jy = ((cell / strata) + unit_from_bits(h << 24)) / strata;
        }
        const Ray r = job.camera->ray(x + jx, y + jy);
        s.primary.set(i, r.origin, r.direction);
      }
    }
  }
  ctx.scene->intersect(s.primary.batch(n), s.hits.data());

  // 2. Surface point, normals and albedo of every hit; shadow rays.
  const MeshData& mesh = *ctx.mesh;
  std::size_t shadows = 0;
  for (i = 0; i < n; ++i) {
    const Hit& hit = s.hits[i];
    if (hit.triangle == kNoHit) continue;
    const auto& tri = mesh.triangles[hit.triangle];
    // The point from barycentrics, in double: more accurate than org + t dir
    // for the inverse mapping.
    const double b1 = hit.b1, b2 = hit.b2, b0 = 1.0 - b1 - b2;
    const Vec3 p = to_vec(mesh.positions[tri[0]]) * b0 + to_vec(mesh.positions[tri[1]]) * b1 +
                   to_vec(mesh.positions[tri[2]]) * b2;
    const Vec3 dir{s.primary.dir_x[i], s.primary.dir_y[i], s.primary.dir_z[i]};
    Vec3 ng = normalize(to_vec(hit.normal));
    if (dot(ng, dir) > 0) ng = -ng;  // two-sided: face the viewer
    s.point[i] = p;
    s.normal[i] = shading_normal(ctx, hit, ng);
    s.albedo[i] = color(hit, p);
    if (opt.shadows && dot(s.normal[i], lights[0].direction) > 0) {
      // Start on the light's side of the triangle so the ray cannot hit it.
      const Vec3 side = dot(ng, lights[0].direction) >= 0 ? ng : -ng;
      const Vec3 o = p + side * ctx.shadow_offset;
      s.shadow.set(shadows, o, lights[0].direction);
      s.shadow_sample[shadows] = static_cast<uint32_t>(i);
      ++shadows;
    }
  }
  std::fill(s.in_shadow.begin(), s.in_shadow.begin() + static_cast<std::ptrdiff_t>(n), 0);
  if (shadows > 0) {
    ctx.scene->occluded(s.shadow.batch(shadows), s.shadow_blocked.data());
    for (std::size_t k = 0; k < shadows; ++k) s.in_shadow[s.shadow_sample[k]] = s.shadow_blocked[k];
    shadow_count.fetch_add(shadows, std::memory_order_relaxed);
  }

  // 3. Phong shading and the pixel means.
  const Vec3 eye = job.camera->position;
  i = 0;
  for (int y = job.y0; y < job.y1; ++y) {
    for (int x = job.x0; x < job.x1; ++x) {
      double sum[3] = {0, 0, 0};
      int covered = 0;
      for (int k = 0; k < spp; ++k, ++i) {
        if (s.hits[i].triangle == kNoHit) continue;
        ++covered;
        const Vec3 nrm = s.normal[i];
        const Vec3 view = normalize(eye - s.point[i]);
        double diffuse = opt.phong.ambient, specular = 0;
        for (int l = 0; l < 2; ++l) {
          if (l == 0 && s.in_shadow[i]) continue;
          const double nl = dot(nrm, lights[l].direction);
          if (nl <= 0) continue;
          diffuse += lights[l].diffuse * nl;
          if (lights[l].specular > 0) {
            const Vec3 refl = nrm * (2 * nl) - lights[l].direction;
            const double rv = dot(refl, view);
            if (rv > 0) specular += lights[l].specular * std::pow(rv, opt.phong.shininess);
          }
        }
        // The albedo's alpha (an atlas or vertex colours of layers over
        // base "none") composites the shaded colour over the background,
        // as uncovered pixels show it: a transparent texel renders as the
        // background, an opaque one (alpha 1, every other source) as
        // shaded.
        const float alpha = s.albedo[i][3];
        const double a = std::isnan(alpha) ? 1.0 : std::clamp(static_cast<double>(alpha), 0.0, 1.0);
        for (int c = 0; c < 3; ++c) {
          const double shaded = std::clamp(s.albedo[i][c] * diffuse + specular, 0.0, 1.0);
          sum[c] += a == 1 ? shaded : a * shaded + (1 - a) * opt.background[c];
        }
      }
      float* out =
          sheet +
          (static_cast<std::size_t>(job.sheet_y + y) * ctx.sheet_width + job.sheet_x + x) * 4;
      // Straight (unassociated) alpha, as PNG stores it: RGB is the mean of
      // the covering samples, alpha the covered fraction.
      if (covered > 0) {
        for (int c = 0; c < 3; ++c) out[c] = static_cast<float>(sum[c] / covered);
        out[3] = static_cast<float>(covered) / spp;
      } else {
        for (int c = 0; c < 3; ++c) out[c] = opt.background[c];
        out[3] = 0;
      }
    }
  }
}

Status validate_options(const RenderOptions& o) {
  auto bad = [](std::string m) { return Status(make_error(ErrorCode::kInvalidArgument, m)); };
  if (o.width <= 0 || o.height <= 0) return bad("render size must be positive");
  if (static_cast<double>(o.width) * o.height * std::max(o.views, 1) > 1e9) {
    return bad("render size is too large (more than 1e9 pixels)");
  }
  if (o.views < 1) return bad("--views must be at least 1");
  if (o.samples_per_pixel < 1) return bad("--samples must be at least 1");
  if (o.samples_per_pixel > 4096) return bad("--samples must be at most 4096");
  if (!std::isfinite(o.azimuth_deg)) return bad("view azimuth is not finite");
  if (!(o.elevation_deg >= -90 && o.elevation_deg <= 90)) {
    return bad("view elevation must be in [-90, 90] degrees");
  }
  if (!is_finite(o.up) || length(o.up) == 0) return bad("up vector is zero or not finite");
  return ok_status();
}

}  // namespace

Ray Camera::ray(double x, double y) const {
  const double sx = (2.0 * x / width - 1.0) * tan_half_x;
  const double sy = (1.0 - 2.0 * y / height) * tan_half_y;
  return {position, normalize(forward + right * sx + up * sy)};
}

CameraProjector pinhole_of_view(const Camera& view) {
  const Vec3 down = -view.up;
  const std::array<double, 9> r = {view.right.x,   view.right.y,   view.right.z,
                                   down.x,         down.y,         down.z,
                                   view.forward.x, view.forward.y, view.forward.z};
  CameraPose pose;
  pose.r = r;
  pose.t = -Vec3{r[0] * view.position.x + r[1] * view.position.y + r[2] * view.position.z,
                 r[3] * view.position.x + r[4] * view.position.y + r[5] * view.position.z,
                 r[6] * view.position.x + r[7] * view.position.y + r[8] * view.position.z};
  const double fx = view.width / (2 * view.tan_half_x), fy = view.height / (2 * view.tan_half_y);
  // The frame is orthonormal by construction (make_camera): make() cannot fail.
  return CameraProjector::make({CameraModel::kPinhole,
                                view.width,
                                view.height,
                                {fx, fy, view.width / 2.0, view.height / 2.0},
                                pose})
      .value();
}

Expected<BoundingSphere> bounding_sphere(const MeshData& mesh) {
  if (mesh.triangles.empty()) {
    return make_error(ErrorCode::kInvalidArgument, "the mesh has no (non-degenerate) triangle");
  }
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const auto& tri : mesh.triangles) {
    for (uint32_t v : tri) {
      const Vec3 p = to_vec(mesh.positions[v]);
      lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
      hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
    }
  }
  BoundingSphere b{(lo + hi) * 0.5, 0};
  for (const auto& tri : mesh.triangles) {
    for (uint32_t v : tri)
      b.radius = std::max(b.radius, length(to_vec(mesh.positions[v]) - b.center));
  }
  return b;
}

Expected<Camera> make_camera(const BoundingSphere& bounds, const RenderOptions& options,
                             double azimuth_deg) {
  if (Status st = validate_options(options); !st) return st.error();
  const Vec3 up_w = normalize(options.up);
  const Vec3 east = rotate_z_to(up_w, {1, 0, 0});
  const Vec3 north = rotate_z_to(up_w, {0, 1, 0});
  const double az = azimuth_deg * kDegToRad, el = options.elevation_deg * kDegToRad;
  const Vec3 horizontal = east * std::sin(az) - north * std::cos(az);
  const Vec3 out = horizontal * std::cos(el) + up_w * std::sin(el);

  Camera cam;
  cam.width = options.width;
  cam.height = options.height;
  const double tan_half = std::tan(0.5 * kFieldOfViewDeg * kDegToRad);
  const double aspect = static_cast<double>(options.width) / options.height;
  cam.tan_half_x = aspect >= 1 ? tan_half * aspect : tan_half;
  cam.tan_half_y = aspect >= 1 ? tan_half : tan_half / aspect;
  // A sphere of radius R at distance D subtends a half-angle asin(R / D).
  const double radius = std::max(bounds.radius, 1e-30) * kFrameMargin;
  const double distance = radius / std::sin(0.5 * kFieldOfViewDeg * kDegToRad);
  cam.position = bounds.center + out * distance;
  cam.forward = -out;
  cam.right = east * std::cos(az) + north * std::sin(az);  // d(out)/d(az), normalised
  cam.up = cross(cam.right, cam.forward);                  // = d(out)/d(el), the image's up
  return cam;
}

Status validate_color_source(const MeshData& mesh, const ColorSource& source) {
  auto bad = [](std::string m) { return Status(make_error(ErrorCode::kInvalidArgument, m)); };
  if (std::holds_alternative<VertexColorSource>(source)) {
    if (mesh.vertex_colors.size() != mesh.vertex_count())
      return bad("the mesh has no vertex colours");
  } else if (const auto* atlas = std::get_if<AtlasSource>(&source)) {
    if (!mesh.has_uvs() || mesh.triangle_corners.size() != mesh.triangles.size()) {
      return bad("the mesh has no texture coordinates for its atlas");
    }
    if (atlas->texture.width < 1 || atlas->texture.height < 1 || !atlas->texture.data) {
      return bad("the atlas texture has no pixels");
    }
  } else if (const auto* proj = std::get_if<ProjectionSource>(&source)) {
    if (proj->texture.width < 1 || proj->texture.height < 1 || !proj->texture.has_texels()) {
      return bad("the projected texture has no pixels");
    }
  } else if (const auto* cam = std::get_if<CameraProjectionSource>(&source)) {
    if (cam->texture.width < 1 || cam->texture.height < 1 || !cam->texture.has_texels()) {
      return bad("the projected photo has no pixels");
    }
  }
  return ok_status();
}

Expected<RenderImage> render_preview(const MeshData& mesh, const EmbreeScene& scene,
                                     const ColorSource& source, const RenderOptions& options,
                                     RenderStats* stats, Progress* progress) {
  if (Status st = validate_options(options); !st) return st.error();
  if (Status st = validate_color_source(mesh, source); !st) return st.error();
  auto bounds = bounding_sphere(mesh);
  if (!bounds) return bounds.error();

  const int views = options.views;
  const int cols = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(views))));
  const int rows = (views + cols - 1) / cols;
  RenderImage image;
  image.width = cols * options.width;
  image.height = rows * options.height;
  image.pixels.resize(static_cast<std::size_t>(image.width) * image.height * 4);
  for (std::size_t p = 0; p < image.pixels.size(); p += 4) {
    for (int c = 0; c < 3; ++c) image.pixels[p + c] = options.background[c];
    image.pixels[p + 3] = 0;
  }

  std::vector<Camera> cameras;
  for (int v = 0; v < views; ++v) {
    auto cam = make_camera(*bounds, options, options.azimuth_deg + v * 360.0 / views);
    if (!cam) return cam.error();
    cameras.push_back(*cam);
  }

  std::vector<Float3> vertex_normals;
  if (options.smooth_normals && mesh.corner_normal.empty()) {
    vertex_normals = smooth_vertex_normals(mesh);  // mesh_io/vertex_normals.h
  }
  RenderContext ctx{&mesh,      &scene, &options, &vertex_normals, kShadowOffset * scene.diagonal(),
                    image.width};

  const int tiles_x = (options.width + kTile - 1) / kTile;
  const int tiles_y = (options.height + kTile - 1) / kTile;
  const std::size_t tiles_per_view = static_cast<std::size_t>(tiles_x) * tiles_y;
  std::atomic<uint64_t> shadow_count{0};

  // The projection's shading rule, once per render (an sRGB texture
  // linearised once with `linear`; a linear one used as it is).
  WorkingImage projected;
  ShadeRule projection_rule;
  if (const auto* proj = std::get_if<ProjectionSource>(&source)) {
    projected = working_image(proj->texture, proj->linear);
    VertexBakeOptions shading;
    shading.outside = proj->outside ? OutsideMode::kColor : OutsideMode::kClamp;
    shading.outside_color = proj->outside.value_or(shading.outside_color);
    shading.linear = proj->linear;
    shading.plane_wrap = proj->plane_wrap;
    projection_rule = make_shade_rule(projected.view, proj->proxy, shading);
  } else if (const auto* cam = std::get_if<CameraProjectionSource>(&source)) {
    projected = working_image(cam->texture, cam->linear);
    VertexBakeOptions shading;
    shading.outside = OutsideMode::kColor;
    shading.outside_color = cam->outside.value_or(Rgba{kGreyAlbedo, kGreyAlbedo, kGreyAlbedo, 1});
    shading.linear = cam->linear;
    projection_rule = make_camera_shade_rule(projected.view, shading);
  }

  // Lights are fixed to the camera; the directions are per view.
  const PhongParams& ph = options.phong;
  std::vector<std::array<Light, 2>> view_lights;
  for (const Camera& cam : cameras) {
    auto world = [&](Vec3 d) {
      return normalize(cam.right * d.x + cam.up * d.y - cam.forward * d.z);
    };
    view_lights.push_back({Light{world(ph.key_direction), ph.key_diffuse, ph.key_specular},
                           Light{world(ph.fill_direction), ph.fill_diffuse, ph.fill_specular}});
  }

  if (progress) progress->start("render", tiles_per_view * views);
  parallel_for_chunks(tiles_per_view * views, 1, [&](std::size_t begin, std::size_t end) {
    if (is_cancelled(progress)) return;
    thread_local TileScratch scratch;
    for (std::size_t t = begin; t < end; ++t) {
      const int view = static_cast<int>(t / tiles_per_view);
      const int local = static_cast<int>(t % tiles_per_view);
      TileJob job;
      job.camera = &cameras[view];
      job.view = view;
      job.x0 = (local % tiles_x) * kTile;
      job.y0 = (local / tiles_x) * kTile;
      job.x1 = std::min(job.x0 + kTile, options.width);
      job.y1 = std::min(job.y0 + kTile, options.height);
      job.sheet_x = (view % cols) * options.width;
      job.sheet_y = (view / cols) * options.height;
      const std::array<Light, 2>& lights = view_lights[view];
      // Dispatch on the colour source (and the proxy) once per tile.
      std::visit(
          [&](const auto& src) {
            using S = std::decay_t<decltype(src)>;
            if constexpr (std::is_same_v<S, GreySource>) {
              render_tile(ctx, job, GreyColor{}, lights, scratch, image.pixels.data(),
                          shadow_count);
            } else if constexpr (std::is_same_v<S, VertexColorSource>) {
              render_tile(ctx, job, VertexColor{&mesh}, lights, scratch, image.pixels.data(),
                          shadow_count);
            } else if constexpr (std::is_same_v<S, AtlasSource>) {
              render_tile(ctx, job, AtlasColor{&mesh, src.texture}, lights, scratch,
                          image.pixels.data(), shadow_count);
            } else if constexpr (std::is_same_v<S, CameraProjectionSource>) {
              render_tile(ctx, job, ProjectedColor<CameraProjector>{&src.camera, &projection_rule},
                          lights, scratch, image.pixels.data(), shadow_count);
            } else {
              std::visit(
                  [&](const auto& proxy) {
                    using P = std::decay_t<decltype(proxy)>;
                    render_tile(ctx, job, ProjectedColor<P>{&proxy, &projection_rule}, lights,
                                scratch, image.pixels.data(), shadow_count);
                  },
                  src.proxy);
            }
          },
          source);
    }
    if (progress) progress->advance(end - begin);
  });
  if (is_cancelled(progress)) return cancelled_error();
  if (progress) progress->finish();

  if (stats) {
    stats->primary_rays =
        static_cast<uint64_t>(options.width) * options.height * views * options.samples_per_pixel;
    stats->shadow_rays = shadow_count.load();
  }
  return image;
}

}  // namespace texbake
