#include "texbake/report.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "bake/atlas/dilate.h"
#include "mesh_io/atomic_file.h"

namespace texbake {

namespace {

using nlohmann::ordered_json;

// The proxy as SPEC section 2's JSON object, by the one serialiser of
// mesh_io/proxy_json.h (kept in key order).
ordered_json proxy_json(const ProxyParams& params) {
  return ordered_json::parse(proxy_params_to_json(params));
}

const char* name(VertexFilter f) {
  if (f == VertexFilter::kEwa) return "ewa";
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

ordered_json atlas_json(const AtlasReport& a, const Stats& stats, double write) {
  const AtlasBakeOptions& o = a.options;
  const Counts& c = stats.counts;
  const Timings& t = stats.timings;
  ordered_json j;
  j["uv"] = to_string(a.uv.used);
  j["size"] = o.size;
  j["samples_per_texel"] = o.samples;
  if (o.padding == kPaddingInfinite) {
    j["padding"] = "inf";
  } else {
    j["padding"] = o.padding == kPaddingDefault ? default_padding(o.size) : o.padding;
  }
  j["counts"] = {
      {"texels", c.texels},     {"samples", c.samples},     {"border_samples", c.border_samples},
      {"occluded", c.occluded}, {"undefined", c.undefined}, {"outside", c.outside},
      {"padded", c.padded}};
  if (a.uv.used == UvLayout::kMesh) {
    j["uv_check"] = {{"corners_outside", a.uv.corners_outside},
                     {"overlap_texels", a.uv.overlap_texels}};
  } else if (a.uv.used == UvLayout::kProxy) {
    j["uv_check"] = {{"overlap_texels", a.uv.overlap_texels}};
    j["cut_triangles"] = a.uv.cut_triangles;
  } else {
    j["charts"] = a.uv.charts;
    j["utilisation"] = a.uv.utilisation;
    j["stretch_l2"] = a.uv.stretch_l2;
  }
  j["timings"] = {{"uv_layout", t.uv_layout},
                  {"rasterize", t.rasterize},
                  {"scene_build", t.scene_build},
                  {"sample", t.bake},
                  {"fill", t.fill},
                  {"pad", t.pad},
                  {"write", write}};
  return j;
}

ordered_json counts_json(ReportSource source, bool atlas, const Counts& c) {
  ordered_json j = {{"vertices", c.vertices}, {"triangles", c.triangles}};
  if (source == ReportSource::kProxy) {
    j["degenerate_skipped"] = c.degenerate_triangles;
    j["unreferenced_vertices"] = c.unreferenced_vertices;
    if (atlas) j["texels"] = c.texels;
    j["samples"] = c.samples;
    j["occluded"] = c.occluded;
    j["undefined"] = c.undefined;
    j["outside"] = c.outside;
    if (atlas) {
      j["padded"] = c.padded;
    } else {
      j["filled"] = c.filled;
      j["unfilled"] = c.unfilled;
    }
  } else if (source == ReportSource::kPhotos && !atlas) {
    j["camera_samples"] = c.samples;
    j["unseen"] = c.occluded;
    j["filled"] = c.filled;
    j["unfilled"] = c.unfilled;
  } else if (source == ReportSource::kPhotos) {
    j["texels"] = c.texels;
    j["samples"] = c.samples;
    j["unseen"] = c.occluded;
    j["filled"] = c.filled;
    j["unfilled_vertices"] = c.unfilled;
    j["padded"] = c.padded;
  } else if (!atlas) {
    j["uncovered"] = c.occluded;
    j["filled"] = c.filled;
  } else {
    j["texels"] = c.texels;
    j["samples"] = c.samples;
    j["uncovered"] = c.occluded;
    j["padded"] = c.padded;
  }
  return j;
}

ordered_json stage_timings_json(ReportSource source, bool atlas, const Timings& t,
                                const std::vector<LayerStats>& layers) {
  ordered_json per_layer = ordered_json::array();
  for (const LayerStats& s : layers) per_layer.push_back(s.seconds);
  ordered_json j = ordered_json::object();
  if (atlas) {
    j["uv_layout"] = t.uv_layout;
    j["rasterize"] = t.rasterize;
    if (source == ReportSource::kPhotos) j["vertex_photos"] = t.fill;
    if (source == ReportSource::kLayers) j["fill"] = t.fill;
  }
  j["scene_build"] = t.scene_build;
  const char* bake = source == ReportSource::kPhotos   ? "photos"
                     : source == ReportSource::kLayers ? "layers"
                     : atlas                           ? "sample"
                                                       : "bake";
  j[bake] = t.bake;
  if (source == ReportSource::kLayers) j["per_layer"] = per_layer;
  if (atlas && source == ReportSource::kProxy) j["fill"] = t.fill;
  if (atlas) j["pad"] = t.pad;
  if (!atlas) j["fill"] = t.fill;
  return j;
}

namespace {

// A job's report timings: `first` (load, fit), the stages, write, total.
ordered_json job_timings(ordered_json first, const ordered_json& stages, double write,
                         double total) {
  for (const auto& [key, value] : stages.items()) first[key] = value;
  first["write"] = write;
  first["total"] = total;
  return first;
}

}  // namespace

std::string report_json(const BakeReport& r) {
  ordered_json j;
  j["command"] = "bake";
  const bool atlas = r.atlas.has_value();
  const Counts& counts = r.stats.counts;
  const Timings& timings = r.stats.timings;
  j["target"] = atlas ? "atlas" : "vertex";
  ordered_json& inputs = j["inputs"];
  inputs["mesh"] = r.mesh_path;
  inputs["texture"] = r.texture_path;
  inputs["output"] = r.output_path;
  inputs["image"] = {{"width", r.image_width},
                     {"height", r.image_height},
                     {"cached", r.image_cached},
                     {"mip_levels", r.image_mip_levels}};
  ordered_json& o = inputs["options"];
  if (atlas) {
    o["filter"] = r.options.filter == VertexFilter::kEwa ? "ewa" : "bilinear";
    o["samples"] = r.atlas->options.samples;
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
  j["counts"] = counts_json(ReportSource::kProxy, atlas, counts);
  if (atlas) j["atlas"] = atlas_json(*r.atlas, r.stats, r.write);
  j["timings"] =
      job_timings({{"load", r.load}, {"fit", r.fit}},
                  stage_timings_json(ReportSource::kProxy, atlas, timings, {}), r.write, r.total);
  return j.dump(2) + "\n";
}

Status write_report(const std::filesystem::path& path, const BakeReport& report) {
  return write_report_text(path, report_json(report));
}

Status write_report_text(const std::filesystem::path& path, const std::string& text) {
  return write_atomically(path, [&](const std::filesystem::path& temp) -> Status {
    std::ofstream out(temp, std::ios::binary);
    out << text;
    out.close();
    if (!out) return make_error(ErrorCode::kIo, "cannot write report " + path.string());
    return ok_status();
  });
}

namespace {

const char* blend_name(PhotoBlend b) {
  return b == PhotoBlend::kSoft ? "soft" : b == PhotoBlend::kBest ? "best" : "mean";
}

nlohmann::ordered_json cameras_json(const std::vector<PhotoCameraStats>& cameras) {
  nlohmann::ordered_json cams = nlohmann::ordered_json::array();
  for (const PhotoCameraStats& s : cameras) {
    cams.push_back({{"image", s.name},
                    {"photo", {s.photo_width, s.photo_height}},
                    {"masked", s.masked_share},
                    {"in_view", s.in_view},
                    {"visible", s.visible},
                    {"weight_share", s.weight_share},
                    {"gain", {s.gain[0], s.gain[1], s.gain[2]}},
                    {"shared", s.shared},
                    {"deviation", s.deviation}});
  }
  return cams;
}

// PhotoConsistency: how well the photos agree on the mesh.
nlohmann::ordered_json consistency_json(const PhotoConsistency& c) {
  return {{"vertices", c.vertices},
          {"agreeing", c.agreeing},
          {"median_deviation", c.median_deviation},
          {"gain_ratio", c.gain_ratio}};
}

// The report's "inputs": the cameras and photos folder, or for a camera
// --proxy-file its file and --texture.
nlohmann::ordered_json photo_inputs(const Job& job) {
  nlohmann::ordered_json in = {{"mesh", job.mesh.string()}};
  if (job.photo) {
    in["proxy_file"] = job.proxy_file.string();
    in["texture"] = job.photo->path.string();
  } else {
    in["cameras"] = job.cameras.string();
    in["images"] = job.images.string();
  }
  in["output"] = job.output.string();
  const PhotoBakeOptions& o = job.photo_options;
  in["options"] = {{"blend", blend_name(o.blend)},
                   {"exposure", o.exposure == ExposureMode::kNone ? "none" : "gain"},
                   {"strict_photos", o.strict_photos},
                   {"threads", job.threads}};
  return in;
}

// One entry per layer: its texture (or cameras), in_domain, visible, blended
// (vertices or atlas samples), mean alpha (timings: per_layer).
nlohmann::ordered_json layers_json(const std::vector<LayerStats>& stats) {
  nlohmann::ordered_json layers = nlohmann::ordered_json::array();
  for (const LayerStats& s : stats) {
    layers.push_back({{s.photos ? "cameras" : "texture", s.name},
                      {"in_domain", s.in_domain},
                      {"visible", s.visible},
                      {"blended", s.blended},
                      {"mean_alpha", s.mean_alpha}});
    if (s.photos) layers.back()["photos_skipped"] = skipped_photos_json(s.skipped);
  }
  return layers;
}

}  // namespace

nlohmann::ordered_json skipped_photos_json(const std::vector<SkippedPhoto>& skipped) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const SkippedPhoto& s : skipped) {
    out.push_back({{"image", s.name}, {"path", s.path.string()}, {"reason", s.reason}});
  }
  return out;
}

// The atlas photo bake's --report: inputs, counts (atlas samples), the
// "atlas" object of the proxy atlas's report, one entry per camera (in_view
// and visible count atlas samples), timings.
std::string photo_atlas_report(const Job& job, const PhotoAtlas& baked, double load, double write,
                               double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "atlas";
  j["inputs"] = photo_inputs(job);
  const Stats& st = baked.atlas.stats;
  j["counts"] = counts_json(ReportSource::kPhotos, /*atlas=*/true, st.counts);
  j["atlas"] = atlas_json(AtlasReport{job.atlas.bake, baked.atlas.uv}, st, write);
  j["cameras"] = cameras_json(baked.cameras);
  j["photo_agreement"] = consistency_json(baked.consistency);
  j["photos_skipped"] = skipped_photos_json(baked.skipped);
  j["timings"] =
      job_timings({{"load", load}}, stage_timings_json(ReportSource::kPhotos, true, st.timings, {}),
                  write, total);
  return j.dump(2) + "\n";
}

// The photo bake's --report: inputs, counts, timings and one entry per camera.
std::string photo_report(const Job& job, const PhotoColors& baked, double load, double write,
                         double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "vertex";
  j["inputs"] = photo_inputs(job);
  j["counts"] = counts_json(ReportSource::kPhotos, /*atlas=*/false, baked.stats.counts);
  j["cameras"] = cameras_json(baked.cameras);
  j["photo_agreement"] = consistency_json(baked.consistency);
  j["photos_skipped"] = skipped_photos_json(baked.skipped);
  j["timings"] = job_timings(
      {{"load", load}}, stage_timings_json(ReportSource::kPhotos, false, baked.stats.timings, {}),
      write, total);
  return j.dump(2) + "\n";
}

// The atlas layers bake's --report: inputs, counts (atlas samples), the
// "atlas" object of the proxy atlas's report, one entry per layer (over the
// samples), timings.
std::string layers_atlas_report(const Job& job, const LayerAtlas& baked, double load, double write,
                                double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "atlas";
  j["inputs"] = {{"mesh", job.mesh.string()},
                 {"layers", job.layers.string()},
                 {"output", job.output.string()},
                 {"options", {{"threads", job.threads}}}};
  const Stats& st = baked.atlas.stats;
  j["counts"] = counts_json(ReportSource::kLayers, /*atlas=*/true, st.counts);
  AtlasBakeOptions options = job.atlas.bake;
  options.size = baked.atlas.image.width;
  j["atlas"] = atlas_json(AtlasReport{options, baked.atlas.uv}, st, write);
  j["layers"] = layers_json(baked.layers);
  j["timings"] = job_timings(
      {{"load", load}}, stage_timings_json(ReportSource::kLayers, true, st.timings, baked.layers),
      write, total);
  return j.dump(2) + "\n";
}

// The layers bake's --report: inputs, counts, timings and one entry per layer.
std::string layers_report(const Job& job, const LayerColors& baked, double load, double write,
                          double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "vertex";
  j["inputs"] = {{"mesh", job.mesh.string()},
                 {"layers", job.layers.string()},
                 {"output", job.output.string()},
                 {"options", {{"threads", job.threads}}}};
  j["counts"] = counts_json(ReportSource::kLayers, /*atlas=*/false, baked.stats.counts);
  j["layers"] = layers_json(baked.layers);
  j["timings"] = job_timings(
      {{"load", load}},
      stage_timings_json(ReportSource::kLayers, false, baked.stats.timings, baked.layers), write,
      total);
  return j.dump(2) + "\n";
}

}  // namespace texbake
