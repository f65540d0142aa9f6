// Ray-traced Phong previews of a mesh (texbake render, SPEC section 5).
//
// The camera is framed on the mesh's bounding sphere; Embree finds the
// surface point under every sample; a colour source gives its albedo; Phong
// shading with a key and a fill light gives the pixel.
//
// Conventions (each stated once, here):
//  - World "up" is RenderOptions::up (default +Z). The horizontal frame is the
//    minimal rotation taking +Z to `up` applied to +X ("east") and +Y
//    ("north"); for up = +Z that is +X and +Y themselves, for up = +Y it is +X
//    and -Z.
//  - View (azimuth, elevation) in degrees: the camera sits at
//    centre + distance * (cos(el) (sin(az) east - cos(az) north) + sin(el) up)
//    and looks at the bounding sphere's centre. Azimuth 0 looks from -north
//    (from -Y for up = +Z: Blender's front view; from +Z for up = +Y, OpenGL's),
//    and grows counter-clockwise seen from above (azimuth 90 looks from
//    +east). Elevation is above the horizon, [-90, 90].
//  - Image axes: x to the right, y down (top row first). The image's right is
//    the camera's d(position)/d(azimuth) direction, its up the
//    d(position)/d(elevation) direction, so elevation 90 (straight down) still
//    has a well-defined frame: right = east, up = north at azimuth 0.
//  - Perspective camera, kFieldOfViewDeg on the image's shorter side; the
//    distance makes the bounding sphere (inflated by kFrameMargin) just fit.
//    Bounding sphere: centre of the axis-aligned box of the referenced
//    vertices, radius the largest distance from it to a referenced vertex.
//  - Lights are directional and fixed to the camera (so every view is lit the
//    same way), given in the camera frame (right, up, towards the camera).
//    Phong: colour = albedo * (ka + sum_l kd_l max(0, N.L_l) vis_l)
//                    + sum_l ks_l max(0, R_l.V)^shininess vis_l,
//    R_l = 2 (N.L_l) N - L_l, clamped to [0, 1] per channel. N faces the
//    viewer (two-sided lighting: back faces are lit like front faces).
//    vis_l is 0 when a shadow ray towards light l is blocked (only the key
//    light casts shadows, and only with RenderOptions::shadows), else 1.
//  - Shading is done on sRGB-encoded albedos, like the bake itself gives
//    them: an sRGB texture's stored values (a ProjectionSource with `linear`
//    interpolates in linear light but gives its colour sRGB-encoded); a
//    linear texture (ImageView::color_space kLinear, e.g. an EXR atlas) is
//    interpolated in linear light and each sample sRGB-encoded.
//  - Pixels have straight (unassociated) alpha, as PNG stores it: RGB = mean
//    of the samples that hit the mesh, A = the fraction that hit. Pixels the
//    mesh does not cover have exactly the background RGB and alpha 0 (so a
//    viewer that ignores alpha shows the background colour).
//  - A sample's albedo alpha (an atlas or vertex colours with coverage, as
//    layers over base "none" give them; a projected texture's alpha)
//    composites its shaded colour over the background RGB before the mean:
//    a * shaded + (1 - a) * background. A fully transparent point shows
//    exactly the background, an opaque one (alpha 1: grey, and every bake
//    without alpha) its shaded colour; the pixel's alpha stays the fraction
//    of samples that hit the mesh. (The surfaces behind are not traced.)
//  - Sampling: samples_per_pixel == 1 shoots through the pixel centre.
//    Otherwise sample s of pixel p lies in stratum s of an m x m grid over the
//    pixel (m = ceil(sqrt(spp)), row-major; with spp < m*m the last strata
//    stay empty),
//    jittered by a hash of (p, s): the image never depends on the thread count.
#pragma once

#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

#include "bake/trace/embree_scene.h"
#include "bake/util/progress.h"
#include "mapping/camera.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

inline constexpr double kFieldOfViewDeg = 30.0;  // on the image's shorter side
inline constexpr double kFrameMargin = 1.05;     // bounding sphere radius factor

// Phong parameters. Light directions are in the camera frame (right, up,
// towards the camera) and need not be unit.
struct PhongParams {
  double ambient = 0.2;
  Vec3 key_direction{-1, 1, 2};  // upper left, in front
  double key_diffuse = 0.7;
  double key_specular = 0.3;
  Vec3 fill_direction{1, 0, 1};  // right, in front
  double fill_diffuse = 0.3;
  double fill_specular = 0.0;
  double shininess = 32;
};

struct RenderOptions {
  int width = 512;             // pixels, per view
  int height = 512;            // pixels, per view
  double azimuth_deg = 0;      // first view's azimuth (see the conventions above)
  double elevation_deg = 20;   // in [-90, 90]
  int views = 1;               // > 1: a contact sheet of views at azimuth + i * 360 / views
  bool shadows = false;        // shadow rays towards the key light
  int samples_per_pixel = 1;   // >= 1
  Vec3 up{0, 0, 1};            // world up, need not be unit; not zero
  bool smooth_normals = true;  // interpolate vertex (or OBJ corner) normals
  Rgba background{0.3f, 0.3f, 0.35f, 0.0f};  // RGB of uncovered pixels (alpha is always 0)
  PhongParams phong;
};

