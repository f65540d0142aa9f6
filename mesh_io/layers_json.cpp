#include "mesh_io/layers_json.h"

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>
#include <variant>

#include "mesh_io/json_strict.h"
#include "mesh_io/proxy_json.h"
#include "mesh_io/regular_file.h"

namespace texbake {

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

Error fail(const std::string& where, const std::string& message) {
  return make_error(ErrorCode::kParse, where + ": " + message);
}

fs::path resolve(const fs::path& folder, const std::string& path) {
  const fs::path p(path);
  return p.is_absolute() ? p : folder / p;
}

Expected<std::string> path_value(const json& v, const std::string& where) {
  if (!v.is_string() || v.get<std::string>().empty()) {
    return fail(where, "must be a non-empty path (a string)");
  }
  return v.get<std::string>();
}

// [r, g, b, a], each a number in [0, 1].
Expected<Rgba> color_value(const json& v, const std::string& where) {
  if (!v.is_array() || v.size() != 4) return fail(where, "must be a colour [r, g, b, a]");
  Rgba c{};
  for (std::size_t i = 0; i < 4; ++i) {
    if (!v[i].is_number() || !(v[i].get<double>() >= 0 && v[i].get<double>() <= 1)) {
      return fail(where, "colour components must be numbers in [0, 1]");
    }
    c[i] = static_cast<float>(v[i].get<double>());
  }
  return c;
}

template <class E>
Expected<E> keyword(const json& v, const std::string& where,
                    std::initializer_list<std::pair<const char*, E>> words) {
  std::string list;
  for (const auto& [name, value] : words) {
    if (v.is_string() && v.get<std::string>() == name) return value;
    list += (list.empty() ? "" : ", ") + std::string("\"") + name + "\"";
  }
  return fail(where, "must be one of " + list);
}

Expected<LayerSpec> read_layer(const json& o, const fs::path& folder, const std::string& where) {
  if (!o.is_object()) return fail(where, "a layer must be a JSON object");
  static const std::set<std::string> keys = {
      "proxy", "proxy_file", "cameras",    "images",  "masks",  "texture", "mask", "opacity",
      "mode",  "angle_fade", "visibility", "outside", "filter", "samples", "wrap"};
  for (const auto& [key, value] : o.items()) {
    if (!keys.count(key)) {
      return fail(where, "unknown key '" + key +
                             "' (expected proxy, proxy_file, cameras, images, masks, texture, "
                             "mask, opacity, mode, angle_fade, visibility, outside, filter, "
                             "samples, wrap)");
    }
  }
  const int projectors = o.contains("proxy") + o.contains("proxy_file") + o.contains("cameras");
  if (projectors != 1) {
    return fail(where, projectors == 0 ? "needs a projector: one of proxy, proxy_file, cameras"
                                       : "has more than one projector (give one of proxy, "
                                         "proxy_file, cameras)");
  }
  LayerSpec layer;
  if (o.contains("proxy")) {
    if (!o["proxy"].is_object()) return fail(where + ".proxy", "must be a proxy object");
    Expected<Projector> p = projector_from_json(o["proxy"].dump(), where + ".proxy");
    if (!p) return p.error();
    layer.projector = std::move(p).value();
  } else if (o.contains("proxy_file")) {
    Expected<std::string> path = path_value(o["proxy_file"], where + ".proxy_file");
    if (!path) return path.error();
    layer.proxy_file = resolve(folder, *path);
    Expected<Projector> p = read_projector_file(layer.proxy_file);
    if (!p) return p.error();
    layer.projector = std::move(p).value();
  } else {
    Expected<std::string> path = path_value(o["cameras"], where + ".cameras");
    if (!path) return path.error();
    layer.cameras = resolve(folder, *path);
  }
  if (o.contains("images")) {
    if (layer.cameras.empty()) return fail(where + ".images", "applies to a cameras layer only");
    Expected<std::string> path = path_value(o["images"], where + ".images");
    if (!path) return path.error();
    layer.images = resolve(folder, *path);
  }
  if (o.contains("masks")) {
    if (layer.cameras.empty()) {
      return fail(where + ".masks",
                  "applies to a cameras layer only (a proxy layer takes \"mask\")");
    }
    Expected<std::string> path = path_value(o["masks"], where + ".masks");
    if (!path) return path.error();
    layer.masks = resolve(folder, *path);
  }
  if (o.contains("texture")) {
    if (!layer.cameras.empty()) {
      return fail(where + ".texture",
                  "does not apply to a cameras layer (its photos are the "
                  "images)");
    }
    Expected<std::string> path = path_value(o["texture"], where + ".texture");
    if (!path) return path.error();
    layer.texture = resolve(folder, *path);
  } else if (layer.cameras.empty()) {
    return fail(where, "missing key 'texture' (the image this layer projects)");
  }
  if (o.contains("mask")) {
    Expected<std::string> path = path_value(o["mask"], where + ".mask");
    if (!path) return path.error();
    layer.mask = resolve(folder, *path);
  }
  if (o.contains("opacity")) {
    const json& v = o["opacity"];
    if (!v.is_number() || !(v.get<double>() >= 0 && v.get<double>() <= 1)) {
      return fail(where + ".opacity", "must be a number in [0, 1]");
    }
    layer.opacity = v.get<double>();
  }
  if (o.contains("mode")) {
    Expected<LayerMode> m = keyword<LayerMode>(o["mode"], where + ".mode",
                                               {{"over", LayerMode::kOver},
                                                {"multiply", LayerMode::kMultiply},
                                                {"add", LayerMode::kAdd},
                                                {"replace", LayerMode::kReplace}});
    if (!m) return m.error();
    layer.mode = *m;
  }
  if (o.contains("angle_fade")) {
    const json& v = o["angle_fade"];
    if (!v.is_array() || v.size() != 2 || !v[0].is_number() || !v[1].is_number()) {
      return fail(where + ".angle_fade", "must be two angles [a0, a1] in degrees");
    }
    const double a0 = v[0].get<double>(), a1 = v[1].get<double>();
    if (!(a0 >= 0 && a0 < a1 && a1 <= 90)) {
      return fail(where + ".angle_fade", "must satisfy 0 <= a0 < a1 <= 90 (degrees)");
    }
    layer.angle_fade = std::array<double, 2>{a0, a1};
  }
  if (o.contains("visibility")) {
    Expected<LayerVisibility> v = keyword<LayerVisibility>(
        o["visibility"], where + ".visibility",
        {{"first", LayerVisibility::kFirst}, {"all", LayerVisibility::kAll}});
    if (!v) return v.error();
    layer.visibility = *v;
  }
  if (o.contains("outside")) {
    const json& v = o["outside"];
    if (v.is_array()) {
      Expected<Rgba> c = color_value(v, where + ".outside");
      if (!c) return c.error();
      layer.outside = LayerOutside::kColor;
      layer.outside_color = *c;
    } else {
      Expected<LayerOutside> k = keyword<LayerOutside>(
          v, where + ".outside",
          {{"transparent", LayerOutside::kTransparent}, {"clamp", LayerOutside::kClamp}});
      if (!k) return fail(where + ".outside", "must be \"transparent\", \"clamp\" or [r, g, b, a]");
      layer.outside = *k;
    }
  }
  if (o.contains("filter")) {
    Expected<LayerFilter> f = keyword<LayerFilter>(o["filter"], where + ".filter",
                                                   {{"bilinear", LayerFilter::kBilinear},
                                                    {"area", LayerFilter::kArea},
                                                    {"ewa", LayerFilter::kEwa}});
    if (!f) return f.error();
    layer.filter = *f;
    if (!layer.cameras.empty() && layer.filter != LayerFilter::kBilinear) {
      return fail(where + ".filter",
                  "a cameras layer takes the photo bake's bilinear lookup (only \"bilinear\" "
                  "applies)");
    }
    if (layer.filter == LayerFilter::kEwa && layer.projector &&
        std::holds_alternative<CameraProjector>(*layer.projector)) {
      return fail(where + ".filter",
                  "\"ewa\" needs an analytic proxy's footprint (a camera takes \"bilinear\" or "
                  "\"area\")");
    }
  }
  if (o.contains("samples")) {
    const json& v = o["samples"];
    if (!v.is_number_integer() || v.get<long long>() < 1 || v.get<long long>() > 65536) {
      return fail(where + ".samples", "must be an integer in 1 .. 65536");
    }
    if (layer.filter != LayerFilter::kArea) {
      return fail(where + ".samples", "applies to \"filter\": \"area\" only");
    }
    layer.samples = static_cast<int>(v.get<long long>());
  }
  if (o.contains("wrap")) {
    Expected<WrapMode> w = keyword<WrapMode>(
        o["wrap"], where + ".wrap", {{"clamp", WrapMode::kClamp}, {"repeat", WrapMode::kRepeat}});
    if (!w) return w.error();
    const Proxy* proxy = layer.projector ? std::get_if<Proxy>(&*layer.projector) : nullptr;
    if (!proxy || !std::holds_alternative<Plane>(*proxy)) {
      return fail(where + ".wrap",
                  "applies to a plane proxy only (the other projectors' wraps are fixed)");
    }
    layer.wrap = *w;
  }
  if (!layer.cameras.empty()) {
    // Several photos have no single (u, v) to put a mask, a clamp or an
    // outside colour through, and a photo shows only what its camera saw.
    if (o.contains("mask")) {
      return fail(where + ".mask",
                  "does not apply to a cameras layer (a mask needs a single projector's "
                  "mapping; give the camera as proxy_file with its photo as texture)");
    }
    if (layer.outside != LayerOutside::kTransparent) {
      return fail(where + ".outside",
                  "a cameras layer is transparent where no photo sees the surface (only "
                  "\"transparent\" applies)");
    }
    if (layer.visibility != LayerVisibility::kFirst) {
      return fail(where + ".visibility",
                  "a cameras layer always tests what each camera sees (only \"first\" "
                  "applies)");
    }
  }
  return layer;
}

}  // namespace

