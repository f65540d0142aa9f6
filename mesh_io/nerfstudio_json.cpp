#include "mesh_io/nerfstudio_json.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <optional>

#include "mesh_io/camera_format_text.h"
#include "mesh_io/json_strict.h"

namespace texbake {

namespace {

using nlohmann::json;

constexpr const char* kDistortionKeys[] = {"k1", "k2", "k3", "k4", "p1", "p2"};

// Lens and timing keys of instant-ngp and nerfstudio that no COLMAP model
// holds: refused rather than left out.
constexpr const char* kRefusedKeys[] = {"k5",
                                        "k6",
                                        "ftheta_p0",
                                        "ftheta_p1",
                                        "ftheta_p2",
                                        "ftheta_p3",
                                        "ftheta_p4",
                                        "latlong",
                                        "equirectangular",
                                        "orthographic",
                                        "transform_matrix_start",
                                        "transform_matrix_end"};

using camera_text::fail;
using camera_text::show;

// A frame's view of the intrinsics: its own keys, else the top level's.
class Keys {
 public:
  Keys(const json& top, const json& frame, std::string where)
      : top_(top), frame_(frame), where_(std::move(where)) {}

  // The value of `key`, from the frame or the top level (nullptr: neither).
  // Both holding it with different values is an error.
  Expected<const json*> get(const char* key) const {
    const json* f = frame_.contains(key) ? &frame_[key] : nullptr;
    const json* t = top_.contains(key) ? &top_[key] : nullptr;
    if (f && t && *f != *t) {
      return fail(where_, "key '" + std::string(key) + "' is " + f->dump() + " here and " +
                              t->dump() +
                              " at the top level (nerfstudio takes the top level's, instant-ngp "
                              "the frame's): give it once");
    }
    return f ? f : t;
  }
  Expected<std::optional<double>> number(const char* key) const {
    Expected<const json*> v = get(key);
    if (!v) return v.error();
    if (!*v) return std::optional<double>();
    if (!(*v)->is_number()) return fail(where_, "key '" + std::string(key) + "' must be a number");
    return std::optional<double>((*v)->get<double>());
  }
  Expected<int> size(const char* key) const {
    Expected<std::optional<double>> v = number(key);
    if (!v) return v.error();
    if (!*v) {
      return fail(where_, "missing key '" + std::string(key) + "' (the photo's " +
                              (key[0] == 'w' ? "width" : "height") + " in pixels)");
    }
    const double d = **v;
    if (!(d >= 1 && d <= (1 << 30) && d == std::floor(d))) {
      return fail(where_,
                  "key '" + std::string(key) + "' must be a positive whole number of pixels");
    }
    return static_cast<int>(d);
  }
  const std::string& where() const { return where_; }

