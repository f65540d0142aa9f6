#include "bake/cli/layers_target.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "bake/cli/atlas_target.h"
#include "bake/cli/commands.h"
#include "bake/cli/file_checks.h"
#include "bake/cli/photo_target.h"
#include "bake/cli/progress_bar.h"
#include "bake/cli/report.h"
#include "bake/util/timing.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/mesh_texture.h"

namespace texbake::cli {

namespace {

namespace fs = std::filesystem;

// One entry per layer: its texture (or cameras), in_domain, visible, blended
// (vertices or atlas samples), mean alpha (timings: per_layer_seconds).
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

// Seconds per layer (LayerStats::seconds), for the report's timings.
nlohmann::ordered_json per_layer_seconds(const std::vector<LayerStats>& stats) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  for (const LayerStats& s : stats) out.push_back(s.seconds);
  return out;
}

// The atlas layers bake's --report: inputs, counts (atlas samples), the
// "atlas" object of the proxy atlas's report, one entry per layer (over the
// samples), timings.
std::string layers_atlas_report(const LayersJob& job, const LayerAtlas& baked, double load,
                                double write, double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "atlas";
  j["inputs"] = {{"mesh", job.mesh},
                 {"layers", job.layers},
                 {"output", job.output},
                 {"options", {{"threads", job.threads}}}};
  const Stats& st = baked.atlas.stats;
  const Counts& c = st.counts;
  j["counts"] = {{"vertices", c.vertices}, {"triangles", c.triangles}, {"texels", c.texels},
                 {"samples", c.samples},   {"uncovered", c.occluded},  {"padded", c.padded}};
  AtlasBakeOptions options = job.atlas_options.bake;
  options.size = baked.atlas.image.width;
  j["atlas"] = atlas_json(AtlasReport{options, baked.atlas.uv}, st, write);
  j["layers"] = layers_json(baked.layers);
  const Timings& t = st.timings;
  j["timings"] = {{"load", load},     {"uv_layout", t.uv_layout},
                  {"fill", t.fill},   {"scene_build", t.scene_build},
                  {"layers", t.bake}, {"per_layer", per_layer_seconds(baked.layers)},
                  {"pad", t.pad},     {"write", write},
                  {"total", total}};
  return j.dump(2) + "\n";
}

// The layers bake's --report: inputs, counts, timings and one entry per layer.
std::string layers_report(const LayersJob& job, const LayerColors& baked, double load, double write,
                          double total) {
  nlohmann::ordered_json j;
  j["command"] = "bake";
  j["target"] = "vertex";
  j["inputs"] = {{"mesh", job.mesh},
                 {"layers", job.layers},
                 {"output", job.output},
                 {"options", {{"threads", job.threads}}}};
  const Counts& c = baked.stats.counts;
  j["counts"] = {{"vertices", c.vertices},
                 {"triangles", c.triangles},
                 {"uncovered", c.occluded},
                 {"filled", c.filled}};
  j["layers"] = layers_json(baked.layers);
  const Timings& t = baked.stats.timings;
  j["timings"] = {{"load", load},     {"scene_build", t.scene_build},
                  {"layers", t.bake}, {"per_layer", per_layer_seconds(baked.layers)},
                  {"fill", t.fill},   {"write", write},
                  {"total", total}};
  return j.dump(2) + "\n";
}

// Bakes the atlas target and writes it (after run_layers_bake's checks).
int run_layers_atlas(const LayersJob& job, const LayersSpec& spec, const LoadedMesh& mesh,
                     const LayersBakeOptions& options, const RunOptions& run,
                     Clock::time_point start, double load) {
  if (spec.base == LayerBase::kMesh && mesh.mesh.has_texture() &&
      mesh.issues.other_material_primitives > 0) {
    std::cerr << "texbake: warning: " << job.mesh << ": " << mesh.issues.other_material_primitives
              << " primitive(s) use another material: base \"mesh\" is the first material's "
                 "texture ("
              << mesh_texture_label(mesh.mesh) << ") over every triangle\n";
  }
  Expected<LayerAtlas> baked =
      bake_atlas_texture_from_layers(mesh.mesh, spec, options, job.atlas_options, run);
  if (!baked) return report_mesh_error(baked.error(), job.mesh);
  for (const std::string& w : baked->atlas.stats.warnings) {
    std::cerr << "texbake: warning: " << w << "\n";
  }
  std::string written;
  if (int code = write_atlas_outputs(
          job.output, baked->atlas, job.write, job.report,
          [&](double write) {
            return layers_atlas_report(job, *baked, load, write, seconds_since(start));
          },
          job.on_report, written);
      code != 0) {
    return code;
  }
  if (!job.quiet) {
    const Counts& c = baked->atlas.stats.counts;
    std::printf(
        "baked a %dx%d atlas (uv %s, %zu texels, %zu samples, %zu uncovered, %zu padded) from "
        "%zu layers in %.2f s -> %s\n",
        baked->atlas.image.width, baked->atlas.image.height, to_string(baked->atlas.uv.used),
        c.texels, c.samples, c.occluded, c.padded, baked->layers.size(), seconds_since(start),
        written.c_str());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace

int run_layers_bake(const LayersJob& job) {
  const auto start = Clock::now();
  const fs::path output = job.output;
  if (Status s = validate_write(output, job.write, job.atlas); !s) return report_error(s.error());
  // No output may be an input (MESH, the layers file and everything it
  // names) or another output (-o and, for an atlas .obj, its material and
  // image, --report).
  JobFileNames files;
  files.mesh = job.mesh;
  files.layers = job.layers;
  files.output = output;
  files.atlas = job.atlas;
  files.write = job.write;
  files.report = job.report;
  if (Status s = check_job_before_work(files); !s) return report_error(s.error());
  auto stage = Clock::now();
  Expected<LayersSpec> spec = read_layers(job.layers);
  if (!spec) return report_error(spec.error());
  Expected<LoadedMesh> mesh = read_mesh(job.mesh, RunOptions{job.threads, {}});
  if (!mesh) return report_error(mesh.error());
  if (job.atlas && mesh->mesh.has_texture()) {
    // Nor the base texture, named by the mesh.
    const std::vector<NamedFile> read{{"the texture of MESH", mesh->mesh.texture_path}};
    if (Status s = check_distinct_files(read, job_outputs(files)); !s)
      return report_error(s.error());
  }
  const double load = seconds_since(stage);

  LayersBakeOptions options;
  options.base = spec->base;
  options.base_color = spec->base_color;
  options.occluded = job.occluded;
  options.occluded_color = job.occluded_color;
  options.cache_mb = job.cache_mb;
  options.strict_photos = job.strict_photos;
  ProgressBar bar(!job.quiet && ProgressBar::stderr_is_terminal());
  RunOptions run;
  run.threads = job.threads;
  run.progress = bar.callback();
  if (job.atlas) return run_layers_atlas(job, *spec, *mesh, options, run, start, load);
  Expected<LayerColors> baked = bake_vertex_colors_from_layers(mesh->mesh, *spec, options, run);
  if (!baked) return report_mesh_error(baked.error(), job.mesh);
  for (const std::string& w : baked->stats.warnings) std::cerr << "texbake: warning: " << w << "\n";
  stage = Clock::now();
  if (Status s = write_vertex_colors(output, mesh->mesh, baked->colors, job.write); !s) {
    return report_error(s.error());
  }
  const double write = seconds_since(stage);
  const double total = seconds_since(start);
  const std::string report = layers_report(job, *baked, load, write, total);
  if (!job.report.empty()) {
    if (Status s = write_report_text(job.report, report); !s) return report_error(s.error());
  }
  if (job.on_report) job.on_report(report);
  if (!job.quiet) {
    const Counts& c = baked->stats.counts;
    std::printf("baked %zu vertices from %zu layers (%zu uncovered, %zu filled) in %.2f s -> %s\n",
                c.vertices, baked->layers.size(), c.occluded, c.filled, total, job.output.c_str());
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace texbake::cli
