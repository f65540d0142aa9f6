// Proxy <-> JSON with nlohmann-json (the only nlohmann user in mesh_io).
#include "mesh_io/proxy_json.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <vector>

#include "mesh_io/atomic_file.h"

namespace texbake {

namespace {

using nlohmann::json;

// Reads the keys of one proxy object; every error names the source and key.
class ObjectReader {
 public:
  ObjectReader(const json& object, const std::string& source) : object_(object), source_(source) {}

  Error fail(const std::string& what) const {
    return make_error(ErrorCode::kParse, source_ + ": " + what);
  }

  // Unknown keys are errors: a typo ("raduis") must not fall back to a default.
  std::optional<Error> only_keys(ProxyKind kind, const std::vector<std::string>& allowed) const {
    for (const auto& [key, value] : object_.items()) {
      if (key == "kind") continue;
      if (std::find(allowed.begin(), allowed.end(), key) == allowed.end()) {
        std::string list = "kind";
        for (const std::string& k : allowed) list += ", " + k;
        return fail("unknown key '" + key + "' for a " + to_string(kind) + " proxy (expected " +
                    list + ")");
      }
    }
    return std::nullopt;
  }

  Expected<double> number(const std::string& key) const {
    const json* v = find(key);
    if (!v) return fail("missing key '" + key + "'");
    return to_number(*v, "key '" + key + "'");
  }

  Expected<Vec3> vector(const std::string& key) const {
    const json* v = find(key);
    if (!v) return fail("missing key '" + key + "'");
    return to_vector(*v, "key '" + key + "'");
  }

  Expected<std::optional<Vec3>> optional_vector(const std::string& key) const {
    const json* v = find(key);
    if (!v) return std::optional<Vec3>{};
    Expected<Vec3> vec = to_vector(*v, "key '" + key + "'");
    if (!vec) return vec.error();
    return std::optional<Vec3>{*vec};
  }

  Expected<std::array<Vec3, 4>> corners(const std::string& key) const {
    const json* v = find(key);
    if (!v) return fail("missing key '" + key + "'");
    if (!v->is_array() || v->size() != 4) {
      return fail("key '" + key + "' must be an array of 4 points [x,y,z] (p00, p10, p11, p01)");
    }
    std::array<Vec3, 4> out;
    for (int i = 0; i < 4; ++i) {
      Expected<Vec3> p = to_vector((*v)[i], "key '" + key + "'[" + std::to_string(i) + "]");
      if (!p) return p.error();
      out[i] = *p;
    }
    return out;
  }

 private:
  const json* find(const std::string& key) const {
    auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }

  Expected<double> to_number(const json& v, const std::string& what) const {
    // Booleans are not numbers in nlohmann; strings like "1" are rejected.
    if (!v.is_number()) return fail(what + " must be a number, not " + v.type_name());
    const double x = v.get<double>();
    // JSON has no NaN/inf literals, but 1e999 parses to inf.
    if (!std::isfinite(x)) return fail(what + " is not a finite number");
    return x;
  }

  Expected<Vec3> to_vector(const json& v, const std::string& what) const {
    if (!v.is_array() || v.size() != 3)
      return fail(what + " must be an array of 3 numbers [x,y,z]");
    double c[3];
    for (int i = 0; i < 3; ++i) {
      Expected<double> x = to_number(v[i], what + "[" + std::to_string(i) + "]");
      if (!x) return x.error();
      c[i] = *x;
    }
    return Vec3{c[0], c[1], c[2]};
  }

