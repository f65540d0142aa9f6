#include "mesh_io/colmap_model.h"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <type_traits>

#include "mesh_io/atomic_file.h"
#include "mesh_io/byte_order.h"
#include "mesh_io/regular_file.h"

namespace texbake {

namespace {

namespace fs = std::filesystem;

// The intrinsics of one COLMAP camera.
struct Intrinsics {
  CameraModel model = CameraModel::kPinhole;
  int width = 0, height = 0;
  std::vector<double> params;
};

Error parse_error(const std::string& where, const std::string& what) {
  return make_error(ErrorCode::kParse, where + ": " + what);
}

// Turns a CameraProjector::make or pose error into one naming the place.
Error located(const std::string& where, const Error& e) {
  return parse_error(where, e.message);
}

Expected<CameraProjector> make_photo_camera(const Intrinsics& in, const std::array<double, 4>& q,
                                            Vec3 t, const std::string& where) {
  Expected<CameraPose> pose = pose_from_quaternion(q, t, CameraAxes::kOpenCV, where);
  // The pose's message already starts with `where`; the file is at fault.
  if (!pose) return make_error(ErrorCode::kParse, pose.error().message);
  Expected<CameraProjector> camera =
      CameraProjector::make({in.model, in.width, in.height, in.params, *pose});
  if (!camera) return located(where, camera.error());
  return camera;
}

// The intrinsics' own checks (CameraProjector::make's: focal lengths,
// principal point, parameters), blamed on the camera's line or record, not
// on the first image that uses it.
Status check_intrinsics(const Intrinsics& in, uint64_t id, const std::string& where) {
  Expected<CameraProjector> camera =
      CameraProjector::make({in.model, in.width, in.height, in.params, CameraPose{}});
  if (!camera)
    return parse_error(where, "camera id " + std::to_string(id) + ": " + camera.error().message);
  return ok_status();
}

// ---- Text ---------------------------------------------------------------

// Calls fn(line_number, line) for every line that is not blank or a comment.
template <class Fn>
Status for_data_lines(const fs::path& path, Fn&& fn) {
  std::ifstream in(path);
  if (!in) return make_error(ErrorCode::kIo, path.string() + ": cannot open");
  std::string line;
  for (std::size_t number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::size_t first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line[first] == '#') continue;
    if (Status s = fn(number, line, first == std::string::npos); !s) return s;
  }
  if (in.bad()) return make_error(ErrorCode::kIo, path.string() + ": read error");
  return ok_status();
}

// A whole token as a number: "12x" or "1e999" are errors.
template <class T>
bool parse_token(const std::string& token, T& out) {
  std::istringstream one(token);
  one >> out;
  return one && one.peek() == std::char_traits<char>::eof() &&
         (!std::is_floating_point_v<T> || std::isfinite(static_cast<double>(out)));
}

// The next whitespace-separated token as a number (parse_token).
template <class T>
bool read_token(std::istringstream& in, T& out) {
  std::string token;
  return (in >> token) && parse_token(token, out);
}

Expected<std::map<uint32_t, Intrinsics>> read_cameras_text(const fs::path& path) {
  std::map<uint32_t, Intrinsics> cameras;
  const std::string file = path.filename().string();
  Status s = for_data_lines(path, [&](std::size_t number, const std::string& line, bool blank) {
    if (blank) return ok_status();
    const std::string where = file + " line " + std::to_string(number);
    std::istringstream in(line);
    uint64_t id = 0;
    std::string model_name;
    int64_t width = 0, height = 0;
    if (!read_token(in, id) || id > UINT32_MAX || !(in >> model_name) || !read_token(in, width) ||
        !read_token(in, height)) {
      return Status(parse_error(where, "expected CAMERA_ID MODEL WIDTH HEIGHT PARAMS..."));
    }
    const std::optional<CameraModel> model = camera_model_from_name(model_name);
    if (!model) return Status(parse_error(where, "unknown camera model " + model_name));
    if (width < 1 || height < 1 || width > INT32_MAX || height > INT32_MAX) {
      return Status(parse_error(where, "the width and height must be positive"));
    }
    Intrinsics cam{*model, static_cast<int>(width), static_cast<int>(height), {}};
    for (std::string token; in >> token;) {
      double v = 0;
      if (!parse_token(token, v)) {
        return Status(parse_error(where, "camera id " + std::to_string(id) +
                                             ": a camera parameter is not a finite number (" +
                                             token + ")"));
      }
      cam.params.push_back(v);
    }
    if (static_cast<int>(cam.params.size()) != camera_param_count(*model)) {
      return Status(
          parse_error(where, model_name + " takes " + std::to_string(camera_param_count(*model)) +
                                 " parameters, got " + std::to_string(cam.params.size())));
    }
    if (Status s = check_intrinsics(cam, id, where); !s) return s;
    if (!cameras.emplace(static_cast<uint32_t>(id), std::move(cam)).second) {
      return Status(parse_error(where, "camera id " + std::to_string(id) + " appears twice"));
    }
    return ok_status();
  });
  if (!s) return s.error();
  return cameras;
}

// A POINTS2D line: X Y POINT3D_ID triples of numbers (none: a blank line).
// Checked so that a file with one line per image (no points lines) is an
// error instead of every second image being skipped.
bool is_points_line(std::string_view line) {
  std::size_t tokens = 0, pos = 0;
  while (true) {
    pos = line.find_first_not_of(" \t", pos);
    if (pos == std::string_view::npos) break;
    std::size_t end = line.find_first_of(" \t", pos);
    if (end == std::string_view::npos) end = line.size();
    double v = 0;
    const auto [ptr, ec] = std::from_chars(line.data() + pos, line.data() + end, v);
    if (ec != std::errc() || ptr != line.data() + end) return false;
    ++tokens;
    pos = end;
  }
  return tokens % 3 == 0;
}

Expected<std::vector<ColmapImage>> read_images_text(const fs::path& path,
                                                    const std::map<uint32_t, Intrinsics>& cameras) {
  std::vector<ColmapImage> images;
  std::map<uint32_t, std::size_t> seen;
  const std::string file = path.filename().string();
  // The line number of the image whose 2D points line comes next (0: none).
  std::size_t points_line_of = 0;
  Status s = for_data_lines(path, [&](std::size_t number, const std::string& line, bool blank) {
    // Each image has a second line, its 2D points, which may be empty.
    if (points_line_of != 0) {
      const std::size_t image_line = points_line_of;
      points_line_of = 0;
      if (!is_points_line(line)) {
        return Status(parse_error(
            file + " line " + std::to_string(number),
            "expected the 2D points of the image on line " + std::to_string(image_line) +
                " (X Y POINT3D_ID triples, possibly none): COLMAP's images.txt has two lines "
                "per image"));
      }
      return ok_status();
    }
    if (blank) return ok_status();
    const std::string where = file + " line " + std::to_string(number);
    std::istringstream in(line);
    uint64_t id = 0, camera_id = 0;
    std::array<double, 4> q{};
    std::array<double, 3> t{};
    bool ok = read_token(in, id) && id <= UINT32_MAX;
    for (double& v : q) ok = ok && read_token(in, v);
    for (double& v : t) ok = ok && read_token(in, v);
    ok = ok && read_token(in, camera_id) && camera_id <= UINT32_MAX;
    std::string name;
    if (ok) {
      std::getline(in >> std::ws, name);
      while (!name.empty() && (name.back() == ' ' || name.back() == '\t')) name.pop_back();
    }
    if (!ok || name.empty()) {
      return Status(parse_error(where, "expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME"));
    }
    const auto cam = cameras.find(static_cast<uint32_t>(camera_id));
    if (cam == cameras.end()) {
      return Status(parse_error(where, "image " + std::to_string(id) + " names camera id " +
                                           std::to_string(camera_id) +
                                           ", which cameras.txt does not define"));
    }
    if (!seen.emplace(static_cast<uint32_t>(id), images.size()).second) {
      return Status(parse_error(where, "image id " + std::to_string(id) + " appears twice"));
    }
    Expected<CameraProjector> camera = make_photo_camera(cam->second, q, {t[0], t[1], t[2]}, where);
    if (!camera) return Status(camera.error());
    images.push_back({static_cast<uint32_t>(id), static_cast<uint32_t>(camera_id), name,
                      std::move(camera).value()});
    points_line_of = number;
    return ok_status();
  });
  if (!s) return s.error();
  return images;
}

// ---- Binary -------------------------------------------------------------

// A little-endian reader streaming a binary model file: only the fields
// read are held, and the 2D points of images.bin (24 bytes each, most of a
// large model: 50 M points are 1.2 GB) are skipped by seeking, so memory
// stays at the images' poses and names whatever the file's size.
class BinaryReader {
 public:
  // The longest image name read (a path; a name without its NUL would
  // otherwise run to the end of the file).
  static constexpr std::size_t kMaxName = 4096;

