#include "mesh_io/camera_json.h"

#include <cmath>
#include <set>

#include "mesh_io/json_strict.h"
#include "mesh_io/regular_file.h"

namespace texbake {

namespace {

using nlohmann::json;

class Reader {
 public:
  explicit Reader(std::string where) : where_(std::move(where)) {}
  Error fail(const std::string& what) const {
    return make_error(ErrorCode::kParse, where_ + ": " + what);
  }
  Status only_keys(const json& o, const std::set<std::string>& allowed, const char* what) const {
    for (const auto& [key, value] : o.items()) {
      if (!allowed.count(key)) {
        std::string list;
        for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
        return fail("unknown key '" + key + "' in " + what + " (expected " + list + ")");
      }
    }
    return ok_status();
  }
  Expected<double> number(const json& v, const std::string& key) const {
    if (!v.is_number()) return fail("key '" + key + "' must be a number");
    const double d = v.get<double>();
    if (!std::isfinite(d)) return fail("key '" + key + "' is not finite");
    return d;
  }
  Expected<int> size(const json& v, const std::string& key) const {
    if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > 1 << 30) {
      return fail("key '" + key + "' must be a positive integer");
    }
    return static_cast<int>(v.get<long long>());
  }
  Expected<std::vector<double>> numbers(const json& v, const std::string& key,
                                        std::size_t n) const {
    if (!v.is_array() || (n != 0 && v.size() != n)) {
      return fail("key '" + key + "' must be an array of " +
                  (n ? std::to_string(n) + " numbers" : std::string("numbers")));
    }
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); ++i) {
      Expected<double> d = number(v[i], key + "[" + std::to_string(i) + "]");
      if (!d) return d.error();
      out.push_back(*d);
    }
    return out;
  }
  Expected<Vec3> vec3(const json& v, const std::string& key) const {
    Expected<std::vector<double>> d = numbers(v, key, 3);
    if (!d) return d.error();
    return Vec3{(*d)[0], (*d)[1], (*d)[2]};
  }
  // A rows x cols matrix given as an array of rows.
  template <std::size_t N>
  Expected<std::array<double, N>> matrix(const json& v, const std::string& key,
                                         std::size_t rows) const {
    const std::size_t cols = N / rows;
    if (!v.is_array() || v.size() != rows) {
      return fail("key '" + key + "' must be " + std::to_string(rows) + " rows of " +
                  std::to_string(cols) + " numbers");
    }
    std::array<double, N> out{};
    for (std::size_t r = 0; r < rows; ++r) {
      Expected<std::vector<double>> row = numbers(v[r], key + "[" + std::to_string(r) + "]", cols);
      if (!row) return row.error();
      for (std::size_t c = 0; c < cols; ++c) out[r * cols + c] = (*row)[c];
    }
    return out;
  }
  const std::string& where() const { return where_; }

 private:
  std::string where_;
};

Expected<CameraPose> read_pose(const Reader& in, const json& p) {
  if (!p.is_object()) return in.fail("key 'pose' must be an object");
  if (Status s = in.only_keys(
          p, {"q_wxyz", "t", "R", "center", "cam_to_world", "eye", "target", "up", "axes"},
          "the pose");
      !s) {
    return s.error();
  }
  CameraAxes axes = CameraAxes::kOpenCV;
  if (p.contains("axes")) {
    const json& a = p["axes"];
    if (!a.is_string() || (a != "opencv" && a != "opengl")) {
      return in.fail("key 'axes' must be \"opencv\" or \"opengl\"");
    }
    axes = a == "opengl" ? CameraAxes::kOpenGL : CameraAxes::kOpenCV;
  }
  auto has = [&](const char* k) { return p.contains(k); };
  const std::string what = in.where() + ": key 'pose'";
  auto need = [&](std::initializer_list<const char*> keys) -> Status {
    for (const char* k : keys) {
      if (!has(k)) return in.fail("the pose needs key '" + std::string(k) + "'");
    }
    for (const auto& [key, value] : p.items()) {
      bool mine = key == "axes";
      for (const char* k : keys) mine = mine || key == k;
      if (!mine)
        return in.fail("key '" + key + "' does not belong to this pose form (one form only)");
    }
    return ok_status();
  };
  auto as_parse = [](Expected<CameraPose> pose) -> Expected<CameraPose> {
    if (!pose) return make_error(ErrorCode::kParse, pose.error().message);
    return pose;
  };
  if (!has("q_wxyz") && !has("center") && !has("R") && !has("cam_to_world") && !has("eye") &&
      !has("target") && !has("up")) {
    return in.fail(
        "the pose needs one of q_wxyz + t, R + t, center + R, cam_to_world, "
        "eye + target + up");
  }
  if (has("q_wxyz")) {
    if (Status s = need({"q_wxyz", "t"}); !s) return s.error();
    Expected<std::vector<double>> q = in.numbers(p["q_wxyz"], "q_wxyz", 4);
    if (!q) return q.error();
    Expected<Vec3> t = in.vec3(p["t"], "t");
    if (!t) return t.error();
    return as_parse(pose_from_quaternion({(*q)[0], (*q)[1], (*q)[2], (*q)[3]}, *t, axes, what));
  }
  if (has("center")) {
    if (Status s = need({"center", "R"}); !s) return s.error();
    Expected<Vec3> c = in.vec3(p["center"], "center");
    if (!c) return c.error();
    Expected<std::array<double, 9>> r = in.matrix<9>(p["R"], "R", 3);
    if (!r) return r.error();
    return as_parse(pose_from_centre(*c, *r, axes, what));
  }
  if (has("R")) {
    if (Status s = need({"R", "t"}); !s) return s.error();
    Expected<std::array<double, 9>> r = in.matrix<9>(p["R"], "R", 3);
    if (!r) return r.error();
    Expected<Vec3> t = in.vec3(p["t"], "t");
    if (!t) return t.error();
    return as_parse(pose_from_rotation(*r, *t, axes, what));
  }
  if (has("cam_to_world")) {
    if (Status s = need({"cam_to_world"}); !s) return s.error();
    Expected<std::array<double, 16>> m = in.matrix<16>(p["cam_to_world"], "cam_to_world", 4);
    if (!m) return m.error();
    return as_parse(pose_from_cam_to_world(*m, axes, what));
  }
  if (Status s = need({"eye", "target", "up"}); !s) return s.error();
  Expected<Vec3> eye = in.vec3(p["eye"], "eye");
  if (!eye) return eye.error();
  Expected<Vec3> target = in.vec3(p["target"], "target");
  if (!target) return target.error();
  Expected<Vec3> up = in.vec3(p["up"], "up");
  if (!up) return up.error();
  return as_parse(pose_from_look_at(*eye, *target, *up, what));
}