const char* to_string(LayerMode mode) {
  switch (mode) {
    case LayerMode::kOver:
      return "over";
    case LayerMode::kMultiply:
      return "multiply";
    case LayerMode::kAdd:
      return "add";
    case LayerMode::kReplace:
      return "replace";
  }
  return "over";
}

Expected<LayersSpec> layers_from_json(std::string_view text, const fs::path& folder,
                                      const std::string& source) {
  Expected<json> parsed = parse_json_object(text, source);
  if (!parsed) return parsed.error();
  const json& root = *parsed;
  for (const auto& [key, value] : root.items()) {
    if (key != "base" && key != "layers") {
      return fail(source, "unknown key '" + key + "' (expected base, layers)");
    }
  }
  LayersSpec spec;
  spec.source = source;
  if (root.contains("base")) {
    const json& b = root["base"];
    if (b.is_array()) {
      Expected<Rgba> c = color_value(b, source + ": base");
      if (!c) return c.error();
      spec.base = LayerBase::kColor;
      spec.base_color = *c;
    } else if (b.is_string() && b.get<std::string>() == "mesh") {
      spec.base = LayerBase::kMesh;
    } else if (b.is_string() && b.get<std::string>() == "none") {
      spec.base = LayerBase::kNone;
    } else {
      return fail(source + ": base", "must be \"mesh\", \"none\" or a colour [r, g, b, a]");
    }
  }
  if (!root.contains("layers") || !root["layers"].is_array() || root["layers"].empty()) {
    return fail(source, "key 'layers' must be a non-empty array of layers");
  }
  const json& list = root["layers"];
  for (std::size_t i = 0; i < list.size(); ++i) {
    Expected<LayerSpec> layer =
        read_layer(list[i], folder, source + ": layers[" + std::to_string(i) + "]");
    if (!layer) return layer.error();
    spec.layers.push_back(std::move(layer).value());
  }
  return spec;
}

Expected<LayersSpec> read_layers_file(const fs::path& path) {
  if (Status s = check_text_file(path, "a layers file"); !s) return s.error();
  std::ifstream in(path, std::ios::binary);
  if (!in) return make_error(ErrorCode::kIo, "cannot read layers file " + path.string());
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) return make_error(ErrorCode::kIo, "cannot read layers file " + path.string());
  return layers_from_json(text.str(), path.parent_path(), path.string());
}

}  // namespace texbake
