#include "mapping/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <string>

namespace texbake {

namespace {

struct ModelInfo {
  CameraModel model;
  std::string_view name;
  int id;      // COLMAP's model id (src/colmap/sensor/models.h)
  int params;  // COLMAP's parameter count
  bool one_focal;
};

constexpr ModelInfo kModels[] = {
    {CameraModel::kSimplePinhole, "SIMPLE_PINHOLE", 0, 3, true},
    {CameraModel::kPinhole, "PINHOLE", 1, 4, false},
    {CameraModel::kSimpleRadial, "SIMPLE_RADIAL", 2, 4, true},
    {CameraModel::kRadial, "RADIAL", 3, 5, true},
    {CameraModel::kOpenCV, "OPENCV", 4, 8, false},
    {CameraModel::kOpenCVFisheye, "OPENCV_FISHEYE", 5, 8, false},
    {CameraModel::kFullOpenCV, "FULL_OPENCV", 6, 12, false},
};

const ModelInfo& info(CameraModel model) {
  for (const ModelInfo& m : kModels) {
    if (m.model == model) return m;
  }
  return kModels[0];  // unreachable: every enumerator is in the table
}

// Files print rotations with 6-7 significant digits (SPEC section 9).
constexpr double kRotationTolerance = 1e-5;

std::string number(double v, int digits = 3) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// r must be orthonormal with determinant +1 within kRotationTolerance.
Status check_rotation(const std::array<double, 9>& r, std::string_view what) {
  double worst = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double d = 0;
      for (int k = 0; k < 3; ++k) d += r[3 * i + k] * r[3 * j + k];
      worst = std::max(worst, std::abs(d - (i == j ? 1.0 : 0.0)));
    }
  }
  const double det = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                     r[2] * (r[3] * r[7] - r[4] * r[6]);
  if (!(worst <= kRotationTolerance)) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(what) + ": the rotation is not orthonormal (|R R^T - I| = " +
                          number(worst) + ", more than 1e-5)");
  }
  if (!(det > 0)) {
    return make_error(
        ErrorCode::kInvalidArgument,
        std::string(what) + ": the rotation is a reflection (determinant " + number(det) + ")");
  }
  return ok_status();
}

// OpenGL camera axes (y up, looking down -z) to OpenCV ones: negate rows 2, 3.
std::array<double, 9> to_opencv_axes(std::array<double, 9> r, CameraAxes axes) {
  if (axes == CameraAxes::kOpenGL) {
    for (int k = 3; k < 9; ++k) r[k] = -r[k];
  }
  return r;
}

Vec3 times(const std::array<double, 9>& r, Vec3 v) {
  return {r[0] * v.x + r[1] * v.y + r[2] * v.z, r[3] * v.x + r[4] * v.y + r[5] * v.z,
          r[6] * v.x + r[7] * v.y + r[8] * v.z};
}

bool finite_all(const double* v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

Status check_finite(const double* v, std::size_t n, std::string_view what) {
  if (finite_all(v, n)) return ok_status();
  return make_error(ErrorCode::kInvalidArgument, std::string(what) + ": a value is not finite");
}

// The first radius where the model's radial map stops increasing, by a
// fine geometric scan of its derivative and bisection; +infinity if it
// increases up to r = 1e4 (a 179.99 degree field of view), which no photo
// reaches. derivative(r) > 0 near 0 for every model (it is 1 there).
template <class Derivative>
double first_turning_radius(Derivative derivative, double r_max) {
  double lo = 0;
  for (double r = 1e-4; r <= r_max; r *= 1.0005) {
    if (!(derivative(r) > 0)) {
      double hi = r;
      for (int i = 0; i < 60; ++i) {
        const double mid = (lo + hi) / 2;
        (derivative(mid) > 0 ? lo : hi) = mid;
      }
      return lo;
    }
    lo = r;
  }
  return std::numeric_limits<double>::infinity();
}

}  // namespace

std::string_view camera_model_name(CameraModel model) {
  return info(model).name;
}

std::optional<CameraModel> camera_model_from_name(std::string_view name) {
  for (const ModelInfo& m : kModels) {
    if (m.name == name) return m.model;
  }
  return std::nullopt;
}

