#include "bake/cli/layers_target.h"

#include <cstdio>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "bake/cli/commands.h"
#include "bake/cli/file_checks.h"
#include "bake/cli/progress_bar.h"
#include "bake/cli/report.h"
#include "bake/util/timing.h"
#include "mesh_io/atomic_file.h"

namespace texbake::cli {

namespace {

namespace fs = std::filesystem;

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
  nlohmann::ordered_json layers = nlohmann::ordered_json::array();
  for (const LayerStats& s : baked.layers) {
    layers.push_back({{"texture", s.name},
                      {"in_domain", s.in_domain},
                      {"visible", s.visible},
                      {"blended", s.blended},
                      {"mean_alpha", s.mean_alpha}});
  }
  j["layers"] = layers;
  const Timings& t = baked.stats.timings;
  j["timings"] = {{"load", load},     {"scene_build", t.scene_build},
                  {"layers", t.bake}, {"fill", t.fill},
                  {"write", write},   {"total", total}};
  return j.dump(2) + "\n";
}

}  // namespace

int run_layers_bake(const LayersJob& job) {
  const auto start = Clock::now();
  const fs::path output = job.output;
  if (Status s = validate_write(output, job.write, /*atlas=*/false); !s)
    return report_error(s.error());
  {
    const std::vector<NamedFile> read{{"MESH", job.mesh}, {"--layers", job.layers}};
    const std::vector<NamedFile> written{{"-o", output}, {"--report", job.report}};
    if (Status s = check_distinct_files(read, written); !s) return report_error(s.error());
  }
  for (const std::string& p : {job.output, job.report}) {
    if (p.empty()) continue;
    if (Status s = check_writable(p); !s) return report_error(s.error());
  }
  auto stage = Clock::now();
  Expected<LayersSpec> spec = read_layers(job.layers);
  if (!spec) return report_error(spec.error());
  // No layer's image may be overwritten by an output either.
  {
    std::vector<NamedFile> read;
    for (std::size_t i = 0; i < spec->layers.size(); ++i) {
      const std::string key = "layers[" + std::to_string(i) + "]";
      read.push_back({key + ".texture", spec->layers[i].texture.string()});
      read.push_back({key + ".mask", spec->layers[i].mask.string()});
    }
    const std::vector<NamedFile> written{{"-o", output}, {"--report", job.report}};
    if (Status s = check_distinct_files(read, written); !s) return report_error(s.error());
  }
  Expected<LoadedMesh> mesh = read_mesh(job.mesh);
  if (!mesh) return report_error(mesh.error());
  const double load = seconds_since(stage);

  LayersBakeOptions options;
  options.base = spec->base;
  options.base_color = spec->base_color;
  options.occluded = job.occluded;
  options.occluded_color = job.occluded_color;
  ProgressBar bar(!job.quiet && ProgressBar::stderr_is_terminal());
  RunOptions run;
  run.threads = job.threads;
  run.progress = bar.callback();
  Expected<LayerColors> baked = bake_vertex_colors_from_layers(mesh->mesh, *spec, options, run);
  if (!baked) return report_mesh_error(baked.error(), job.mesh);
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