// Owning RGBA float image, top row first (the layout of ImageView).
struct RenderImage {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // width * height * 4
  ImageView view() const { return {width, height, pixels.data()}; }
  const float* pixel(int x, int y) const { return view().pixel(x, y); }
};

// ---- Colour sources: what a hit point's albedo is. ----------------------

// Plain grey (kGreyAlbedo) everywhere: for meshes without colours.
struct GreySource {};
inline constexpr float kGreyAlbedo = 0.7f;

// Interpolated per-vertex colours. Precondition: mesh.has_vertex_colors().
struct VertexColorSource {};

// A texture through the mesh's per-corner UVs (an OBJ + MTL atlas), sampled
// bilinearly with clamped edges (a linear texture in linear light, each
// sample then sRGB-encoded). Precondition: mesh.has_uvs(), texture >= 1x1.
struct AtlasSource {
  ImageView texture;
};

// Direct per-hit inverse mapping: the ground truth a bake is compared with.
// The hit point goes through proxy.inverse_map and the bake's shading rule
// (bake/shade/shade.h): the texture sampled bilinearly with the proxy's wrap
// rules (SPEC section 1; a plane with plane_wrap = kRepeat tiles, so nothing
// is outside it), points outside the proxy's domain take `outside` when set
// (--outside R,G,B[,A]), else the clamped sample; with `linear` (--linear)
// or a linear texture (ImageView::color_space kLinear) the texture is
// interpolated in linear light and each hit's colour sRGB-encoded. Points
// with no mapping (kUndefined) are grey. No visibility test: this is the
// projected colour of every point.
struct ProjectionSource {
  Proxy proxy;
  ImageView texture;
  std::optional<Rgba> outside;
  WrapMode plane_wrap = WrapMode::kClamp;  // --wrap; ignored by the other proxies
  bool linear = false;                     // --linear
};

// A photo through a calibrated camera (SPEC section 9, a "camera" proxy
// file): the ground truth of a single-camera bake. The hit point is
// projected through the camera's lens model and the photo sampled
// bilinearly (clamped; in linear light with `linear` or for a linear photo,
// then sRGB-encoded); points the camera does not map (behind it, past the
// distortion's turning point, off the photo) take `outside` when set, else
// grey. No visibility test, as for ProjectionSource.
struct CameraProjectionSource {
  CameraProjector camera;
  ImageView texture;
  std::optional<Rgba> outside;
  bool linear = false;
};

using ColorSource = std::variant<GreySource, VertexColorSource, AtlasSource, ProjectionSource,
                                 CameraProjectionSource>;

// Checks the source's preconditions against the mesh (kInvalidArgument).
Status validate_color_source(const MeshData& mesh, const ColorSource& source);

// ---- Camera. -------------------------------------------------------------

struct Ray {
  Vec3 origin, direction;  // direction unit
};

struct Camera {
  Vec3 position;
  Vec3 right, up, forward;  // orthonormal; forward looks at the target
  double tan_half_x = 0, tan_half_y = 0;
  int width = 0, height = 0;

  // The ray through continuous image position (x, y), pixel (i, j) covering
  // [i, i+1) x [j, j+1) (so its centre is at (i + 0.5, j + 0.5)).
  Ray ray(double x, double y) const;
};

// The view as a COLMAP PINHOLE camera (mapping/camera.h): the same pixel
// convention (pixel (i, j) centred at (i + 0.5, j + 0.5)), fx = W / (2
// tan_half_x), fy = H / (2 tan_half_y), principal point at the image centre,
// the rows of R right, -up (OpenCV's y down), forward. A render of the view is
// then a photo of that camera (tests/bake/photo, the Photographs demo).
CameraProjector pinhole_of_view(const Camera& view);

struct BoundingSphere {
  Vec3 center;
  double radius = 0;
};

// Bounding sphere of the vertices referenced by mesh.triangles (see above).
// Error kInvalidArgument if the mesh has no triangle.
Expected<BoundingSphere> bounding_sphere(const MeshData& mesh);

// The camera of one view. Errors: kInvalidArgument for a zero `up`, an
// elevation outside [-90, 90], a non-positive size.
Expected<Camera> make_camera(const BoundingSphere& bounds, const RenderOptions& options,
                             double azimuth_deg);

// ---- Rendering. ------------------------------------------------------------

struct RenderStats {
  std::uint64_t primary_rays = 0;
  std::uint64_t shadow_rays = 0;
};

// Renders options.views views of `mesh` (whose triangles `scene` was built
// from) into one image. views == 1: width x height. views > 1: a contact
// sheet of cols = ceil(sqrt(views)) columns and ceil(views / cols) rows of
// width x height cells, row-major by azimuth; unused cells are background.
// Runs in parallel (parallel_for_chunks over 16x16 tiles); the result does
// not depend on the thread count. `stats`, if not null, receives ray counts.
// `progress`, if not null, hears the stage "render" (tiles done) and may
// cancel. Errors: kInvalidArgument (invalid options or colour source),
// kCancelled (progress's callback returned false).
Expected<RenderImage> render_preview(const MeshData& mesh, const EmbreeScene& scene,
                                     const ColorSource& source, const RenderOptions& options,
                                     RenderStats* stats = nullptr, Progress* progress = nullptr);

}  // namespace texbake