  const json& object_;
  const std::string& source_;
};

// Parses `text`, noting the first duplicate key (seen by hand inside each
// object before nlohmann overwrites it) and the last key read (so an error
// inside its value, e.g. a number overflow, can name it).
json parse_tracking_keys(std::string_view text, std::string* duplicate, std::string* last_key) {
  std::vector<std::set<std::string>> keys_per_depth;
  json::parser_callback_t callback = [&](int depth, json::parse_event_t event, json& parsed) {
    const auto d = static_cast<std::size_t>(depth);
    if (keys_per_depth.size() <= d + 1) keys_per_depth.resize(d + 2);
    if (event == json::parse_event_t::object_start) {
      keys_per_depth[d + 1].clear();
    } else if (event == json::parse_event_t::key) {
      *last_key = parsed.get<std::string>();
      if (!keys_per_depth[d].insert(*last_key).second && duplicate->empty()) *duplicate = *last_key;
    }
    return true;
  };
  return json::parse(text.begin(), text.end(), callback);
}

template <class Params, class Fill>
Expected<ProxyParams> read_kind(const ObjectReader& in, ProxyKind kind,
                                const std::vector<std::string>& keys, Fill fill) {
  if (auto e = in.only_keys(kind, keys)) return *e;
  Params p;
  if (auto e = fill(p)) return *e;
  return ProxyParams{p};
}

// Assigns a parsed value or returns its error from the enclosing lambda.
#define TEXBAKE_READ(target, expr)      \
  do {                                  \
    auto value_ = (expr);               \
    if (!value_) return value_.error(); \
    (target) = *value_;                 \
  } while (0)

Expected<ProxyParams> read_params(const ObjectReader& in, ProxyKind kind) {
  using Opt = std::optional<Error>;
  switch (kind) {
    case ProxyKind::kSphere:
      return read_kind<SphereParams>(in, kind, {"center", "radius", "pole", "equator"},
                                     [&](SphereParams& p) -> Opt {
                                       TEXBAKE_READ(p.center, in.vector("center"));
                                       TEXBAKE_READ(p.radius, in.number("radius"));
                                       TEXBAKE_READ(p.pole, in.vector("pole"));
                                       TEXBAKE_READ(p.equator, in.optional_vector("equator"));
                                       return std::nullopt;
                                     });
    case ProxyKind::kCylinder:
      return read_kind<CylinderParams>(in, kind, {"base", "axis", "equator", "radius", "height"},
                                       [&](CylinderParams& p) -> Opt {
                                         TEXBAKE_READ(p.base, in.vector("base"));
                                         TEXBAKE_READ(p.axis, in.vector("axis"));
                                         TEXBAKE_READ(p.equator, in.optional_vector("equator"));
                                         TEXBAKE_READ(p.radius, in.number("radius"));
                                         TEXBAKE_READ(p.height, in.number("height"));
                                         return std::nullopt;
                                       });
    case ProxyKind::kCone:
      return read_kind<ConeParams>(in, kind, {"apex", "axis", "equator", "height", "radius"},
                                   [&](ConeParams& p) -> Opt {
                                     TEXBAKE_READ(p.apex, in.vector("apex"));
                                     TEXBAKE_READ(p.axis, in.vector("axis"));
                                     TEXBAKE_READ(p.equator, in.optional_vector("equator"));
                                     TEXBAKE_READ(p.height, in.number("height"));
                                     TEXBAKE_READ(p.radius, in.number("radius"));
                                     return std::nullopt;
                                   });
    case ProxyKind::kDisk:
      return read_kind<DiskParams>(in, kind, {"center", "normal", "equator", "radius"},
                                   [&](DiskParams& p) -> Opt {
                                     TEXBAKE_READ(p.center, in.vector("center"));
                                     TEXBAKE_READ(p.normal, in.vector("normal"));
                                     TEXBAKE_READ(p.equator, in.optional_vector("equator"));
                                     TEXBAKE_READ(p.radius, in.number("radius"));
                                     return std::nullopt;
                                   });
    case ProxyKind::kQuad:
      return read_kind<QuadParams>(in, kind, {"corners"}, [&](QuadParams& p) -> Opt {
        TEXBAKE_READ(p.corners, in.corners("corners"));
        return std::nullopt;
      });
    case ProxyKind::kPlane:
      return read_kind<PlaneParams>(in, kind, {"origin", "u_axis", "v_axis"},
                                    [&](PlaneParams& p) -> Opt {
                                      TEXBAKE_READ(p.origin, in.vector("origin"));
                                      TEXBAKE_READ(p.u_axis, in.vector("u_axis"));
                                      TEXBAKE_READ(p.v_axis, in.vector("v_axis"));
                                      return std::nullopt;
                                    });
  }
  return in.fail("unknown proxy kind");
}

#undef TEXBAKE_READ

json to_json(Vec3 v) {
  return json::array({v.x, v.y, v.z});
}

json params_json(const ProxyParams& params) {
  json j;
  j["kind"] = to_string(kind_of(params));
  const auto equator = [&j](const std::optional<Vec3>& e) {
    if (e) j["equator"] = to_json(*e);
  };
  std::visit(
      [&](const auto& p) {
        using T = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<T, SphereParams>) {
          j["center"] = to_json(p.center);
          j["radius"] = p.radius;
          j["pole"] = to_json(p.pole);
          equator(p.equator);
        } else if constexpr (std::is_same_v<T, CylinderParams>) {
          j["base"] = to_json(p.base);
          j["axis"] = to_json(p.axis);
          equator(p.equator);
          j["radius"] = p.radius;
          j["height"] = p.height;
        } else if constexpr (std::is_same_v<T, ConeParams>) {
          j["apex"] = to_json(p.apex);
          j["axis"] = to_json(p.axis);
          equator(p.equator);
          j["height"] = p.height;
          j["radius"] = p.radius;
        } else if constexpr (std::is_same_v<T, DiskParams>) {
          j["center"] = to_json(p.center);
          j["normal"] = to_json(p.normal);
          equator(p.equator);
          j["radius"] = p.radius;
        } else if constexpr (std::is_same_v<T, QuadParams>) {
          j["corners"] = json::array();
          for (const Vec3& c : p.corners) j["corners"].push_back(to_json(c));
        } else {
          j["origin"] = to_json(p.origin);
          j["u_axis"] = to_json(p.u_axis);
          j["v_axis"] = to_json(p.v_axis);
        }
      },
      params);
  return j;
}

}  // namespace

