#include "mesh_io/metashape_xml.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <pugixml.hpp>
#include <set>

#include "mesh_io/camera_format_text.h"

namespace texbake {

namespace {

using camera_text::show;

class Reader {
 public:
  Reader(std::string_view text, std::string source) : text_(text), source_(std::move(source)) {}

  // "SOURCE line L: "
  std::string at(const pugi::xml_node& node) const {
    const std::ptrdiff_t offset = node.offset_debug();
    if (offset < 0) return source_;
    const auto end = text_.begin() + std::min<std::ptrdiff_t>(offset, text_.size());
    return source_ + " line " + std::to_string(1 + std::count(text_.begin(), end, '\n'));
  }
  Error fail(const pugi::xml_node& node, const std::string& what) const {
    return make_error(ErrorCode::kParse, at(node) + ": " + what);
  }

  // The numbers of an element's text ("1 0 0 ..."), exactly `count` of them.
  Expected<std::vector<double>> numbers(const pugi::xml_node& node, std::size_t count,
                                        const std::string& what) const {
    std::vector<double> out;
    const std::string_view s = node.text().get();
    std::size_t pos = 0;
    while (true) {
      pos = s.find_first_not_of(" \t\r\n", pos);
      if (pos == std::string_view::npos) break;
      std::size_t end = s.find_first_of(" \t\r\n", pos);
      if (end == std::string_view::npos) end = s.size();
      double v = 0;
      const auto [ptr, ec] = std::from_chars(s.data() + pos, s.data() + end, v);
      if (ec != std::errc() || ptr != s.data() + end || !std::isfinite(v)) {
        return fail(node, what + ": '" + std::string(s.substr(pos, end - pos)) +
                              "' is not a finite number");
      }
      out.push_back(v);
      pos = end;
    }
    if (out.size() != count) {
      return fail(node, what + " must hold " + std::to_string(count) + " number" +
                            (count == 1 ? "" : "s") + ", not " + std::to_string(out.size()));
    }
    return out;
  }
  Expected<double> number(const pugi::xml_node& node, const std::string& what) const {
    Expected<std::vector<double>> v = numbers(node, 1, what);
    if (!v) return v.error();
    return (*v)[0];
  }
  Expected<int> size_attribute(const pugi::xml_node& node, const char* name,
                               const std::string& what) const {
    const pugi::xml_attribute a = node.attribute(name);
    const std::string_view s = a.value();
    long long v = 0;
    const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (!a || ec != std::errc() || ptr != s.data() + s.size() || v < 1 || v > (1 << 30)) {
      return fail(node, what + ": the " + name + " must be a positive whole number of pixels");
    }
    return static_cast<int>(v);
  }