Expected<CameraProjector> read_camera(const json& o, const std::string& where, bool with_image) {
  const Reader in(where);
  if (!o.is_object()) return in.fail("a camera must be a JSON object");
  std::set<std::string> keys = {"kind", "model", "width", "height", "params", "pose"};
  if (with_image) keys.insert("image");
  if (Status s = in.only_keys(o, keys, "a camera"); !s) return s.error();
  for (const char* k : {"kind", "model", "width", "height", "params", "pose"}) {
    if (!o.contains(k)) return in.fail("missing key '" + std::string(k) + "'");
  }
  if (o["kind"] != "camera") return in.fail("key 'kind' must be \"camera\"");
  if (!o["model"].is_string()) return in.fail("key 'model' must be a string");
  const std::string name = o["model"].get<std::string>();
  const std::optional<CameraModel> model = camera_model_from_name(name);
  if (!model) {
    return in.fail("key 'model': unknown camera model '" + name +
                   "' (expected SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL, OPENCV, "
                   "FULL_OPENCV or OPENCV_FISHEYE)");
  }
  Expected<int> w = in.size(o["width"], "width");
  if (!w) return w.error();
  Expected<int> h = in.size(o["height"], "height");
  if (!h) return h.error();
  Expected<std::vector<double>> params = in.numbers(o["params"], "params", 0);
  if (!params) return params.error();
  Expected<CameraPose> pose = read_pose(in, o["pose"]);
  if (!pose) return pose.error();
  Expected<CameraProjector> camera =
      CameraProjector::make({*model, *w, *h, std::move(params).value(), *pose});
  if (!camera) return in.fail("key 'params': " + camera.error().message);
  return camera;
}

Expected<std::string> read_text(const std::filesystem::path& path) {
  return read_text_file(path, "a camera list");
}

}  // namespace

Expected<CameraProjector> camera_from_json(std::string_view text, const std::string& source) {
  Expected<json> root = parse_json_object(text, source);
  if (!root) return root.error();
  return read_camera(*root, source, false);
}

Expected<std::vector<CameraListEntry>> read_camera_list(const std::filesystem::path& path) {
  Expected<std::string> text = read_text(path);
  if (!text) return text.error();
  return camera_list_from_json(*text, path.string());
}

Expected<std::vector<CameraListEntry>> camera_list_from_json(std::string_view text,
                                                             const std::string& source) {
  Expected<json> root = parse_json_object(text, source);
  if (!root) return root.error();
  const Reader in(source);
  if (Status s = in.only_keys(*root, {"cameras"}, "a camera list"); !s) return s.error();
  if (!root->contains("cameras") || !(*root)["cameras"].is_array() || (*root)["cameras"].empty()) {
    return in.fail("key 'cameras' must be a non-empty array of cameras");
  }
  std::vector<CameraListEntry> out;
  const json& list = (*root)["cameras"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string where = source + ": cameras[" + std::to_string(i) + "]";
    Expected<CameraProjector> camera = read_camera(list[i], where, true);
    if (!camera) return camera.error();
    if (!list[i].contains("image") || !list[i]["image"].is_string() ||
        list[i]["image"].get<std::string>().empty()) {
      return make_error(ErrorCode::kParse, where + ": key 'image' must name the photo");
    }
    out.push_back({std::move(camera).value(), list[i]["image"].get<std::string>()});
  }
  return out;
}

}  // namespace texbake
