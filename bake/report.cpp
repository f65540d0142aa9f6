#include "bake/report.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "mesh_io/atomic_file.h"

namespace texbake {

namespace {

using nlohmann::ordered_json;

ordered_json vec_json(Vec3 v) {
  return ordered_json::array({v.x, v.y, v.z});
}

// The vector the proxy actually used: make_proxy fills in a missing equator,
// so params_of() output always has one; an absent one is written as null.
ordered_json optional_vec_json(const std::optional<Vec3>& v) {
  return v ? vec_json(*v) : ordered_json(nullptr);
}

ordered_json proxy_json(const ProxyParams& params) {
  return std::visit(
      [](const auto& p) -> ordered_json {
        using T = std::decay_t<decltype(p)>;
        ordered_json j;
        if constexpr (std::is_same_v<T, SphereParams>) {
          j["kind"] = "sphere";
          j["center"] = vec_json(p.center);
          j["radius"] = p.radius;
          j["pole"] = vec_json(p.pole);
          j["equator"] = optional_vec_json(p.equator);
        } else if constexpr (std::is_same_v<T, CylinderParams>) {
          j["kind"] = "cylinder";
          j["base"] = vec_json(p.base);
          j["axis"] = vec_json(p.axis);
          j["equator"] = optional_vec_json(p.equator);
          j["radius"] = p.radius;
          j["height"] = p.height;
        } else if constexpr (std::is_same_v<T, ConeParams>) {
          j["kind"] = "cone";
          j["apex"] = vec_json(p.apex);
          j["axis"] = vec_json(p.axis);
          j["equator"] = optional_vec_json(p.equator);
          j["height"] = p.height;
          j["radius"] = p.radius;
        } else if constexpr (std::is_same_v<T, DiskParams>) {
          j["kind"] = "disk";
          j["center"] = vec_json(p.center);
          j["normal"] = vec_json(p.normal);
          j["equator"] = optional_vec_json(p.equator);
          j["radius"] = p.radius;
        } else if constexpr (std::is_same_v<T, QuadParams>) {
          j["kind"] = "quad";
          j["corners"] = ordered_json::array();
          for (const Vec3& c : p.corners) j["corners"].push_back(vec_json(c));
        } else {
          j["kind"] = "plane";
          j["origin"] = vec_json(p.origin);
          j["u_axis"] = vec_json(p.u_axis);
          j["v_axis"] = vec_json(p.v_axis);
        }
        return j;
      },
      params);
}

const char* name(VertexFilter f) {
  return f == VertexFilter::kArea ? "area" : "bilinear";
}
const char* name(Visibility v) {
  return v == Visibility::kFirst ? "first" : "all";
}
const char* name(WrapMode w) {
  return w == WrapMode::kRepeat ? "repeat" : "clamp";
}

ordered_json color_json(const Rgba& c) {
  return ordered_json::array({c[0], c[1], c[2], c[3]});
}

}  // namespace

std::string proxy_params_json(const ProxyParams& params) {
  return proxy_json(params).dump();
}

std::string report_json(const BakeReport& r) {
  ordered_json j;
  j["command"] = "bake";
  j["target"] = "vertex";
  ordered_json& inputs = j["inputs"];
  inputs["mesh"] = r.mesh_path;
  inputs["texture"] = r.texture_path;
  inputs["output"] = r.output_path;
  inputs["image"] = {{"width", r.image_width}, {"height", r.image_height}};
  ordered_json& o = inputs["options"];
  o["filter"] = name(r.options.filter);
  o["samples"] = r.options.filter == VertexFilter::kArea ? r.options.samples : 1;
  o["visibility"] = name(r.options.visibility);
  switch (r.options.occluded) {
    case OccludedMode::kFill:
      o["occluded"] = "fill";
      break;
    case OccludedMode::kProject:
      o["occluded"] = "project";
      break;
    case OccludedMode::kColor:
      o["occluded"] = color_json(r.options.occluded_color);
      break;
  }
  o["outside"] = r.options.outside == OutsideMode::kClamp ? ordered_json("clamp")
                                                          : color_json(r.options.outside_color);
  o["wrap"] = name(r.options.plane_wrap);
  o["linear"] = r.options.linear;
  o["threads"] = r.threads;
  j["proxy"] = proxy_json(r.proxy);
  ordered_json& c = j["counts"];
  c["vertices"] = r.counts.vertices;
  c["triangles"] = r.counts.triangles;
  c["degenerate_skipped"] = r.degenerate_skipped;
  c["unreferenced_vertices"] = r.unreferenced_vertices;
  c["samples"] = r.counts.samples;
  c["occluded"] = r.counts.occluded;
  c["undefined"] = r.counts.undefined;
  c["outside"] = r.counts.outside;
  c["filled"] = r.counts.filled;
  c["unfilled"] = r.counts.unfilled;
  ordered_json& t = j["timings"];
  t["load"] = r.timings.load;
  t["scene_build"] = r.timings.scene_build;
  t["bake"] = r.timings.bake;
  t["fill"] = r.timings.fill;
  t["write"] = r.timings.write;
  t["total"] = r.timings.total;
  return j.dump(2) + "\n";
}

Status write_report(const std::filesystem::path& path, const BakeReport& report) {
  const std::string text = report_json(report);
  return write_atomically(path, [&](const std::filesystem::path& temp) -> Status {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    out.close();
    if (!out) return make_error(ErrorCode::kIo, "cannot write report " + path.string());
    return ok_status();
  });
}

}  // namespace texbake
