// Refining the photos' poses so that they agree on the mesh (SPEC section
// 9, `texbake cameras refine`; issue 30 item 3).
//
// What is minimised: over surface sample points X_i (the mesh's vertices,
// subsampled evenly to at most max_points) and the photos c that see them,
//   sum_ic rho(|| g_c * I_c(pi_c(X_i)) - C_i ||)
// in linear light (sRGB decoded), where pi_c projects through camera c's
// lens model (mapping/camera.h, forward distortion), I_c is its photo
// sampled bilinearly, g_c its exposure gains (one per channel), C_i a
// consensus colour per point and rho a truncated Huber loss. It is solved
// by alternation, per pyramid level:
//  1. gains and consensus in closed form (C_i the mean of the gained
//     samples; g_c = sum I C / sum I^2 per channel; the gains' geometric
//     mean fixed at 1), samples past the loss's truncation left out;
//  2. one joint Levenberg-Marquardt step on every photo's 6 pose
//     parameters (with `intrinsics` also its focal length(s) and principal
//     point) with the consensus colours eliminated (the Schur complement:
//     each sample's residual is its distance to its point's weighted
//     mean), iteratively reweighted: Huber weights at 1.5 robust sigmas
//     of the photo's residuals (1.4826 median), samples past 6 sigmas left
//     out. Derivatives: analytic for the pose and the projection, central
//     differences for the lens distortion, image gradients of the level
//     (central differences, interpolated bilinearly). A step is kept only
//     when it lowers the joint cost.
// Levels: 2x box downsampling of each photo until the shorter side would
// drop below 48 pixels (at most 5 levels), coarse to fine.
// Which points a photo sees is decided per level at its current pose as
// the photo bake decides it (bake/photo/photo_view.h's cull: inside, in
// front, normal within 75 degrees; the segment to the camera's centre free
// of triangles, Embree), and points near a depth discontinuity are left out:
// eight rays from the centre at a radius of 2 + 2^(level+1) pixels around
// the point's projection must hit the point's tangent plane within 2 % of
// its depth (an occluding contour, or the background behind a silhouette,
// fails that). Only points seen by two photos or more count. A photo's
// alpha is its mask (photo_bake.h "Masks"): a sample whose bilinear
// footprint has a pixel of alpha 0 is not taken.
// Bounds: a photo's rotation may change by at most max_rotation_deg and its
// centre move by at most max_translation times the mesh's size (its
// bounding-box diagonal); a step past either is clamped onto the bound and
// the photo flagged. Every reduction runs over fixed blocks in a fixed
// order: results do not depend on the thread count.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "bake/photo/photo_bake.h"
#include "bake/shade/options.h"
#include "bake/util/progress.h"
#include "mapping/camera.h"
#include "mapping/error.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct PoseRefineOptions {
  bool intrinsics = false;         // also refine focal length(s) and principal point
  double max_rotation_deg = 2;     // the most a photo's rotation may change (degrees, > 0)
  double max_translation = 0.05;   // the most its centre may move, times the mesh's size (> 0)
  int iterations = 200;            // the most Gauss-Newton steps per pyramid level (1 .. 1000)
  std::size_t max_points = 30000;  // surface sample points (the vertices, subsampled evenly)
  // How the photos' colour space is taken (--texture-colorspace), for the
  // API's reader (texbake/texbake.h refine_cameras).
  TextureColorSpace color_space = TextureColorSpace::kAuto;
  // A photo that cannot be read is left out (its pose written unchanged)
  // with a warning; with strict_photos it is an error.
  bool strict_photos = false;
};

// One photo's outcome, in the input's order.
struct RefinedPose {
  std::string name;
  CameraProjector camera;          // the refined camera (the input's when skipped)
  double rotation_change_deg = 0;  // angle of R_refined R_input^T
  double translation_change = 0;   // |C_refined - C_input| / mesh size
  double focal_change = 0;         // relative change of the mean focal length (intrinsics)
  double residual_before = 0;      // RMS per channel, linear light, full resolution
  double residual_after = 0;       //   (against the other photos' consensus)
  std::size_t samples_before = 0;  // the points that residual is over
  std::size_t samples_after = 0;
  int iterations = 0;                   // accepted steps, all levels
  bool clamped = false;                 // a step was clamped onto max_rotation / max_translation
  bool skipped = false;                 // the photo cannot be read: not refined
  std::array<double, 3> gain{1, 1, 1};  // exposure gains at the refined poses
};

struct PoseRefineResult {
  std::vector<RefinedPose> photos;  // one per input photo, in order
  std::vector<SkippedPhoto> skipped;
  std::vector<std::string> warnings;
  std::size_t points = 0;  // surface sample points used
  int levels = 0;          // pyramid levels
  double mesh_size = 0;    // the bounding-box diagonal max_translation is relative to
  double seconds_scene = 0, seconds_photos = 0, seconds_refine = 0;
};

// Errors: kInvalidArgument (options out of range, fewer than two photos:
// "nothing to agree with"), kIo (no usable photo), a photo's read error
// under strict_photos, kParse (a photo of the wrong size; fewer than two
// readable photos; no point seen by two photos), kInternal (Embree),
// kCancelled (progress). `progress` (may be null): stage "refine".
Expected<PoseRefineResult> refine_poses(const MeshData& mesh, const std::vector<Photo>& photos,
                                        const PoseRefineOptions& options,
                                        const PhotoReader& reader = {},
                                        Progress* progress = nullptr);

}  // namespace texbake