int camera_model_id(CameraModel model) {
  return info(model).id;
}

std::optional<CameraModel> camera_model_from_id(int id) {
  for (const ModelInfo& m : kModels) {
    if (m.id == id) return m.model;
  }
  return std::nullopt;
}

int camera_param_count(CameraModel model) {
  return info(model).params;
}

Expected<CameraPose> pose_from_rotation(const std::array<double, 9>& r, Vec3 t, CameraAxes axes,
                                        std::string_view what) {
  if (Status s = check_finite(r.data(), r.size(), what); !s) return s.error();
  if (!is_finite(t))
    return make_error(ErrorCode::kInvalidArgument, std::string(what) + ": t is not finite");
  if (Status s = check_rotation(r, what); !s) return s.error();
  CameraPose pose;
  pose.r = to_opencv_axes(r, axes);
  pose.t = axes == CameraAxes::kOpenGL ? Vec3{t.x, -t.y, -t.z} : t;
  return pose;
}

Expected<CameraPose> pose_from_quaternion(const std::array<double, 4>& q_in, Vec3 t,
                                          CameraAxes axes, std::string_view what) {
  if (Status s = check_finite(q_in.data(), q_in.size(), what); !s) return s.error();
  // Normalised as COLMAP does (files print 6-7 digits: |q| is 1 only to
  // about 1e-6); scaled by its largest component first, so that tiny
  // (denormal) components neither underflow nor divide by zero.
  double largest = 0;
  for (double v : q_in) largest = std::max(largest, std::abs(v));
  if (!(largest > 0)) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(what) + ": the quaternion is zero (no rotation)");
  }
  std::array<double, 4> q{};
  for (int i = 0; i < 4; ++i) q[i] = q_in[i] / largest;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& v : q) v /= norm;
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const std::array<double, 9> r = {
      1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
      2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
      2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
  return pose_from_rotation(r, t, axes, what);
}

Expected<CameraPose> pose_from_centre(Vec3 centre, const std::array<double, 9>& r, CameraAxes axes,
                                      std::string_view what) {
  if (!is_finite(centre)) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(what) + ": the centre is not finite");
  }
  Expected<CameraPose> pose = pose_from_rotation(r, {0, 0, 0}, axes, what);
  if (!pose) return pose;
  pose->t = -times(pose->r, centre);
  return pose;
}

Expected<CameraPose> pose_from_cam_to_world(const std::array<double, 16>& m, CameraAxes axes,
                                            std::string_view what) {
  if (Status s = check_finite(m.data(), m.size(), what); !s) return s.error();
  if (!(std::abs(m[12]) <= kRotationTolerance && std::abs(m[13]) <= kRotationTolerance &&
        std::abs(m[14]) <= kRotationTolerance && std::abs(m[15] - 1) <= kRotationTolerance)) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(what) + ": the bottom row of cam_to_world must be 0 0 0 1");
  }
  // The upper 3x3's columns are the camera axes in the world: its transpose
  // is the world-to-camera rotation.
  const std::array<double, 9> r = {m[0], m[4], m[8], m[1], m[5], m[9], m[2], m[6], m[10]};
  return pose_from_centre({m[3], m[7], m[11]}, r, axes, what);
}

Expected<CameraPose> pose_from_look_at(Vec3 eye, Vec3 target, Vec3 up, std::string_view what) {
  if (!is_finite(eye) || !is_finite(target) || !is_finite(up)) {
    return make_error(ErrorCode::kInvalidArgument, std::string(what) + ": a value is not finite");
  }
  const Vec3 view = target - eye;
  if (!(length(view) > 0)) {
    return make_error(ErrorCode::kInvalidArgument, std::string(what) + ": eye and target coincide");
  }
  const Vec3 forward = normalize(view);
  const Vec3 side = cross(forward, up);
  if (!(length(up) > 0) || !(length(side) > 1e-9 * length(up))) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(what) + ": up is zero or parallel to the viewing direction");
  }
  const Vec3 right = normalize(side);
  const Vec3 down = cross(forward, right);
  CameraPose pose;
  pose.r = {right.x, right.y, right.z, down.x, down.y, down.z, forward.x, forward.y, forward.z};
  pose.t = -times(pose.r, eye);
  return pose;
}