  static Expected<BinaryReader> open(const fs::path& path) {
    std::error_code ec;
    const uintmax_t size = fs::file_size(path, ec);
    if (ec) {
      return make_error(ErrorCode::kIo, path.string() + ": cannot open (" + ec.message() + ")");
    }
    BinaryReader r(path);
    if (!r.in_) return make_error(ErrorCode::kIo, path.string() + ": cannot open");
    r.size_ = size;
    return r;
  }

  template <class T>
  bool read(T& out) {
    if (remaining() < sizeof(T)) return false;
    char b[sizeof(T)];
    if (!in_.read(b, sizeof(T))) return false;
    std::memcpy(&out, b, sizeof(T));
    pos_ += sizeof(T);
    if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
      if constexpr (std::is_same_v<T, double>) {
        out = std::bit_cast<double>(byte_swap(std::bit_cast<uint64_t>(out)));
      } else {
        out = static_cast<T>(byte_swap(static_cast<std::make_unsigned_t<T>>(out)));
      }
    }
    return true;
  }
  // Up to the NUL; false when the file ends first or the name is longer
  // than kMaxName (then too_long).
  bool read_string(std::string& out, bool& too_long) {
    out.clear();
    too_long = false;
    char c = 0;
    while (pos_ < size_ && in_.get(c)) {
      ++pos_;
      if (c == '\0') return true;
      if (out.size() == kMaxName) {
        too_long = true;
        return false;
      }
      out.push_back(c);
    }
    return false;
  }
  bool skip(uint64_t count, uint64_t size) {
    if (size != 0 && count > remaining() / size) return false;
    pos_ += count * size;
    in_.seekg(static_cast<std::streamoff>(pos_));
    return static_cast<bool>(in_);
  }
  uint64_t remaining() const { return size_ - pos_; }
  Error truncated(uint64_t record) const {
    return parse_error(file_, "truncated in record " + std::to_string(record));
  }