 private:
  const json& top_;
  const json& frame_;
  std::string where_;
};

// A rows x cols matrix given as an array of rows, row-major.
template <std::size_t Rows, std::size_t Cols>
Expected<std::array<double, Rows * Cols>> matrix(const json& v, const std::string& where,
                                                 const std::string& key) {
  const Error bad = fail(where, "key '" + key + "' must be " + std::to_string(Rows) + " rows of " +
                                    std::to_string(Cols) + " numbers");
  if (!v.is_array() || v.size() != Rows) return bad;
  std::array<double, Rows * Cols> out{};
  for (std::size_t r = 0; r < Rows; ++r) {
    if (!v[r].is_array() || v[r].size() != Cols) return bad;
    for (std::size_t c = 0; c < Cols; ++c) {
      if (!v[r][c].is_number()) return bad;
      out[r * Cols + c] = v[r][c].get<double>();
    }
  }
  return out;
}

// The similarity the file's poses were re-framed by: X_file = s (A X + a).
struct Reframe {
  std::array<double, 9> a{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 offset{0, 0, 0};
  double scale = 1;
  bool identity = true;
};

Expected<Reframe> read_reframe(const json& root, const std::string& source) {
  Reframe f;
  if (root.contains("applied_transform")) {
    Expected<std::array<double, 12>> m =
        matrix<3, 4>(root["applied_transform"], source, "applied_transform");
    if (!m) return m.error();
    f.a = {(*m)[0], (*m)[1], (*m)[2], (*m)[4], (*m)[5], (*m)[6], (*m)[8], (*m)[9], (*m)[10]};
    f.offset = {(*m)[3], (*m)[7], (*m)[11]};
    // Its rotation must be one (orthonormal, no reflection): the same check
    // as a pose's.
    Expected<CameraPose> check = pose_from_rotation(f.a, f.offset, CameraAxes::kOpenCV,
                                                    source + ": key 'applied_transform'");
    if (!check) return make_error(ErrorCode::kParse, check.error().message);
  }
  if (root.contains("applied_scale")) {
    const json& s = root["applied_scale"];
    if (!s.is_number() || !(s.get<double>() > 0)) {
      return fail(source, "key 'applied_scale' must be a positive number");
    }
    f.scale = s.get<double>();
  }
  const std::array<double, 9> eye{1, 0, 0, 0, 1, 0, 0, 0, 1};
  f.identity = f.a == eye && f.offset.x == 0 && f.offset.y == 0 && f.offset.z == 0 && f.scale == 1;
  return f;
}

// camera-to-world m (4x4, row-major) of the file's frame in the original
// one: rotation A^T R, centre A^T (t / s - a).
std::array<double, 16> undo(const Reframe& f, const std::array<double, 16>& m) {
  if (f.identity) return m;
  std::array<double, 16> out = m;
  const Vec3 t{m[3] / f.scale - f.offset.x, m[7] / f.scale - f.offset.y,
               m[11] / f.scale - f.offset.z};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) {
      out[4 * r + c] =
          f.a[0 + r] * m[0 + c] + f.a[3 + r] * m[4 + c] + f.a[6 + r] * m[8 + c];  // A^T R
    }
    out[4 * r + 3] = f.a[0 + r] * t.x + f.a[3 + r] * t.y + f.a[6 + r] * t.z;
  }
  return out;
}

// fl_x (or fl_y): given, or from camera_angle_x (radians) or x_fov
// (degrees), which must agree with it when both are given.
Expected<std::optional<double>> focal(const Keys& k, char axis, int pixels) {
  const std::string fl = std::string("fl_") + axis;
  const std::string angle = std::string("camera_angle_") + axis;
  const std::string fov = std::string(1, axis) + "_fov";
  Expected<std::optional<double>> f = k.number(fl.c_str());
  if (!f) return f;
  for (const auto& [key, degrees] : {std::pair{angle, false}, std::pair{fov, true}}) {
    Expected<std::optional<double>> a = k.number(key.c_str());
    if (!a) return a;
    if (!*a) continue;
    const double radians = degrees ? **a * std::numbers::pi / 180 : **a;
    if (!(radians > 0 && radians < std::numbers::pi)) {
      return fail(k.where(), "key '" + key + "' must be an angle of view between 0 and " +
                                 (degrees ? "180 degrees" : "pi radians"));
    }
    const double from_angle = 0.5 * pixels / std::tan(0.5 * radians);
    if (!*f) {
      f = std::optional<double>(from_angle);
    } else if (!(std::abs(**f - from_angle) <= 1e-6 * **f)) {
      return fail(k.where(), "key '" + key + "' (" + show(**a) + ") gives the focal length " +
                                 show(from_angle) + " px, but key '" + fl + "' is " + show(**f));
    }
  }
  return f;
}

Expected<CameraSpec> read_intrinsics(const Keys& k) {
  for (const char* key : kRefusedKeys) {
    Expected<const json*> v = k.get(key);
    if (!v) return v.error();
    if (*v) {
      return fail(k.where(), "key '" + std::string(key) +
                                 "': texbake has no camera model for it (COLMAP's models only)");
    }
  }
  if (Expected<const json*> rs = k.get("rolling_shutter"); !rs) {
    return rs.error();
  } else if (*rs) {
    bool zero = (*rs)->is_array();
    if (zero) {
      for (const json& v : **rs) zero = zero && v.is_number() && v.get<double>() == 0;
    }
    if (!zero) return fail(k.where(), "key 'rolling_shutter': texbake models no rolling shutter");
  }
  CameraSpec spec;
  Expected<int> w = k.size("w");
  if (!w) return w.error();
  Expected<int> h = k.size("h");
  if (!h) return h.error();
  spec.width = *w;
  spec.height = *h;
  Expected<std::optional<double>> fx = focal(k, 'x', *w);
  if (!fx) return fx.error();
  if (!*fx) return fail(k.where(), "missing key 'fl_x' (the focal length in pixels)");
  Expected<std::optional<double>> fy = focal(k, 'y', *h);
  if (!fy) return fy.error();
  Expected<std::optional<double>> cx = k.number("cx");
  if (!cx) return cx.error();
  Expected<std::optional<double>> cy = k.number("cy");
  if (!cy) return cy.error();
  const double f_x = **fx, f_y = fy->value_or(f_x);
  const double c_x = cx->value_or(*w / 2.0), c_y = cy->value_or(*h / 2.0);

  double d[6] = {0, 0, 0, 0, 0, 0};  // k1 k2 k3 k4 p1 p2
  for (int i = 0; i < 6; ++i) {
    Expected<std::optional<double>> v = k.number(kDistortionKeys[i]);
    if (!v) return v.error();
    d[i] = v->value_or(0);
  }
  const double k1 = d[0], k2 = d[1], k3 = d[2], k4 = d[3], p1 = d[4], p2 = d[5];

  Expected<const json*> model_key = k.get("camera_model");
  if (!model_key) return model_key.error();
  Expected<const json*> fisheye_key = k.get("is_fisheye");
  if (!fisheye_key) return fisheye_key.error();
  if (*fisheye_key && !(*fisheye_key)->is_boolean()) {
    return fail(k.where(), "key 'is_fisheye' must be true or false");
  }
  const bool ngp_fisheye = *fisheye_key && (*fisheye_key)->get<bool>();
  std::string model = ngp_fisheye ? "OPENCV_FISHEYE" : "OPENCV";
  if (*model_key) {
    if (!(*model_key)->is_string()) return fail(k.where(), "key 'camera_model' must be a string");
    model = (*model_key)->get<std::string>();
    if (*fisheye_key && ngp_fisheye != (model == "OPENCV_FISHEYE")) {
      return fail(k.where(), "key 'is_fisheye' contradicts key 'camera_model' (" + model + ")");
    }
  }
  if (model == "OPENCV_FISHEYE") {
    for (int i : {4, 5}) {
      if (d[i] != 0) {
        return fail(k.where(), "key '" + std::string(kDistortionKeys[i]) + "' is " + show(d[i]) +
                                   ": OPENCV_FISHEYE has no tangential terms");
      }
    }
    spec.model = CameraModel::kOpenCVFisheye;
    spec.params = {f_x, f_y, c_x, c_y, k1, k2, k3, k4};
    return spec;
  }
  if (model != "SIMPLE_PINHOLE" && model != "PINHOLE" && model != "SIMPLE_RADIAL" &&
      model != "RADIAL" && model != "OPENCV") {
    return fail(k.where(), "key 'camera_model': '" + model +
                               "' is not a camera texbake models (expected OPENCV, "
                               "OPENCV_FISHEYE, PINHOLE, SIMPLE_PINHOLE, SIMPLE_RADIAL or RADIAL)");
  }
  // nerfstudio's perspective lens: radial 1 + k1 r^2 + k2 r^4 + k3 r^6 + k4 r^8.
  if (k4 != 0) {
    return fail(k.where(), "key 'k4' is " + show(k4) +
                               ": nerfstudio's perspective k4 is a radial r^8 term, which no "
                               "COLMAP camera model has");
  }
  if (k1 == 0 && k2 == 0 && k3 == 0 && p1 == 0 && p2 == 0) {
    spec.model = CameraModel::kPinhole;
    spec.params = {f_x, f_y, c_x, c_y};
  } else if (k3 == 0) {
    spec.model = CameraModel::kOpenCV;
    spec.params = {f_x, f_y, c_x, c_y, k1, k2, p1, p2};
  } else {
    // FULL_OPENCV's radial (1 + k1 r^2 + k2 r^4 + k3 r^6) / (1 + k4 r^2 +
    // k5 r^4 + k6 r^6) with its k4..k6 = 0 is this one exactly.
    spec.model = CameraModel::kFullOpenCV;
    spec.params = {f_x, f_y, c_x, c_y, k1, k2, p1, p2, k3, 0, 0, 0};
  }
  return spec;
}

// The distortion must come from one place: nerfstudio reads all of it from
// the top level when the top level gives any, instant-ngp key by key, so a
// frame may not add a distortion key when the top level gives some.
Status check_distortion_place(const json& top, const json& frame, const std::string& where) {
  const char* top_key = nullptr;
  for (const char* key : kDistortionKeys) {
    if (top.contains(key)) top_key = key;
  }
  if (!top_key) return ok_status();
  for (const char* key : kDistortionKeys) {
    if (frame.contains(key) && !top.contains(key)) {
      return fail(where, "key '" + std::string(key) +
                             "' is given here while the top level gives the distortion (key '" +
                             top_key +
                             "'): nerfstudio would leave the frame's out, instant-ngp use it; give "
                             "the distortion in one place");
    }
  }
  return ok_status();
}

}  // namespace

