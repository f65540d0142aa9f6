// Proxy <-> JSON with nlohmann-json (the only nlohmann user in mesh_io).
#include "mesh_io/proxy_json.h"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <vector>

#include "mapping/proxy_schema.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/camera_json.h"
#include "mesh_io/json_strict.h"
#include "mesh_io/regular_file.h"

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
  std::optional<Error> only_keys(ProxyKind kind) const {
    for (const auto& [key, value] : object_.items()) {
      if (key == "kind") continue;
      if (!find_field(kind, key)) {
        std::string list = "kind";
        for (const ParamField& f : proxy_fields(kind)) list += ", " + std::string(f.key);
        return fail("unknown key '" + key + "' for a " + to_string(kind) + " proxy (expected " +
                    list + ")");
      }
    }
    return std::nullopt;
  }

  // The value of `field` as its type; nullopt if the key is absent.
  Expected<std::optional<ParamValue>> value(const ParamField& field) const {
    const std::string key(field.key);
    const json* v = find(key);
    if (!v) return std::optional<ParamValue>{};
    const auto some = [](auto x) -> Expected<std::optional<ParamValue>> {
      if (!x) return x.error();
      return std::optional<ParamValue>{ParamValue{*x}};
    };
    switch (field.type) {
      case ParamType::kVec3:
        return some(to_vector(*v, "key '" + key + "'"));
      case ParamType::kNumber:
        return some(to_number(*v, "key '" + key + "'"));
      case ParamType::kCorners:
        return some(to_corners(*v, key));
    }
    return fail("key '" + key + "' has an unknown type");
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

  Expected<std::array<Vec3, 4>> to_corners(const json& v, const std::string& key) const {
    if (!v.is_array() || v.size() != 4) {
      return fail("key '" + key + "' must be an array of 4 points [x,y,z] (p00, p10, p11, p01)");
    }
    std::array<Vec3, 4> out;
    for (int i = 0; i < 4; ++i) {
      Expected<Vec3> p = to_vector(v[i], "key '" + key + "'[" + std::to_string(i) + "]");
      if (!p) return p.error();
      out[i] = *p;
    }
    return out;
  }

  const json& object_;
  const std::string& source_;
};

// Every field of the kind's table, in its order; all are required but the
// equator (mapping/proxy.h's default).
Expected<ProxyParams> read_params(const ObjectReader& in, ProxyKind kind) {
  if (auto e = in.only_keys(kind)) return *e;
  ProxySpec spec{kind, {}, std::nullopt};
  for (const ParamField& f : proxy_fields(kind)) {
    Expected<std::optional<ParamValue>> value = in.value(f);
    if (!value) return value.error();
    if (*value) {
      spec.values.emplace(f.key, **value);
    } else if (f.role != ParamRole::kEquator) {
      return in.fail("missing key '" + std::string(f.key) + "'");
    }
  }
  // Every field is there with its type: this cannot fail.
  Expected<ProxyParams> params = params_from_spec(spec);
  if (!params) return in.fail(params.error().message);
  return params;
}

json to_json(const ParamValue& value) {
  const auto vector = [](Vec3 v) { return json::array({v.x, v.y, v.z}); };
  if (const double* x = std::get_if<double>(&value)) return *x;
  if (const Vec3* v = std::get_if<Vec3>(&value)) return vector(*v);
  json corners = json::array();
  for (const Vec3& c : std::get<std::array<Vec3, 4>>(value)) corners.push_back(vector(c));
  return corners;
}

// The kind and every field spec_from_params gives (json's std::map orders
// the keys alphabetically on output).
json params_json(const ProxyParams& params) {
  json j;
  j["kind"] = to_string(kind_of(params));
  for (const auto& [key, value] : spec_from_params(params).values) j[key] = to_json(value);
  return j;
}

}  // namespace

Expected<ProxyParams> proxy_params_from_json(std::string_view text, const std::string& source) {
  Expected<json> parsed = parse_json_object(text, source);
  if (!parsed) return parsed.error();
  const json& root = *parsed;
  const ObjectReader in(root, source);
  const auto kind_it = root.find("kind");
  if (kind_it == root.end()) return in.fail("missing key 'kind'");
  if (!kind_it->is_string()) return in.fail("key 'kind' must be a string");
  const std::string kind_name = kind_it->get<std::string>();
  const std::optional<ProxyKind> kind = parse_proxy_kind(kind_name);
  if (kind_name == "camera") {
    return in.fail(
        "key 'kind': a camera is not an analytic proxy (cameras work with map, bake and "
        "render)");
  }
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

namespace {

Expected<std::string> read_proxy_text(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    return make_error(ErrorCode::kIo,
                      "cannot read proxy file " + path.string() + ": it is a folder");
  }
  // A FIFO or a link to /dev/zero would block or be read until memory runs out.
  if (Status s = check_text_file(path, "a proxy file"); !s) return s.error();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    return make_error(ErrorCode::kIo,
                      "cannot read proxy file " + path.string() + ": " + std::strerror(errno));
  }
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return make_error(ErrorCode::kIo, "cannot read proxy file " + path.string());
  return text.str();
}

}  // namespace

Expected<Proxy> read_proxy_file(const std::filesystem::path& path) {
  Expected<std::string> text = read_proxy_text(path);
  if (!text) return text.error();
  return proxy_from_json(*text, path.string());
}

Expected<Projector> projector_from_json(std::string_view text, const std::string& source) {
  Expected<json> parsed = parse_json_object(text, source);
  if (!parsed) return parsed.error();
  const auto kind = parsed->find("kind");
  if (kind != parsed->end() && kind->is_string() && kind->get<std::string>() == "camera") {
    Expected<CameraProjector> camera = camera_from_json(text, source);
    if (!camera) return camera.error();
    return Projector{std::move(camera).value()};
  }
  Expected<Proxy> proxy = proxy_from_json(text, source);
  if (!proxy) return proxy.error();
  return Projector{*proxy};
}

Expected<Projector> read_projector_file(const std::filesystem::path& path) {
  Expected<std::string> text = read_proxy_text(path);
  if (!text) return text.error();
  return projector_from_json(*text, path.string());
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