 private:
  explicit BinaryReader(const fs::path& path)
      : file_(path.filename().string()), in_(path, std::ios::binary) {}

  std::string file_;
  std::ifstream in_;
  uint64_t size_ = 0, pos_ = 0;
};

Status check_count(BinaryReader& r, uint64_t count, uint64_t min_record_bytes,
                   const std::string& file) {
  if (min_record_bytes != 0 && count > r.remaining() / min_record_bytes) {
    return parse_error(file, "declares " + std::to_string(count) +
                                 " records, more than the file can hold (truncated?)");
  }
  return ok_status();
}

// Opens a binary model file and reads its record count, which must fit in
// the file at min_record_bytes per record.
Expected<BinaryReader> open_records(const fs::path& path, uint64_t min_record_bytes,
                                    uint64_t& count) {
  Expected<BinaryReader> opened = BinaryReader::open(path);
  if (!opened) return opened.error();
  if (!opened->read(count)) return opened->truncated(0);
  if (Status s = check_count(*opened, count, min_record_bytes, path.filename().string()); !s) {
    return s.error();
  }
  return opened;
}

Status check_end(const BinaryReader& r, const std::string& file) {
  if (r.remaining() != 0) {
    return parse_error(file, std::to_string(r.remaining()) + " bytes after the last record");
  }
  return ok_status();
}

