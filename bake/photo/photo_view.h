// What the vertex and the atlas photo bakes (photo_bake.h, photo_atlas.h)
// share (SPEC section 9): reading and checking one photo, and one camera's
// view of a surface point: the cull (inside the photo, in front, normal
// within 75 degrees of d), the quality q = cos(theta) (f / z)^2 border and
// the blend weight. Internal to bake/photo.
#pragma once

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "bake/photo/photo_bake.h"
#include "mapping/camera.h"
#include "mapping/sample.h"
#include "mapping/vec.h"
#include "mesh_io/image_io.h"

namespace texbake::photo_detail {

inline constexpr double kBorderFraction = 0.05;  // border weight reaches 1 at 5 % of min(W, H)
inline constexpr double kSoftTemperature = 0.1;  // --blend soft: exp(-(1 - q / q_max) / 0.1)

// mesh_io's read_image as a PhotoReader (the default reader).
Expected<PhotoImage> read_photo_file(const Photo& photo);

// `read` for a pass that reads photos[0], photos[1], ... in that order: when
// asked for photos[i] (the element itself, by address) it returns its
// image and starts reading photos[i + 1] in the background
// (bake/util/parallel.h BackgroundTask), so that decoding the next photo
// overlaps the work on this one. Calls of `read` stay one at a time and in
// order (its side effects, such as progress, are as without it); a photo
// asked for out of that order is read directly. Two decoded photos are in
// memory at once. The reader must outlive the pass; its last background read
// is waited for when it is destroyed.
PhotoReader prefetching_reader(const PhotoReader& read, const std::vector<Photo>& photos);

// Reads `photo` with `read`, checks its size (the camera's, or its aspect
// at another size: then stats.scaled and a warning), records its size in
// `stats` and linearises an sRGB photo in place (so that bilinear
// interpolation happens in linear light too; a linear photo is used as is).
// Its mask (photo_bake.h, "Masks"): alpha clamped to [0, 1] and multiplied
// by its mask file's (read_mask); when some alpha is below 1, stats.masked
// and masked_share are set and R, G, B are premultiplied by alpha (sample
// with sample_masked). Errors: the reader's (then `unreadable` is set,
// unless it is kCancelled); kParse for a size of another aspect; the mask
// file's (read_mask's, and kParse for a mask of another size than the
// photo's, naming both), which start "the mask of camera NAME: ".
Expected<PhotoImage> load_photo(const Photo& photo, const PhotoReader& read,
                                PhotoCameraStats& stats, std::vector<std::string>& warnings,
                                bool& unreadable);

// The mask file of `photo` (Photo::mask) by COLMAP's rule: alpha 0 where
// the file's value is 0 (R, G and B all 0), 1 elsewhere; R, G, B as read.
// Errors: read_image's, prefixed "the mask of camera NAME: ".
Expected<Image> read_mask(const Photo& photo);

// A mask checked against its camera without its photo (cameras check): the
// camera's size, or its aspect at another size (then `scaled`); else kParse
// naming the mask file and both sizes.
Status check_mask_size(const Photo& photo, const PhotoImage& mask, bool& scaled);

// A photo's sample at `uv` as load_photo left it: the colour in linear light
// and its mask value m (alpha bilinearly interpolated). For a masked photo
// (premultiplied) the colour is the premultiplied sample divided by m, the
// alpha-weighted mean of the four texels; m = 0: no colour (the point is
// masked out). An unmasked photo: the plain bilinear sample and m = 1.
inline Rgba sample_masked(const ImageView& view, bool masked, UV uv) {
  Rgba s = sample_bilinear(view, uv, WrapMode::kClamp, WrapMode::kClamp);
  if (!masked) {
    s[3] = 1;
  } else if (s[3] > 0) {
    for (int ch = 0; ch < 3; ++ch) s[ch] /= s[3];
  }
  return s;
}

// The mask value alone (sample_masked's m).
inline float mask_at(const ImageView& view, bool masked, UV uv) {
  return masked ? sample_bilinear(view, uv, WrapMode::kClamp, WrapMode::kClamp)[3] : 1.f;
}

// The error of an unreadable photo under PhotoBakeOptions::strict_photos.
Error unreadable_photo_error(const Photo& photo, const Error& read);
// The error when every photo was left out: kIo naming the count and the
// first one's reason.
Error no_usable_photo_error(const std::vector<SkippedPhoto>& skipped);
// Leaves `photo` out: its SkippedPhoto in `skipped` and a warning.
void skip_photo(const Photo& photo, const Error& read, std::vector<SkippedPhoto>& skipped,
                std::vector<std::string>& warnings);

// 0 at the photo's edge, 1 from kBorderFraction * min(W, H) inside on.
double border_weight(Vec2 pixel, int w, int h);

// One camera's view of surface points.
class CameraLook {
 public:
  // max_angle_deg: PhotoBakeOptions::max_view_angle_deg.
  CameraLook(const CameraProjector& camera, double max_angle_deg)
      : camera_(&camera),
        min_cosine_(std::cos(max_angle_deg * std::numbers::pi / 180.0)),
        centre_(camera.centre()),
        w_(camera.spec().width),
        h_(camera.spec().height),
        focal2_(camera.mean_focal() * camera.mean_focal()) {}

  Vec3 centre() const { return centre_; }

  // The point p with the unit normal n is a candidate: it projects inside
  // the photo, in front of the camera, with n within the maximum angle
  // (75 degrees by default) of d = normalize(C - p), strictly (a zero n
  // never is). Sets proj when it returns true. The angle first: it is cheaper
  // than the projection through the lens and turns away about half the
  // points of a closed mesh (the same conjunction, so the same answer).
  bool candidate(Vec3 p, Vec3 n, CameraProjection& proj) const {
    const Vec3 to_camera = centre_ - p;
    const double distance = length(to_camera);
    if (!(distance > 0 && dot(n, to_camera) > min_cosine_ * distance)) return false;
    proj = camera_->project(p);
    return proj.inside;
  }

  // The quality of a visible candidate, as stored (float, at least 1e-30
  // so that 0 means "not seen"): cos(theta) (f / z)^2 border.
  float quality(Vec3 p, Vec3 n, const CameraProjection& proj) const {
    const double cosine = dot(n, normalize(centre_ - p)) / length(n);
    const double q =
        cosine * focal2_ / (proj.depth * proj.depth) * border_weight(proj.pixel, w_, h_);
    return static_cast<float>(std::max(q, 1e-30));
  }

 private:
  const CameraProjector* camera_;
  double min_cosine_;
  Vec3 centre_;
  int w_, h_;
  double focal2_;
};

// The blend weight of a view of quality q at a point whose best view has
// q_max; `best`: this view is the point's first of largest q (kBest).
inline double blend_weight(PhotoBlend blend, float q, float q_max, bool best) {
  switch (blend) {
    case PhotoBlend::kSoft:
      return std::exp(-(1 - static_cast<double>(q) / q_max) / kSoftTemperature);
    case PhotoBlend::kBest:
      return best ? 1 : 0;
    case PhotoBlend::kMean:
      return 1;
  }
  return 0;
}

}  // namespace texbake::photo_detail