Expected<CameraFile> nerfstudio_from_json(std::string_view text, const std::string& source) {
  Expected<json> parsed = parse_json_object(text, source);
  if (!parsed) return parsed.error();
  const json& root = *parsed;
  if (!root.contains("frames") || !root["frames"].is_array() || root["frames"].empty()) {
    return fail(source, "key 'frames' must be a non-empty array of frames");
  }
  Expected<Reframe> reframe = read_reframe(root, source);
  if (!reframe) return reframe.error();
  CameraFile out;
  out.format = CameraFormat::kNerfstudio;
  const json& frames = root["frames"];
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::string where = source + ": frames[" + std::to_string(i) + "]";
    const json& frame = frames[i];
    if (!frame.is_object()) return fail(where, "a frame must be a JSON object");
    if (Status s = check_distortion_place(root, frame, where); !s) return s.error();
    Expected<CameraSpec> spec = read_intrinsics(Keys(root, frame, where));
    if (!spec) return spec.error();
    if (!frame.contains("file_path") || !frame["file_path"].is_string() ||
        frame["file_path"].get<std::string>().empty()) {
      return fail(where, "key 'file_path' must name the photo");
    }
    if (!frame.contains("transform_matrix")) return fail(where, "missing key 'transform_matrix'");
    Expected<std::array<double, 16>> m =
        matrix<4, 4>(frame["transform_matrix"], where, "transform_matrix");
    if (!m) return m.error();
    const std::string what = where + ": key 'transform_matrix'";
    // The matrix as given (its bottom row, its rotation), then in the
    // original frame.
    if (Expected<CameraPose> given = pose_from_cam_to_world(*m, CameraAxes::kOpenGL, what);
        !given) {
      return make_error(ErrorCode::kParse, given.error().message);
    }
    Expected<CameraPose> pose =
        pose_from_cam_to_world(undo(*reframe, *m), CameraAxes::kOpenGL, what);
    if (!pose) return make_error(ErrorCode::kParse, pose.error().message);
    spec->pose = *pose;
    Expected<CameraProjector> camera = CameraProjector::make(std::move(spec).value());
    if (!camera) return fail(where, camera.error().message);
    const std::string name =
        std::filesystem::path(frame["file_path"].get<std::string>()).lexically_normal().string();
    out.cameras.push_back({std::move(camera).value(), name});
  }
  if (!reframe->identity) {
    std::string a;
    for (int r = 0; r < 3; ++r) {
      a += std::string(r ? ", " : "") + "[" + show(reframe->a[3 * r]) + ", " +
           show(reframe->a[3 * r + 1]) + ", " + show(reframe->a[3 * r + 2]) + ", " +
           show(r == 0   ? reframe->offset.x
                : r == 1 ? reframe->offset.y
                         : reframe->offset.z) +
           "]";
    }
    out.notes.push_back(source +
                        ": the poses are taken back to the frame of the data they were "
                        "made from (applied_transform [" +
                        a + "] and applied_scale " + show(reframe->scale) +
                        " undone, as nerfstudio's transform_poses_to_original_space does): a mesh "
                        "of the same reconstruction is in that frame");
  }
  return out;
}

}  // namespace texbake