Expected<std::map<uint32_t, Intrinsics>> read_cameras_binary(const fs::path& path) {
  const std::string file = path.filename().string();
  uint64_t count = 0;
  Expected<BinaryReader> opened = open_records(path, 24, count);
  if (!opened) return opened.error();
  BinaryReader& r = *opened;
  std::map<uint32_t, Intrinsics> cameras;
  for (uint64_t k = 1; k <= count; ++k) {
    const std::string where = file + " record " + std::to_string(k);
    uint32_t id = 0;
    int32_t model_id = 0;
    uint64_t width = 0, height = 0;
    if (!r.read(id) || !r.read(model_id) || !r.read(width) || !r.read(height))
      return r.truncated(k);
    const std::optional<CameraModel> model = camera_model_from_id(model_id);
    if (!model) return parse_error(where, "unknown camera model id " + std::to_string(model_id));
    if (width < 1 || height < 1 || width > INT32_MAX || height > INT32_MAX) {
      return parse_error(where, "the width and height must be positive");
    }
    Intrinsics cam{*model, static_cast<int>(width), static_cast<int>(height),
                   std::vector<double>(static_cast<std::size_t>(camera_param_count(*model)))};
    for (double& v : cam.params) {
      if (!r.read(v)) return r.truncated(k);
    }
    if (Status s = check_intrinsics(cam, id, where); !s) return s.error();
    if (!cameras.emplace(id, std::move(cam)).second) {
      return parse_error(where, "camera id " + std::to_string(id) + " appears twice");
    }
  }
  if (Status s = check_end(r, file); !s) return s.error();
  return cameras;
}

Expected<std::vector<ColmapImage>> read_images_binary(
    const fs::path& path, const std::map<uint32_t, Intrinsics>& cameras) {
  const std::string file = path.filename().string();
  uint64_t count = 0;
  Expected<BinaryReader> opened = open_records(path, 72, count);
  if (!opened) return opened.error();
  BinaryReader& r = *opened;
  std::vector<ColmapImage> images;
  std::map<uint32_t, std::size_t> seen;
  for (uint64_t k = 1; k <= count; ++k) {
    const std::string where = file + " record " + std::to_string(k);
    uint32_t id = 0, camera_id = 0;
    std::array<double, 4> q{};
    std::array<double, 3> t{};
    bool ok = r.read(id);
    for (double& v : q) ok = ok && r.read(v);
    for (double& v : t) ok = ok && r.read(v);
    ok = ok && r.read(camera_id);
    std::string name;
    uint64_t points = 0;
    bool too_long = false;
    ok = ok && r.read_string(name, too_long);
    if (too_long) {
      return parse_error(where, "the image name is longer than " +
                                    std::to_string(BinaryReader::kMaxName) +
                                    " bytes (no NUL: not a COLMAP images.bin?)");
    }
    ok = ok && r.read(points) && r.skip(points, 24);
    if (!ok) return r.truncated(k);
    if (name.empty()) return parse_error(where, "the image has no name");
    const auto cam = cameras.find(camera_id);
    if (cam == cameras.end()) {
      return parse_error(where, "image " + std::to_string(id) + " names camera id " +
                                    std::to_string(camera_id) +
                                    ", which cameras.bin does not define");
    }
    if (!seen.emplace(id, images.size()).second) {
      return parse_error(where, "image id " + std::to_string(id) + " appears twice");
    }
    Expected<CameraProjector> camera = make_photo_camera(cam->second, q, {t[0], t[1], t[2]}, where);
    if (!camera) return camera.error();
    images.push_back({id, camera_id, name, std::move(camera).value()});
  }
  if (Status s = check_end(r, file); !s) return s.error();
  return images;
}

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