Expected<ProxyParams> proxy_params_from_json(std::string_view text, const std::string& source) {
  json root;
  std::string duplicate, last_key;
  try {
    root = parse_tracking_keys(text, &duplicate, &last_key);
  } catch (const json::out_of_range& e) {
    // 406: a number beyond double's range (1e999), which would be infinity.
    return make_error(
        ErrorCode::kParse,
        source + ": key '" + last_key + "' holds a number that is not finite (" + e.what() + ")");
  } catch (const json::exception& e) {
    // e.what() names the line and column: "[json.exception.parse_error.101]
    // parse error at line 3, column 12: ..."
    return make_error(ErrorCode::kParse, source + ": not valid JSON: " + e.what());
  }
  if (!duplicate.empty()) {
    return make_error(ErrorCode::kParse, source + ": duplicate key '" + duplicate + "'");
  }
  if (!root.is_object()) {
    return make_error(ErrorCode::kParse,
                      source + ": expected a JSON object, not " + root.type_name());
  }
  const ObjectReader in(root, source);
  const auto kind_it = root.find("kind");
  if (kind_it == root.end()) return in.fail("missing key 'kind'");
  if (!kind_it->is_string()) return in.fail("key 'kind' must be a string");
  const std::string kind_name = kind_it->get<std::string>();
  const std::optional<ProxyKind> kind = parse_proxy_kind(kind_name);
  if (!kind) {
    return in.fail("key 'kind': unknown proxy kind '" + kind_name +
                   "' (expected sphere, cylinder, cone, disk, quad or plane)");
  }
  return read_params(in, *kind);
}

Expected<Proxy> proxy_from_json(std::string_view text, const std::string& source) {
  Expected<ProxyParams> params = proxy_params_from_json(text, source);
  if (!params) return params.error();
  Expected<Proxy> proxy = make_proxy(*params, ParamNaming::kKey);
  // A geometric error in a file is the file's fault (exit 1), not usage.
  if (!proxy) return make_error(ErrorCode::kParse, source + ": " + proxy.error().message);
  return proxy;
}

Expected<Proxy> read_proxy_file(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return make_error(ErrorCode::kIo,
                      "cannot read proxy file " + path.string() + ": it is a folder");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return make_error(ErrorCode::kIo,
                      "cannot read proxy file " + path.string() + ": " + std::strerror(errno));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return make_error(ErrorCode::kIo, "cannot read proxy file " + path.string());
  return proxy_from_json(text.str(), path.string());
}

std::string proxy_params_to_json(const ProxyParams& params, int indent) {
  return params_json(params).dump(indent);
}

std::string proxy_to_json(const Proxy& proxy, int indent) {
  return proxy_params_to_json(params_of(proxy), indent);
}

Status write_proxy_file(const std::filesystem::path& path, const Proxy& proxy) {
  const std::string text = proxy_to_json(proxy, 2) + "\n";
  return write_atomically(path, [&](const std::filesystem::path& temp) -> Status {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    out.close();
    if (!out) return make_error(ErrorCode::kIo, "cannot write " + path.string());
    return ok_status();
  });
}

}  // namespace texbake
