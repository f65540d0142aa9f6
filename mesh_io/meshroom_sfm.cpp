#include "mesh_io/meshroom_sfm.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <optional>

#include "mesh_io/camera_format_text.h"
#include "mesh_io/json_strict.h"

namespace texbake {

namespace {

using nlohmann::json;

using camera_text::fail;
using camera_text::show;

// A number as AliceVision writes it: a JSON string holding it (boost's
// property tree), or a JSON number.
std::optional<double> as_number(const json& v) {
  if (v.is_number()) return v.get<double>();
  if (!v.is_string()) return std::nullopt;
  const std::string& s = v.get_ref<const std::string&>();
  double d = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), d);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size() || !std::isfinite(d)) {
    return std::nullopt;
  }
  return d;
}

Expected<double> number(const json& obj, const std::string& key, const std::string& where) {
  if (!obj.contains(key)) return fail(where, "missing key '" + key + "'");
  const std::optional<double> d = as_number(obj[key]);
  if (!d) return fail(where, "key '" + key + "' must be a finite number, not " + obj[key].dump());
  return *d;
}

Expected<double> number_or(const json& obj, const std::string& key, double fallback,
                           const std::string& where) {
  if (!obj.contains(key)) return fallback;
  return number(obj, key, where);
}

template <std::size_t N>
Expected<std::array<double, N>> numbers(const json& obj, const std::string& key,
                                        const std::string& where) {
  if (!obj.contains(key)) return fail(where, "missing key '" + key + "'");
  const json& v = obj[key];
  const Error bad = fail(where, "key '" + key + "' must be an array of " + std::to_string(N) +
                                    " numbers, not " + v.dump());
  if (!v.is_array() || v.size() != N) return bad;
  std::array<double, N> out{};
  for (std::size_t i = 0; i < N; ++i) {
    const std::optional<double> d = as_number(v[i]);
    if (!d) return bad;
    out[i] = *d;
  }
  return out;
}

// An id (intrinsicId, poseId, viewId): a whole number >= 0, as number or
// string; nullopt when the key is absent.
Expected<std::optional<unsigned long long>> id(const json& obj, const std::string& key,
                                               const std::string& where) {
  if (!obj.contains(key)) return std::optional<unsigned long long>();
  const json& v = obj[key];
  std::string s;
  if (v.is_number_unsigned()) return std::optional<unsigned long long>(v.get<unsigned long long>());
  if (v.is_string()) s = v.get<std::string>();
  unsigned long long n = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), n);
  if (s.empty() || ec != std::errc() || ptr != s.data() + s.size()) {
    return fail(where, "key '" + key + "' must be a whole number (an id), not " + v.dump());
  }
  return std::optional<unsigned long long>(n);
}

