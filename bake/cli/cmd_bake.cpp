// texbake bake MESH --texture IMG --proxy KIND [geometry] [--target vertex|atlas]
//   -o OUT.ply|OUT.obj|OUT.glb [options]   (SPEC sections 3 to 7)
//
// The flags are the library's job options (texbake/job_options.h: one
// table of key, flag, type, default, range, the bakes it applies to and
// help), registered here as they are listed there; what was given becomes
// a Job through job_from_settings, which checks every value and
// combination (exit 2: bad values are rejected, never clamped, and options
// of another bake or target are rejected rather than ignored), and run_job
// runs it (no output an input, outputs writable, read, fit the geometry not
// given, bake, write atomically, report). This file prints what happens:
// a progress bar on a terminal, warnings and the fit's line as they come,
// the error or the summary line.
#include <cstdio>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

#include "bake/cli/commands.h"
#include "bake/cli/progress_bar.h"
#include "texbake/job_options.h"
#include "texbake/texbake.h"

namespace texbake::cli {

namespace {

struct BakeCliOptions {
  std::vector<JobSetting> settings;  // the job options given, as text
  bool quiet = false;
  std::function<void(const std::string&)> on_report;  // CliHooks::on_report
};

// Runs `job` as the command line shows it; returns the exit code.
int run_cli_job(Job& job, const BakeCliOptions& o) {
  ProgressBar bar(!o.quiet && ProgressBar::stderr_is_terminal());
  job.progress = bar.callback();
  job.on_warning = [](const std::string& w) { std::cerr << "texbake: warning: " << w << "\n"; };
  if (!o.quiet) job.on_note = [](const std::string& n) { std::cerr << "texbake: " << n << "\n"; };
  const JobResult result = run_job(job);
  if (!result.ok()) return report_error(*result.error);
  if (o.on_report) o.on_report(result.report);
  if (!o.quiet) {
    std::printf("%s\n", result.summary.c_str());
    std::fflush(stdout);
  }
  return 0;
}

int run_bake(const BakeCliOptions& o) {
  Expected<Job> job = job_from_settings(o.settings);
  if (!job) return report_error(job.error());
  return run_cli_job(*job, o);
}

// Registers one job option on `cmd`: its value is recorded as given.
void add_job_option(CLI::App& cmd, const JobOption& option, BakeCliOptions& o) {
  const std::string key(option.key);
  const std::string help(option.help);
  if (option.flag.empty()) {  // the mesh: the positional MESH
    cmd.add_option_function<std::string>(
           "mesh",
           [&o, key](const std::string& v) {
             o.settings.push_back({key, v});
           },
           help)
        ->required();
    return;
  }
  std::string names(option.flag);
  if (!option.short_flag.empty()) names = std::string(option.short_flag) + "," + names;
  if (option.type == JobOptionType::kFlag) {
    cmd.add_flag_function(
        names,
        [&o, key](std::int64_t) {
          o.settings.push_back({key, "true"});
        },
        help);
    return;
  }
  CLI::Option* added = cmd.add_option_function<std::string>(
      names,
      [&o, key](const std::string& v) {
        o.settings.push_back({key, v});
      },
      help);
  added->type_name(std::string(option.value_name));
  if (option.key == "output") added->required();
}

}  // namespace

RunFunction add_bake_command(CLI::App& app, const CliHooks& hooks) {
  auto o = std::make_shared<BakeCliOptions>();
  o->on_report = hooks.on_report;
  CLI::App* cmd = app.add_subcommand(
      "bake",
      "Bake an image onto a mesh through a proxy shape: per-vertex colours (--target vertex: "
      ".ply, .obj, .glb) or a texture atlas (--target atlas: .obj + .mtl + image, .glb). "
      "Geometry flags not given are fitted to the mesh (as texbake fit) and printed. With "
      "--cameras, calibrated photos take the place of --texture and the proxy, for either "
      "target (--uv generate or mesh for the atlas).");
  for (const JobOption& option : job_options()) add_job_option(*cmd, option, *o);
  cmd->add_flag("-q,--quiet", o->quiet,
                "no progress bar, no fitted-proxy line, no summary (warnings still print)");
  return [o] { return run_bake(*o); };
}

}  // namespace texbake::cli