 private:
  std::string_view text_;
  std::string source_;
};

// A sensor's calibration, Agisoft's terms (0 when absent).
struct Calibration {
  bool fisheye = false;
  int width = 0, height = 0;
  std::map<std::string, double> terms;  // f cx cy b1 b2 k1..k4 p1..p4
  double get(const std::string& k) const {
    const auto it = terms.find(k);
    return it == terms.end() ? 0 : it->second;
  }
};

// The sensor's calibration or why it has none usable (the error is given
// only when a camera uses the sensor).
struct Sensor {
  std::optional<Calibration> calibration;
  std::optional<Error> problem;
  std::string where;  // "SOURCE line L: sensor ID"
};

Expected<Calibration> read_calibration(const Reader& in, const pugi::xml_node& sensor,
                                       const std::string& name) {
  const std::string type = sensor.attribute("type").value();
  if (type != "frame" && type != "fisheye" && !type.empty()) {
    return in.fail(sensor, name + ": a " + type +
                               " sensor, which no COLMAP camera model describes (frame and "
                               "fisheye sensors are read)");
  }
  const pugi::xml_node calib = sensor.child("calibration");
  if (!calib) return in.fail(sensor, name + " has no <calibration> (not calibrated)");
  Calibration c;
  c.fisheye = type == "fisheye";
  pugi::xml_node res = calib.child("resolution");
  if (!res) res = sensor.child("resolution");
  if (!res) return in.fail(calib, name + ": no <resolution width height>");
  Expected<int> w = in.size_attribute(res, "width", name + ": <resolution>");
  if (!w) return w.error();
  Expected<int> h = in.size_attribute(res, "height", name + ": <resolution>");
  if (!h) return h.error();
  c.width = *w;
  c.height = *h;
  static const std::set<std::string> kTerms = {"f",  "cx", "cy", "b1", "b2", "k1", "k2",
                                               "k3", "k4", "p1", "p2", "p3", "p4"};
  for (const pugi::xml_node& e : calib.children()) {
    if (e.type() != pugi::node_element) continue;
    const std::string tag = e.name();
    if (tag == "resolution" || tag == "date") continue;
    if (!kTerms.count(tag)) {
      return in.fail(e, name + ": <" + tag +
                            "> is not a term of Agisoft's camera model that texbake knows "
                            "(f, cx, cy, b1, b2, k1..k4, p1..p4)");
    }
    Expected<double> v = in.number(e, name + ": <" + tag + ">");
    if (!v) return v.error();
    if (!c.terms.emplace(tag, *v).second) {
      return in.fail(e, name + ": <" + tag + "> is given twice");
    }
  }
  if (!c.terms.count("f")) return in.fail(calib, name + ": no focal length <f>");
  return c;
}

// Agisoft's model as one of COLMAP's, exactly (see the header), or the term
// that has none.
Expected<CameraSpec> colmap_camera(const Calibration& c, const std::string& name) {
  const auto refuse = [&](const std::string& term, const std::string& why) -> Error {
    return make_error(ErrorCode::kParse,
                      name + ": " + term + " is " + show(c.get(term)) + ": " + why);
  };
  if (c.get("b2") != 0) return refuse("b2", "skew (non-orthogonality) has no COLMAP camera model");
  for (const char* t : {"p3", "p4"}) {
    if (c.get(t) != 0)
      return refuse(t, "higher-order tangential terms have no COLMAP camera model");
  }
  CameraSpec spec;
  spec.width = c.width;
  spec.height = c.height;
  const double fx = c.get("f") + c.get("b1"), fy = c.get("f");
  const double cx = c.width / 2.0 + c.get("cx"), cy = c.height / 2.0 + c.get("cy");
  const double k1 = c.get("k1"), k2 = c.get("k2"), k3 = c.get("k3"), k4 = c.get("k4");
  // Agisoft's p1 multiplies (r^2 + 2x^2) in x', OpenCV's p2 does.
  const double p1 = c.get("p2"), p2 = c.get("p1");
  if (c.fisheye) {
    for (const char* t : {"p1", "p2"}) {
      if (c.get(t) != 0) {
        return refuse(t, "a fisheye camera's tangential terms have no COLMAP camera model");
      }
    }
    spec.model = CameraModel::kOpenCVFisheye;
    spec.params = {fx, fy, cx, cy, k1, k2, k3, k4};
    return spec;
  }
  if (k4 != 0) return refuse("k4", "a radial r^8 term, which no COLMAP camera model has");
  if (k1 == 0 && k2 == 0 && k3 == 0 && p1 == 0 && p2 == 0) {
    spec.model = CameraModel::kPinhole;
    spec.params = {fx, fy, cx, cy};
  } else if (k3 == 0) {
    spec.model = CameraModel::kOpenCV;
    spec.params = {fx, fy, cx, cy, k1, k2, p1, p2};
  } else {
    spec.model = CameraModel::kFullOpenCV;
    spec.params = {fx, fy, cx, cy, k1, k2, p1, p2, k3, 0, 0, 0};
  }
  return spec;
}

// X_world = s R X_chunk + t.
struct Similarity {
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 t{0, 0, 0};
  double s = 1;
  bool identity() const {
    return r == std::array<double, 9>{1, 0, 0, 0, 1, 0, 0, 0, 1} && t.x == 0 && t.y == 0 &&
           t.z == 0 && s == 1;
  }
};

Expected<Similarity> read_similarity(const Reader& in, const pugi::xml_node& node,
                                     const std::string& name) {
  Similarity m;
  if (const pugi::xml_node r = node.child("rotation")) {
    Expected<std::vector<double>> v = in.numbers(r, 9, name + ": <rotation>");
    if (!v) return v.error();
    std::copy(v->begin(), v->end(), m.r.begin());
    Expected<CameraPose> check = pose_from_rotation(m.r, {0, 0, 0}, CameraAxes::kOpenCV,
                                                    in.at(r) + ": " + name + ": <rotation>");
    if (!check) return make_error(ErrorCode::kParse, check.error().message);
  }
  if (const pugi::xml_node t = node.child("translation")) {
    Expected<std::vector<double>> v = in.numbers(t, 3, name + ": <translation>");
    if (!v) return v.error();
    m.t = {(*v)[0], (*v)[1], (*v)[2]};
  }
  if (const pugi::xml_node s = node.child("scale")) {
    Expected<double> v = in.number(s, name + ": <scale>");
    if (!v) return v.error();
    if (!(*v > 0)) return in.fail(s, name + ": <scale> must be positive");
    m.s = *v;
  }
  return m;
}

}  // namespace

Expected<CameraFile> metashape_from_xml(std::string_view text, const std::string& source) {
  pugi::xml_document doc;
  // No parse_eol: the offsets stay those of the text, for line numbers.
  const pugi::xml_parse_result parsed = doc.load_buffer(
      text.data(), text.size(),
      pugi::parse_cdata | pugi::parse_escapes | pugi::parse_wconv_attribute, pugi::encoding_utf8);
  const Reader in(text, source);
  if (!parsed) {
    const auto end = text.begin() + std::min<std::ptrdiff_t>(parsed.offset, text.size());
    return make_error(ErrorCode::kParse,
                      source + " line " + std::to_string(1 + std::count(text.begin(), end, '\n')) +
                          ": not valid XML: " + parsed.description());
  }
  const pugi::xml_node document = doc.child("document");
  if (!document) {
    return make_error(ErrorCode::kParse,
                      source + ": not a Metashape cameras file (no <document> element)");
  }
  const pugi::xml_node chunk = document.child("chunk");
  if (!chunk) return in.fail(document, "no <chunk>");
  if (chunk.next_sibling("chunk")) {
    return in.fail(chunk.next_sibling("chunk"),
                   "more than one <chunk>: export the cameras of one chunk");
  }

  std::map<std::string, Sensor> sensors;
  for (const pugi::xml_node& s : chunk.child("sensors").children("sensor")) {
    const std::string id = s.attribute("id").value();
    const std::string name = "sensor " + id;
    Sensor sensor;
    sensor.where = in.at(s) + ": " + name;
    Expected<Calibration> c = read_calibration(in, s, name);
    if (c) {
      sensor.calibration = *c;
    } else {
      sensor.problem = c.error();
    }
    if (!sensors.emplace(id, std::move(sensor)).second) {
      return in.fail(s, name + " is defined twice");
    }
  }
  std::map<std::string, Similarity> components;
  for (const pugi::xml_node& c : chunk.child("components").children("component")) {
    const pugi::xml_node t = c.child("transform");
    if (!t) continue;
    const std::string name = "component " + std::string(c.attribute("id").value());
    Expected<Similarity> m = read_similarity(in, t, name + ": <transform>");
    if (!m) return m.error();
    components[c.attribute("id").value()] = *m;
  }
  Similarity chunk_transform;
  if (const pugi::xml_node t = chunk.child("transform")) {
    Expected<Similarity> m = read_similarity(in, t, "the chunk's <transform>");
    if (!m) return m.error();
    chunk_transform = *m;
  }

  CameraFile out;
  out.format = CameraFormat::kMetashape;
  std::size_t unaligned = 0;
  bool reframed = false;
  const pugi::xml_node cameras = chunk.child("cameras");
  if (!cameras) return in.fail(chunk, "no <cameras>");
  // Cameras, also inside camera groups.
  for (const pugi::xpath_node& xp : cameras.select_nodes(".//camera")) {
    const pugi::xml_node cam = xp.node();
    const std::string label = cam.attribute("label").value();
    const std::string name =
        "camera " + std::string(cam.attribute("id").value()) + " (" + label + ")";
    const pugi::xml_node transform = cam.child("transform");
    if (!transform) {
      ++unaligned;
      continue;
    }
    if (label.empty()) return in.fail(cam, name + ": no label (the photo's name)");
    const std::string sensor_id = cam.attribute("sensor_id").value();
    const auto sensor = sensors.find(sensor_id);
    if (sensor == sensors.end()) {
      return in.fail(cam, name + ": sensor_id " + sensor_id + " names no <sensor>");
    }
    if (sensor->second.problem) return *sensor->second.problem;
    Expected<CameraSpec> spec = colmap_camera(*sensor->second.calibration, sensor->second.where);
    if (!spec) return spec.error();
    Expected<std::vector<double>> m = in.numbers(transform, 16, name + ": <transform>");
    if (!m) return m.error();
    const auto comp = components.find(cam.attribute("component_id").value());
    const Similarity& world = comp != components.end() ? comp->second : chunk_transform;
    reframed = reframed || !world.identity();
    // Camera-to-world: rotation R R_c, centre s R t_c + t (the scale does
    // not turn the camera).
    std::array<double, 16> c2w{};
    const std::vector<double>& c = *m;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        c2w[4 * i + j] =
            world.r[3 * i] * c[j] + world.r[3 * i + 1] * c[4 + j] + world.r[3 * i + 2] * c[8 + j];
      }
      c2w[4 * i + 3] = world.s * (world.r[3 * i] * c[3] + world.r[3 * i + 1] * c[7] +
                                  world.r[3 * i + 2] * c[11]) +
                       (i == 0   ? world.t.x
                        : i == 1 ? world.t.y
                                 : world.t.z);
    }
    c2w[12] = c[12];
    c2w[13] = c[13];
    c2w[14] = c[14];
    c2w[15] = c[15];
    Expected<CameraPose> pose = pose_from_cam_to_world(
        c2w, CameraAxes::kOpenCV, in.at(transform) + ": " + name + ": <transform>");
    if (!pose) return make_error(ErrorCode::kParse, pose.error().message);
    spec->pose = *pose;
    Expected<CameraProjector> camera = CameraProjector::make(std::move(spec).value());
    if (!camera) return in.fail(cam, name + ": " + camera.error().message);
    out.cameras.push_back({std::move(camera).value(), label});
  }
  if (out.cameras.empty()) return in.fail(cameras, "no aligned camera (none has a <transform>)");
  if (reframed) {
    out.notes.push_back(source +
                        ": the cameras are placed in the chunk's world frame by its (or its "
                        "component's) <transform>, as Metashape exports models");
  }
  if (unaligned) {
    out.notes.push_back(source + ": " + std::to_string(unaligned) + " camera" +
                        (unaligned == 1 ? " is" : "s are") +
                        " not aligned (no <transform>) and left out");
  }
  return out;
}

}  // namespace texbake