// The rotation's unit quaternion (w, x, y, z), w >= 0 (Shepperd's method:
// the largest of the four candidates keeps it accurate).
std::array<double, 4> quaternion_of(const std::array<double, 9>& r) {
  const double trace = r[0] + r[4] + r[8];
  std::array<double, 4> q{};
  if (trace > 0) {
    const double s = 2 * std::sqrt(1 + trace);
    q = {s / 4, (r[7] - r[5]) / s, (r[2] - r[6]) / s, (r[3] - r[1]) / s};
  } else if (r[0] > r[4] && r[0] > r[8]) {
    const double s = 2 * std::sqrt(1 + r[0] - r[4] - r[8]);
    q = {(r[7] - r[5]) / s, s / 4, (r[1] + r[3]) / s, (r[2] + r[6]) / s};
  } else if (r[4] > r[8]) {
    const double s = 2 * std::sqrt(1 + r[4] - r[0] - r[8]);
    q = {(r[2] - r[6]) / s, (r[1] + r[3]) / s, s / 4, (r[5] + r[7]) / s};
  } else {
    const double s = 2 * std::sqrt(1 + r[8] - r[0] - r[4]);
    q = {(r[3] - r[1]) / s, (r[2] + r[6]) / s, (r[5] + r[7]) / s, s / 4};
  }
  if (q[0] < 0) {
    for (double& v : q) v = -v;
  }
  const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  for (double& v : q) v /= n;
  return q;
}

// Stages `bytes` as `path` in `set`.
Status stage_file(AtomicFileSet& set, const fs::path& path, const std::string& bytes) {
  return set.stage(path, [&](const fs::path& temp) -> Status {
    std::ofstream out(temp, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) return make_error(ErrorCode::kIo, "cannot write " + path.string());
    return ok_status();
  });
}

template <class T>
void put(std::string& out, T v) {
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    if constexpr (std::is_same_v<T, double>) {
      v = std::bit_cast<double>(byte_swap(std::bit_cast<uint64_t>(v)));
    } else {
      v = static_cast<T>(byte_swap(static_cast<std::make_unsigned_t<T>>(v)));
    }
  }
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

std::string exact(double v) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace

Status write_colmap_model(const fs::path& folder, const std::vector<ColmapImage>& images,
                          bool binary, AtomicFileSet* set, std::span<const Vec3> points) {
  if (!set) {
    AtomicFileSet own;
    if (Status s = write_colmap_model(folder, images, binary, &own, points); !s) return s;
    return own.commit();
  }
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec)
    return make_error(ErrorCode::kIo, "cannot create " + folder.string() + ": " + ec.message());
  // Cameras: one per distinct (model, size, params), numbered from 1.
  std::vector<const CameraSpec*> cameras;
  std::vector<uint32_t> camera_of(images.size());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const CameraSpec& s = images[i].camera.spec();
    std::size_t k = 0;
    while (k < cameras.size() &&
           !(cameras[k]->model == s.model && cameras[k]->width == s.width &&
             cameras[k]->height == s.height && cameras[k]->params == s.params)) {
      ++k;
    }
    if (k == cameras.size()) cameras.push_back(&s);
    camera_of[i] = static_cast<uint32_t>(k + 1);
  }
  std::string cam, img;
  if (binary) {
    put<uint64_t>(cam, cameras.size());
    for (std::size_t k = 0; k < cameras.size(); ++k) {
      put<uint32_t>(cam, static_cast<uint32_t>(k + 1));
      put<int32_t>(cam, camera_model_id(cameras[k]->model));
      put<uint64_t>(cam, static_cast<uint64_t>(cameras[k]->width));
      put<uint64_t>(cam, static_cast<uint64_t>(cameras[k]->height));
      for (double p : cameras[k]->params) put(cam, p);
    }
    put<uint64_t>(img, images.size());
  } else {
    // (A stream, not operator+ chains: GCC 12 warns falsely about those, -Wrestrict.)
    std::ostringstream c;
    c << "# Camera list with one line of data per camera:\n"
         "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
         "# Number of cameras: "
      << cameras.size() << "\n";
    for (std::size_t k = 0; k < cameras.size(); ++k) {
      c << k + 1 << ' ' << camera_model_name(cameras[k]->model) << ' ' << cameras[k]->width << ' '
        << cameras[k]->height;
      for (double p : cameras[k]->params) c << ' ' << exact(p);
      c << '\n';
    }
    cam = c.str();
  }
  std::ostringstream text;
  if (!binary) {
    text << "# Image list with two lines of data per image:\n"
            "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
            "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
            "# Number of images: "
         << images.size() << "\n";
  }
  for (std::size_t i = 0; i < images.size(); ++i) {
    const CameraPose& pose = images[i].camera.spec().pose;
    const std::array<double, 4> q = quaternion_of(pose.r);
    const uint32_t id = images[i].image_id ? images[i].image_id : static_cast<uint32_t>(i + 1);
    if (binary) {
      put<uint32_t>(img, id);
      for (double v : q) put(img, v);
      for (double v : {pose.t.x, pose.t.y, pose.t.z}) put(img, v);
      put<uint32_t>(img, camera_of[i]);
      img.append(images[i].name).push_back('\0');
      put<uint64_t>(img, 0);
    } else {
      text << id;
      for (double v : q) text << ' ' << exact(v);
      for (double v : {pose.t.x, pose.t.y, pose.t.z}) text << ' ' << exact(v);
      text << ' ' << camera_of[i] << ' ' << images[i].name << "\n\n";
    }
  }
  if (!binary) img = text.str();
  // The 3D points given (grey, error 0, no track), or none: an empty
  // points3D file, so that COLMAP itself reads the model and no earlier
  // model's points stay beside these cameras.
  std::string points_file;
  if (binary) {
    put<uint64_t>(points_file, points.size());
    for (std::size_t i = 0; i < points.size(); ++i) {
      put<uint64_t>(points_file, i + 1);
      for (double v : {points[i].x, points[i].y, points[i].z}) put(points_file, v);
      points_file.append(3, static_cast<char>(128));
      put(points_file, 0.0);
      put<uint64_t>(points_file, 0);
    }
  } else {
    std::ostringstream p;
    p << "# 3D point list with one line of data per point:\n"
         "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
         "# Number of points: "
      << points.size() << "\n";
    for (std::size_t i = 0; i < points.size(); ++i) {
      p << i + 1 << ' ' << exact(points[i].x) << ' ' << exact(points[i].y) << ' '
        << exact(points[i].z) << " 128 128 128 0\n";
    }
    points_file = p.str();
  }
  const std::string ext = binary ? ".bin" : ".txt", other = binary ? ".txt" : ".bin";
  for (const char* name : {"cameras", "images", "points3D"}) {
    // The other form's files go with the commit: a reader prefers the
    // binary form, so a stale cameras.bin would win over new text files.
    if (Status s = set->stage_removal(folder / (name + other)); !s) return s;
  }
  if (Status s = stage_file(*set, folder / ("cameras" + ext), cam); !s) return s;
  if (Status s = stage_file(*set, folder / ("points3D" + ext), points_file); !s) return s;
  return stage_file(*set, folder / ("images" + ext), img);
}