Expected<std::string> text(const json& obj, const std::string& key, const std::string& where) {
  if (!obj.contains(key)) return fail(where, "missing key '" + key + "'");
  if (!obj[key].is_string()) return fail(where, "key '" + key + "' must be a string");
  return obj[key].get<std::string>();
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// [major, minor, revision], compared as a whole.
using Version = std::array<int, 3>;
constexpr Version kNewestVersion = {1, 2, 11};

std::string show(const Version& v) {
  return std::to_string(v[0]) + "." + std::to_string(v[1]) + "." + std::to_string(v[2]);
}

Expected<Version> read_version(const json& root, const std::string& source) {
  if (!root.contains("version")) {
    return fail(source,
                "missing key 'version' (AliceVision requires it: [major, minor, revision])");
  }
  Expected<std::array<double, 3>> v = numbers<3>(root, "version", source);
  if (!v) return v.error();
  Version out{};
  for (int i = 0; i < 3; ++i) {
    const double d = (*v)[i];
    if (!(d >= 0 && d <= 1000 && d == std::floor(d))) {
      return fail(source, "key 'version' must hold 3 whole numbers");
    }
    out[i] = static_cast<int>(d);
  }
  if (out > kNewestVersion) {
    return fail(source, "version " + show(out) + " is newer than the SfMData version " +
                            show(kNewestVersion) +
                            " whose conventions texbake knows (AliceVision refuses newer "
                            "files too)");
  }
  return out;
}

// An intrinsic as one of COLMAP's camera models, exactly (see the header).
Expected<CameraSpec> read_intrinsic(const json& in, const Version& version,
                                    const std::string& where) {
  CameraSpec spec;
  for (const char* key : {"width", "height"}) {
    Expected<double> d = number(in, key, where);
    if (!d) return d.error();
    if (!(*d >= 1 && *d <= (1 << 30) && *d == std::floor(*d))) {
      return fail(where,
                  "key '" + std::string(key) + "' must be a positive whole number of pixels");
    }
    (key[0] == 'w' ? spec.width : spec.height) = static_cast<int>(*d);
  }
  const double w = spec.width, h = spec.height;

  // The camera type and its distortion.
  Expected<std::string> type = text(in, "type", where);
  if (!type) return type.error();
  std::string camera = lower(*type), distortion = "none", undistortion = "none";
  std::string distortion_key = "type";
  if (version < Version{1, 2, 8}) {
    static const std::map<std::string, std::string> kOld = {
        {"pinhole", "none"}, {"radial1", "radialk1"}, {"radial3", "radialk3"},
        {"brown", "brown"},  {"fisheye4", "fisheye"}, {"fisheye1", "fisheye1"}};
    const auto it = kOld.find(camera);
    if (it == kOld.end()) {
      return fail(where, "type '" + *type +
                             "': no COLMAP camera model describes it (pinhole, radial1, "
                             "radial3, brown and fisheye4 are read)");
    }
    distortion = it->second;
    camera = "pinhole";
  } else {
    if (camera != "pinhole") {
      return fail(where, "type '" + *type +
                             "': no COLMAP camera model describes it (pinhole cameras are read)");
    }
    Expected<std::string> d = text(in, "distortionType", where);
    if (!d) return d.error();
    Expected<std::string> u = text(in, "undistortionType", where);
    if (!u) return u.error();
    distortion = lower(*d);
    undistortion = lower(*u);
    distortion_key = "distortionType";
    if (undistortion != "none") {
      return fail(where, "undistortionType '" + *u +
                             "': an undistortion model, which no COLMAP camera model describes");
    }
  }
  static const std::map<std::string, std::size_t> kCounts = {
      {"none", 0}, {"radialk1", 1}, {"radialk3", 3}, {"brown", 5}, {"fisheye", 4}};
  const auto count = kCounts.find(distortion);
  if (count == kCounts.end()) {
    return fail(where, distortion_key + " '" + distortion +
                           "': no COLMAP camera model describes this distortion (radialk1, "
                           "radialk3, brown and fisheye are read)");
  }
  std::vector<double> k;
  if (count->second > 0 || in.contains("distortionParams")) {
    if (!in.contains("distortionParams")) return fail(where, "missing key 'distortionParams'");
    const json& v = in["distortionParams"];
    if (!v.is_array()) return fail(where, "key 'distortionParams' must be an array of numbers");
    for (const json& e : v) {
      const std::optional<double> d = as_number(e);
      if (!d) return fail(where, "key 'distortionParams' holds " + e.dump() + ", not a number");
      k.push_back(*d);
    }
    if (k.size() != count->second) {
      return fail(where, "key 'distortionParams' holds " + std::to_string(k.size()) +
                             " numbers; a " + distortion + " distortion has " +
                             std::to_string(count->second));
    }
  }

  // Focal length in pixels.
  double fx = 0, fy = 0;
  if (version < Version{1, 2, 0}) {
    Expected<double> f = number(in, "pxFocalLength", where);
    if (!f) return f.error();
    fx = fy = *f;
  } else if (version < Version{1, 2, 2}) {
    Expected<std::array<double, 2>> f = numbers<2>(in, "pxFocalLength", where);
    if (!f) return f.error();
    fx = (*f)[0];
    fy = (*f)[1];
  } else {
    Expected<double> fmm = number(in, "focalLength", where);
    if (!fmm) return fmm.error();
    Expected<double> sensor = number_or(in, "sensorWidth", 36.0, where);
    if (!sensor) return sensor.error();
    if (!(*sensor > 0)) return fail(where, "key 'sensorWidth' must be positive");
    Expected<double> ratio = number_or(in, "pixelRatio", 1.0, where);
    if (!ratio) return ratio.error();
    if (!(*ratio > 0)) return fail(where, "key 'pixelRatio' must be positive");
    const double px = w / *sensor;
    if (version < Version{1, 2, 5}) {
      fx = *fmm * px;
      fy = fx / *ratio;
    } else if (version < Version{1, 2, 11}) {
      fx = *fmm * px;
      fy = fx * *ratio;
    } else {
      fx = *fmm / *ratio * px;
      fy = *fmm * px;
    }
  }
  if (!(fx > 0 && fy > 0 && std::isfinite(fx) && std::isfinite(fy))) {
    return fail(where,
                "the focal length in pixels (" + show(fx) + ", " + show(fy) + ") must be positive");
  }

  // Principal point: the offset from the image centre (absolute before
  // 1.2.1), AliceVision's pixel centres at integers -> COLMAP's + 0.5.
  Expected<std::array<double, 2>> pp = numbers<2>(in, "principalPoint", where);
  if (!pp) return pp.error();
  double cx = (*pp)[0] + 0.5, cy = (*pp)[1] + 0.5;
  if (!(version < Version{1, 2, 1})) {
    cx += w / 2;
    cy += h / 2;
  }

  if (distortion == "none") {
    spec.model = CameraModel::kPinhole;
    spec.params = {fx, fy, cx, cy};
  } else if (distortion == "fisheye") {
    spec.model = CameraModel::kOpenCVFisheye;
    spec.params = {fx, fy, cx, cy, k[0], k[1], k[2], k[3]};
  } else {
    const double k1 = k[0], k2 = k.size() > 1 ? k[1] : 0, k3 = k.size() > 2 ? k[2] : 0;
    const double p1 = k.size() > 3 ? k[3] : 0, p2 = k.size() > 4 ? k[4] : 0;
    if (k3 == 0) {
      spec.model = CameraModel::kOpenCV;
      spec.params = {fx, fy, cx, cy, k1, k2, p1, p2};
    } else {
      spec.model = CameraModel::kFullOpenCV;
      spec.params = {fx, fy, cx, cy, k1, k2, p1, p2, k3, 0, 0, 0};
    }
  }
  return spec;
}

}  // namespace

