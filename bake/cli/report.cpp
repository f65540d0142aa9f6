#include "bake/cli/report.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "mesh_io/atomic_file.h"
#include "mesh_io/proxy_json.h"

namespace texbake {

namespace {

using nlohmann::ordered_json;

// The proxy as SPEC section 2's JSON object, by the one serialiser of
// mesh_io/proxy_json.h (kept in key order).
ordered_json proxy_json(const ProxyParams& params) {
  return ordered_json::parse(proxy_params_to_json(params));
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

std::string report_json(const BakeReport& r) {
  ordered_json j;
  j["command"] = "bake";
  const bool atlas = r.atlas_counts.has_value();
  j["target"] = atlas ? "atlas" : "vertex";
  ordered_json& inputs = j["inputs"];
  inputs["mesh"] = r.mesh_path;
  inputs["texture"] = r.texture_path;
  inputs["output"] = r.output_path;
  inputs["image"] = {{"width", r.image_width}, {"height", r.image_height}};
  ordered_json& o = inputs["options"];
  if (atlas) {
    o["samples"] = r.atlas_samples;
  } else {
    o["filter"] = name(r.options.filter);
    o["samples"] = r.options.filter == VertexFilter::kArea ? r.options.samples : 1;
  }
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
  j["proxy_fitted"] = r.fitted_flags;
  ordered_json& c = j["counts"];
  c["vertices"] = r.counts.vertices;
  c["triangles"] = r.counts.triangles;
  c["degenerate_skipped"] = r.degenerate_skipped;
  c["unreferenced_vertices"] = r.unreferenced_vertices;
  if (atlas) {
    const AtlasBakeCounts& a = *r.atlas_counts;
    c["texels"] = a.texels;
    c["samples"] = a.samples;
    c["occluded"] = a.occluded;
    c["undefined"] = a.undefined;
    c["outside"] = a.outside;
    c["padded"] = a.padded;
    j["atlas"] = ordered_json::parse(r.atlas_json.empty() ? "{}" : r.atlas_json);
  } else {
    c["samples"] = r.counts.samples;
    c["occluded"] = r.counts.occluded;
    c["undefined"] = r.counts.undefined;
    c["outside"] = r.counts.outside;
    c["filled"] = r.counts.filled;
    c["unfilled"] = r.counts.unfilled;
  }
  ordered_json& t = j["timings"];
  t["load"] = r.timings.load;
  t["fit"] = r.timings.fit;
  if (atlas) {
    t["uv_layout"] = r.timings.uv_layout;
    t["rasterize"] = r.timings.rasterize;
    t["scene_build"] = r.timings.scene_build;
    t["sample"] = r.timings.sample;
    t["fill"] = r.timings.fill;
    t["pad"] = r.timings.pad;
  } else {
    t["scene_build"] = r.timings.scene_build;
    t["bake"] = r.timings.bake;
    t["fill"] = r.timings.fill;
  }
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