Vec3 camera_centre(const CameraPose& pose) {
  const auto& r = pose.r;
  const Vec3 t = pose.t;
  return -Vec3{r[0] * t.x + r[3] * t.y + r[6] * t.z, r[1] * t.x + r[4] * t.y + r[7] * t.z,
               r[2] * t.x + r[5] * t.y + r[8] * t.z};
}

Vec3 camera_forward(const CameraPose& pose) {
  return {pose.r[6], pose.r[7], pose.r[8]};
}

Expected<CameraProjector> CameraProjector::make(CameraSpec spec) {
  const ModelInfo& m = info(spec.model);
  if (static_cast<int>(spec.params.size()) != m.params) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(m.name) + " takes " + std::to_string(m.params) +
                          " parameters, got " + std::to_string(spec.params.size()));
  }
  if (!finite_all(spec.params.data(), spec.params.size())) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(m.name) + ": a camera parameter is not finite");
  }
  if (spec.width < 1 || spec.height < 1) {
    return make_error(ErrorCode::kInvalidArgument,
                      "the camera's width and height must be at least 1");
  }
  CameraProjector c;
  const std::vector<double>& p = spec.params;
  const int first_k = m.one_focal ? 3 : 4;
  c.fx_ = p[0];
  c.fy_ = m.one_focal ? p[0] : p[1];
  c.cx_ = p[first_k - 2];
  c.cy_ = p[first_k - 1];
  // A denormal focal length (below DBL_MIN) is no lens: 1 / f overflows.
  if (!(c.fx_ >= std::numeric_limits<double>::min() &&
        c.fy_ >= std::numeric_limits<double>::min())) {
    return make_error(ErrorCode::kInvalidArgument, std::string(m.name) +
                                                       ": the focal length must be positive (got " +
                                                       number(std::min(c.fx_, c.fy_), 6) + ")");
  }
  if (!(c.cx_ >= 0 && c.cx_ <= spec.width && c.cy_ >= 0 && c.cy_ <= spec.height)) {
    return make_error(ErrorCode::kInvalidArgument,
                      std::string(m.name) + ": the principal point (" + number(c.cx_, 6) + ", " +
                          number(c.cy_, 6) + ") is outside the " + std::to_string(spec.width) +
                          " x " + std::to_string(spec.height) + " image");
  }
  for (int i = first_k; i < m.params; ++i) c.k_[i - first_k] = p[i];
  const auto& k = c.k_;
  // The radial map's derivative in r (normalised radius), and its turning point.
  double r_turn = std::numeric_limits<double>::infinity();
  switch (spec.model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kPinhole:
      break;
    case CameraModel::kSimpleRadial:  // r (1 + k s): 1 + 3 k s
      r_turn = first_turning_radius([&](double r) { return 1 + 3 * k[0] * r * r; }, 1e4);
      break;
    case CameraModel::kRadial:  // r (1 + k1 s + k2 s^2)
    case CameraModel::kOpenCV:
      r_turn = first_turning_radius(
          [&](double r) {
            const double s = r * r;
            return 1 + 3 * k[0] * s + 5 * k[1] * s * s;
          },
          1e4);
      break;
    case CameraModel::kFullOpenCV:  // r N(s) / D(s); k = k1 k2 p1 p2 k3 k4 k5 k6
      r_turn = first_turning_radius(
          [&](double r) {
            const double s = r * r;
            const double n = 1 + k[0] * s + k[1] * s * s + k[4] * s * s * s;
            const double d = 1 + k[5] * s + k[6] * s * s + k[7] * s * s * s;
            const double dn = k[0] + 2 * k[1] * s + 3 * k[4] * s * s;
            const double dd = k[5] + 2 * k[6] * s + 3 * k[7] * s * s;
            if (!(d > 0)) return -1.0;  // a pole of the rational model: folded
            return n / d + 2 * s * (dn * d - n * dd) / (d * d);
          },
          1e4);
      break;
    case CameraModel::kOpenCVFisheye: {  // theta (1 + k1 t^2 + ...), theta = atan(r)
      // In theta, up to pi/2: the turning point in theta, then r = tan(theta).
      const double theta_turn = first_turning_radius(
          [&](double t) {
            const double s = t * t;
            return 1 + 3 * k[0] * s + 5 * k[1] * s * s + 7 * k[2] * s * s * s +
                   9 * k[3] * s * s * s * s;
          },
          std::numbers::pi / 2);
      if (std::isfinite(theta_turn)) r_turn = std::tan(theta_turn);
      break;
    }
  }
  c.max_r2_ = r_turn * r_turn;
  c.centre_ = camera_centre(spec.pose);
  c.spec_ = std::move(spec);
  return c;
}