Expected<std::vector<ColmapImage>> read_colmap_model(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) {
    return make_error(ErrorCode::kIo, folder.string() + ": no such folder (a COLMAP sparse model)");
  }
  const bool binary = is_file(folder / "cameras.bin") && is_file(folder / "images.bin");
  const bool text = is_file(folder / "cameras.txt") && is_file(folder / "images.txt");
  if (!binary && !text) {
    return make_error(ErrorCode::kIo, folder.string() +
                                          ": no COLMAP model (cameras.txt + images.txt or "
                                          "cameras.bin + images.bin)");
  }
  const fs::path cameras_path = folder / (binary ? "cameras.bin" : "cameras.txt");
  const fs::path images_path = folder / (binary ? "images.bin" : "images.txt");
  for (const fs::path& p : {cameras_path, images_path}) {
    if (Status s = check_regular_file(p, "a COLMAP model file"); !s) return s.error();
  }
  Expected<std::map<uint32_t, Intrinsics>> cameras =
      binary ? read_cameras_binary(cameras_path) : read_cameras_text(cameras_path);
  if (!cameras) return cameras.error();
  Expected<std::vector<ColmapImage>> images =
      binary ? read_images_binary(images_path, *cameras) : read_images_text(images_path, *cameras);
  if (!images) return images.error();
  if (images->empty()) {
    return parse_error(images_path.filename().string(), "the model has no registered image");
  }
  return images;
}

namespace {

// points3D.txt: `POINT3D_ID X Y Z R G B ERROR TRACK[]`; only X Y Z are kept.
Expected<std::vector<Vec3>> read_points_text(const fs::path& path) {
  std::vector<Vec3> points;
  const std::string file = path.filename().string();
  Status s = for_data_lines(path, [&](std::size_t number, const std::string& line, bool blank) {
    if (blank) return ok_status();
    std::istringstream in(line);
    uint64_t id = 0;
    double x = 0, y = 0, z = 0;
    if (!read_token(in, id) || !read_token(in, x) || !read_token(in, y) || !read_token(in, z)) {
      return Status(parse_error(file + " line " + std::to_string(number),
                                "expected POINT3D_ID X Y Z R G B ERROR TRACK[] (finite X Y Z)"));
    }
    points.push_back({x, y, z});
    return ok_status();
  });
  if (!s) return s.error();
  return points;
}

// points3D.bin: u64 count; per point u64 id, 3 doubles, 3 bytes of colour, a
// double error, u64 track length and 8 bytes per track element (skipped).
Expected<std::vector<Vec3>> read_points_binary(const fs::path& path) {
  Expected<BinaryReader> r = BinaryReader::open(path);
  if (!r) return r.error();
  const std::string file = path.filename().string();
  uint64_t count = 0;
  if (!r->read(count)) return r->truncated(0);
  constexpr uint64_t kMinRecord = 8 + 24 + 3 + 8 + 8;
  if (Status s = check_count(*r, count, kMinRecord, file); !s) return s.error();
  std::vector<Vec3> points;
  points.reserve(count);
  for (uint64_t i = 0; i < count; ++i) {
    uint64_t id = 0, track = 0;
    double xyz[3], error = 0;
    uint8_t rgb[3];
    if (!r->read(id) || !r->read(xyz[0]) || !r->read(xyz[1]) || !r->read(xyz[2]) ||
        !r->read(rgb[0]) || !r->read(rgb[1]) || !r->read(rgb[2]) || !r->read(error) ||
        !r->read(track) || !r->skip(track, 8)) {
      return r->truncated(i);
    }
    if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2])) {
      return parse_error(file, "record " + std::to_string(i) + ": a point that is not finite");
    }
    points.push_back({xyz[0], xyz[1], xyz[2]});
  }
  if (r->remaining() != 0) {
    return parse_error(file, "trailing bytes after record " + std::to_string(count));
  }
  return points;
}

}  // namespace

Expected<std::vector<Vec3>> read_colmap_points(const fs::path& folder) {
  const bool binary = is_file(folder / "cameras.bin") && is_file(folder / "images.bin");
  const fs::path path = folder / (binary ? "points3D.bin" : "points3D.txt");
  std::error_code ec;
  if (!fs::exists(path, ec)) return std::vector<Vec3>{};
  if (Status s = check_regular_file(path, "a COLMAP model file"); !s) return s.error();
  return binary ? read_points_binary(path) : read_points_text(path);
}

}  // namespace texbake