Expected<CameraFile> meshroom_from_json(std::string_view text_in, const std::string& source) {
  Expected<json> parsed = parse_json_object(text_in, source);
  if (!parsed) return parsed.error();
  const json& root = *parsed;
  Expected<Version> version = read_version(root, source);
  if (!version) return version.error();

  // Intrinsics: read when a reconstructed view uses them (an intrinsic no
  // such view uses may be of any kind).
  std::map<unsigned long long, const json*> intrinsics;
  if (root.contains("intrinsics")) {
    if (!root["intrinsics"].is_array()) return fail(source, "key 'intrinsics' must be an array");
    for (std::size_t i = 0; i < root["intrinsics"].size(); ++i) {
      const json& in = root["intrinsics"][i];
      const std::string where = source + ": intrinsics[" + std::to_string(i) + "]";
      if (!in.is_object()) return fail(where, "must be an object");
      Expected<std::optional<unsigned long long>> key = id(in, "intrinsicId", where);
      if (!key) return key.error();
      if (!*key) return fail(where, "missing key 'intrinsicId'");
      if (!intrinsics.emplace(**key, &in).second) {
        return fail(where, "intrinsicId " + std::to_string(**key) + " is given twice");
      }
    }
  }
  std::map<unsigned long long, const json*> poses;
  if (root.contains("poses")) {
    if (!root["poses"].is_array()) return fail(source, "key 'poses' must be an array");
    for (std::size_t i = 0; i < root["poses"].size(); ++i) {
      const json& p = root["poses"][i];
      const std::string where = source + ": poses[" + std::to_string(i) + "]";
      if (!p.is_object()) return fail(where, "must be an object");
      Expected<std::optional<unsigned long long>> key = id(p, "poseId", where);
      if (!key) return key.error();
      if (!*key) return fail(where, "missing key 'poseId'");
      if (!poses.emplace(**key, &p).second) {
        return fail(where, "poseId " + std::to_string(**key) + " is given twice");
      }
    }
  }
  if (!root.contains("views") || !root["views"].is_array()) {
    return fail(source, "key 'views' must be an array (the photos)");
  }

  CameraFile out;
  out.format = CameraFormat::kMeshroom;
  std::map<unsigned long long, CameraSpec> specs;
  std::size_t unposed = 0;
  for (std::size_t i = 0; i < root["views"].size(); ++i) {
    const json& v = root["views"][i];
    std::string where = source + ": views[" + std::to_string(i) + "]";
    if (!v.is_object()) return fail(where, "must be an object");
    Expected<std::optional<unsigned long long>> view_id = id(v, "viewId", where);
    if (!view_id) return view_id.error();
    if (*view_id) where = source + ": view " + std::to_string(**view_id);
    Expected<std::optional<unsigned long long>> pose_id = id(v, "poseId", where);
    if (!pose_id) return pose_id.error();
    const auto pose = *pose_id ? poses.find(**pose_id) : poses.end();
    if (pose == poses.end()) {
      ++unposed;
      continue;
    }
    if (v.contains("rigId")) {
      return fail(where,
                  "key 'rigId': the view belongs to a camera rig, whose poses (the rig's "
                  "composed with a sub-pose) texbake does not read");
    }
    Expected<std::string> path = text(v, "path", where);
    if (!path) return path.error();
    if (path->empty()) return fail(where, "key 'path' is empty (the photo)");

    Expected<std::optional<unsigned long long>> intrinsic_id = id(v, "intrinsicId", where);
    if (!intrinsic_id) return intrinsic_id.error();
    if (!*intrinsic_id) return fail(where, "missing key 'intrinsicId'");
    auto spec = specs.find(**intrinsic_id);
    if (spec == specs.end()) {
      const auto in = intrinsics.find(**intrinsic_id);
      if (in == intrinsics.end()) {
        return fail(where, "intrinsicId " + std::to_string(**intrinsic_id) + " names no intrinsic");
      }
      Expected<CameraSpec> s = read_intrinsic(
          *in->second, *version, source + ": intrinsic " + std::to_string(**intrinsic_id));
      if (!s) return s.error();
      spec = specs.emplace(**intrinsic_id, std::move(s).value()).first;
    }

    const std::string pose_where = source + ": pose " + std::to_string(**pose_id);
    const json& p = *pose->second;
    if (!p.contains("pose") || !p["pose"].is_object() || !p["pose"].contains("transform") ||
        !p["pose"]["transform"].is_object()) {
      return fail(pose_where, "missing key 'pose.transform' (rotation and center)");
    }
    const json& t = p["pose"]["transform"];
    Expected<std::array<double, 9>> columns = numbers<9>(t, "rotation", pose_where);
    if (!columns) return columns.error();
    Expected<std::array<double, 3>> centre = numbers<3>(t, "center", pose_where);
    if (!centre) return centre.error();
    // Column by column -> row by row.
    std::array<double, 9> r{};
    for (int row = 0; row < 3; ++row) {
      for (int col = 0; col < 3; ++col) r[3 * row + col] = (*columns)[3 * col + row];
    }
    Expected<CameraPose> pose_value =
        pose_from_centre({(*centre)[0], (*centre)[1], (*centre)[2]}, r, CameraAxes::kOpenCV,
                         pose_where + ": key 'rotation'");
    if (!pose_value) return make_error(ErrorCode::kParse, pose_value.error().message);
    CameraSpec s = spec->second;
    s.pose = *pose_value;
    Expected<CameraProjector> camera = CameraProjector::make(std::move(s));
    if (!camera) return fail(where, camera.error().message);
    out.cameras.push_back({std::move(camera).value(), *path});
  }
  if (out.cameras.empty()) {
    return fail(source, "no reconstructed view (no view's poseId names a pose)");
  }
  if (unposed) {
    out.notes.push_back(source + ": " + std::to_string(unposed) + " view" +
                        (unposed == 1 ? " is" : "s are") +
                        " not reconstructed (no pose) and left out");
  }
  return out;
}

}  // namespace texbake