Vec2 CameraProjector::pixel_of_normalised(double a, double b) const {
  const auto& k = k_;
  const double r2 = a * a + b * b;
  double da = a, db = b;
  switch (spec_.model) {
    case CameraModel::kSimplePinhole:
    case CameraModel::kPinhole:
      break;
    case CameraModel::kSimpleRadial: {
      const double radial = 1 + k[0] * r2;
      da = a * radial, db = b * radial;
      break;
    }
    case CameraModel::kRadial: {
      const double radial = 1 + k[0] * r2 + k[1] * r2 * r2;
      da = a * radial, db = b * radial;
      break;
    }
    case CameraModel::kOpenCV:
    case CameraModel::kFullOpenCV: {
      double radial = 1 + k[0] * r2 + k[1] * r2 * r2;
      if (spec_.model == CameraModel::kFullOpenCV) {
        radial =
            (radial + k[4] * r2 * r2 * r2) / (1 + k[5] * r2 + k[6] * r2 * r2 + k[7] * r2 * r2 * r2);
      }
      const double p1 = k[2], p2 = k[3];
      da = a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a);
      db = b * radial + p1 * (r2 + 2 * b * b) + 2 * p2 * a * b;
      break;
    }
    case CameraModel::kOpenCVFisheye: {
      const double r = std::sqrt(r2);
      if (r > 0) {
        const double theta = std::atan(r), t2 = theta * theta;
        const double theta_d = theta * (1 + k[0] * t2 + k[1] * t2 * t2 + k[2] * t2 * t2 * t2 +
                                        k[3] * t2 * t2 * t2 * t2);
        da = a * theta_d / r, db = b * theta_d / r;
      }
      break;
    }
  }
  return {fx_ * da + cx_, fy_ * db + cy_};
}

CameraProjection CameraProjector::project(Vec3 world) const {
  CameraProjection out;
  const Vec3 p = times(spec_.pose.r, world) + spec_.pose.t;
  out.depth = p.z;
  if (!(p.z > 0)) return out;
  const double a = p.x / p.z, b = p.y / p.z;
  out.pixel = pixel_of_normalised(a, b);
  out.uv = {out.pixel.x / spec_.width, 1 - out.pixel.y / spec_.height};
  if (!(a * a + b * b <= max_r2_)) {
    out.outside = CameraOutside::kFolded;
  } else if (!(out.pixel.x >= 0 && out.pixel.x <= spec_.width && out.pixel.y >= 0 &&
               out.pixel.y <= spec_.height)) {
    out.outside = CameraOutside::kOffPhoto;
  } else {
    out.outside = CameraOutside::kNone;
  }
  out.inside = out.outside == CameraOutside::kNone;
  return out;
}

PhotoFit photo_fit(const CameraSpec& spec, int width, int height) {
  const int w = spec.width, h = spec.height;
  if (width == w && height == h) return PhotoFit::kExact;
  const long long cross = static_cast<long long>(width) * h - static_cast<long long>(height) * w;
  if (width > 0 && height > 0 && std::llabs(cross) < std::max(w, h)) return PhotoFit::kScaled;
  return PhotoFit::kWrong;
}

MapResult CameraProjector::inverse_map(Vec3 world) const {
  const CameraProjection proj = project(world);
  const Vec3 to_camera = centre_ - world;
  const double distance = length(to_camera);
  if (!(distance > 0)) return {proj.uv, {0, 0, 0}, MapStatus::kUndefined};
  return {proj.uv, to_camera / distance, proj.inside ? MapStatus::kOk : MapStatus::kOutside};
}

}  // namespace texbake
