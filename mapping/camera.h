// The camera projector's mathematics (SPEC section 9): COLMAP's seven camera
// models with their exact parameter order, forward lens distortion, the pose
// forms users bring, and the projection of a world point to a photo pixel.
// Standard C++ only.
//
// Conventions (texbake's, which are COLMAP's):
// - camera axes: OpenCV (x right, y down, z forward);
// - pose: world-to-camera, X_cam = R X + t; the centre is C = -R^T t;
// - pixels: the centre of the top-left pixel is at (0.5, 0.5); a pixel
//   (x, y) is at (u, v) = (x / width, 1 - y / height), so SPEC section 1's
//   lookup lands on that very texel.
#pragma once

#include <array>
#include <optional>
#include <string_view>
#include <vector>

#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mapping/vec.h"

namespace texbake {

enum class CameraModel {
  kSimplePinhole,  // f, cx, cy
  kPinhole,        // fx, fy, cx, cy
  kSimpleRadial,   // f, cx, cy, k
  kRadial,         // f, cx, cy, k1, k2
  kOpenCV,         // fx, fy, cx, cy, k1, k2, p1, p2
  kFullOpenCV,     // fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6
  kOpenCVFisheye,  // fx, fy, cx, cy, k1, k2, k3, k4
};

// COLMAP's name of a model ("SIMPLE_PINHOLE", ...), and back (exact,
// upper case); nullopt for a name that is none of the seven.
std::string_view camera_model_name(CameraModel model);
std::optional<CameraModel> camera_model_from_name(std::string_view name);
// COLMAP's model id (cameras.bin: 0 SIMPLE_PINHOLE ... 5 OPENCV_FISHEYE,
// 6 FULL_OPENCV), and back.
int camera_model_id(CameraModel model);
std::optional<CameraModel> camera_model_from_id(int id);
// How many parameters the model takes (3, 4, 4, 5, 8, 12, 8).
int camera_param_count(CameraModel model);

// A rigid world-to-camera transform in OpenCV axes: X_cam = r X + t, r
// row-major.
struct CameraPose {
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 t{0, 0, 0};
};

// The axes a pose is given in: OpenCV (x right, y down, z forward; COLMAP,
// OpenCV, openMVS) or OpenGL (x right, y up, looking down -z; Blender,
// nerfstudio, instant-ngp).
enum class CameraAxes { kOpenCV, kOpenGL };

// The pose forms of SPEC section 9, each turned into texbake's one form.
// Every rotation matrix must be orthonormal with determinant +1 within 1e-5
// (files print 6-7 significant digits), else kInvalidValue naming `what`
// (e.g. the key); it is used as given (not re-orthonormalised). A
// quaternion is normalised, as COLMAP does; a zero or non-finite one is an
// error.
//   q_wxyz + t: COLMAP's images.txt, world-to-camera.
//   r + t:      a world-to-camera rotation (row-major) and translation.
//   centre + r: the camera centre in the world and the world-to-camera r.
//   cam_to_world: a 4x4 row-major matrix whose upper 3x3 columns are the
//               camera axes in the world and whose last column is the centre
//               (the bottom row must be 0 0 0 1).
//   look_at:    eye, target and an up vector (not parallel to target - eye);
//               the axes flag does not apply (the view is fully given).
// With CameraAxes::kOpenGL the given rotation maps into OpenGL camera axes,
// and is turned into OpenCV ones (y and z negated).
Expected<CameraPose> pose_from_quaternion(const std::array<double, 4>& q_wxyz, Vec3 t,
                                          CameraAxes axes, std::string_view what);
Expected<CameraPose> pose_from_rotation(const std::array<double, 9>& r, Vec3 t, CameraAxes axes,
                                        std::string_view what);
Expected<CameraPose> pose_from_centre(Vec3 centre, const std::array<double, 9>& r, CameraAxes axes,
                                      std::string_view what);
Expected<CameraPose> pose_from_cam_to_world(const std::array<double, 16>& m, CameraAxes axes,
                                            std::string_view what);
Expected<CameraPose> pose_from_look_at(Vec3 eye, Vec3 target, Vec3 up, std::string_view what);

// The camera centre -r^T t, and the world-space direction of the optical
// axis (the third row of r).
Vec3 camera_centre(const CameraPose& pose);
Vec3 camera_forward(const CameraPose& pose);

struct CameraSpec {
  CameraModel model = CameraModel::kPinhole;
  int width = 0, height = 0;   // the photo's size in pixels
  std::vector<double> params;  // COLMAP's order for `model`
  CameraPose pose;
};

// Why a point is outside a camera's photo (SPEC section 9).
enum class CameraOutside {
  kNone,     // inside: in front, within the valid radius, inside the photo
  kBehind,   // Z <= 0 in camera axes
  kFolded,   // past the distortion's first turning point
  kOffPhoto  // the pixel is outside [0, width] x [0, height]
};

// How a photo of `width` x `height` pixels fits the camera (SPEC section 9):
// its size, or its aspect at another size (within one pixel: the camera's
// (u, v) do not depend on the resolution), or neither (an error for the
// caller).
enum class PhotoFit { kExact, kScaled, kWrong };
PhotoFit photo_fit(const CameraSpec& spec, int width, int height);

// Where a world point lands in the photo.
struct CameraProjection {
  bool inside = false;  // in front, inside the photo, within the distortion's valid radius
  Vec2 pixel{0, 0};     // (x, y), COLMAP convention (valid when the point is in front)
  UV uv{0, 0};          // (x / width, 1 - y / height)
  double depth = 0;     // z in camera axes
  CameraOutside outside = CameraOutside::kBehind;
};

class CameraProjector {
 public:
  // Errors (kInvalidValue): wrong parameter count, a non-finite parameter, a
  // focal length that is not a positive normal number (zero, negative,
  // denormal), a principal point outside [0, width] x [0, height], a size
  // below 1 pixel.
  static Expected<CameraProjector> make(CameraSpec spec);

  const CameraSpec& spec() const { return spec_; }
  Vec3 centre() const { return centre_; }
  // (fx + fy) / 2: image pixels per unit of the normalised image plane.
  double mean_focal() const { return (fx_ + fy_) / 2; }
  // The largest r^2 = a^2 + b^2 (normalised image plane) before the radial
  // distortion's first turning point, where r_d(r) stops increasing and the
  // model folds back; +infinity when it never does. For OPENCV_FISHEYE, r is
  // tan(theta).
  double max_radius2() const { return max_r2_; }

  // The distorted pixel of a point (a, b) of the normalised image plane
  // (a = X/Z, b = Y/Z), forward distortion exactly as SPEC section 9.
  Vec2 pixel_of_normalised(double a, double b) const;
  // P in world coordinates to the photo: outside when Z <= 0, r^2 past
  // max_radius2(), or the pixel outside [0, width] x [0, height].
  CameraProjection project(Vec3 world) const;
  // The camera as a proxy (SPEC section 9: a "camera" proxy file): (u, v)
  // of project(), kOk when inside, else kOutside (behind the camera, past
  // the turning point or off the photo; uv is then project()'s, meaningless
  // behind the camera); to_projector = normalize(C - P) (kUndefined at
  // P = C).
  MapResult inverse_map(Vec3 world) const;

 private:
  CameraSpec spec_;
  Vec3 centre_{0, 0, 0};
  double fx_ = 1, fy_ = 1, cx_ = 0, cy_ = 0;
  std::array<double, 8> k_{};  // the distortion coefficients after cx, cy, in order
  double max_r2_ = 0;
};

}  // namespace texbake
