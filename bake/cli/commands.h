// The texbake subcommands. Each add_* function registers its CLI11
// subcommand on `app` and returns the function that runs it after parsing.
// A run function returns the process exit code (SPEC section 5: 0 success,
// 1 the work failed, 2 usage error) and prints errors as
// "texbake: error: ..." on stderr.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "texbake/job.h"
#include "texbake/texbake.h"

namespace texbake::cli {

using RunFunction = std::function<int()>;

// What a caller that runs the commands in-process (texbake batch) hears
// besides the exit code.
struct CliHooks {
  // Called by a successful `bake` with its report (report_json of
  // texbake/report.h), whether or not --report was given.
  std::function<void(const std::string& report_json)> on_report;
};

RunFunction add_map_command(CLI::App& app);
RunFunction add_bake_command(CLI::App& app, const CliHooks& hooks = {});
RunFunction add_fit_command(CLI::App& app);
RunFunction add_render_command(CLI::App& app);
RunFunction add_compare_command(CLI::App& app);
RunFunction add_info_command(CLI::App& app);
// texbake batch JOBS.jsonl (bake/cli/cmd_batch.cpp): each line's job runs
// through a fresh app of make_cli_app (bake/cli/app.h).
RunFunction add_batch_command(CLI::App& app);
// texbake cameras check (bake/cli/cmd_cameras.cpp).
RunFunction add_cameras_command(CLI::App& app);

// exit_code(error): texbake/job.h's, the one place errors map to exit codes.

// Prints "texbake: error: <message>" to stderr and returns exit_code(error).
int report_error(const Error& error);
int report_error(ErrorCode code, const std::string& message);

// report_error for an error of a call on the mesh read from `mesh`: the
// API's errors about a mesh do not name its file, so a kInput message not
// naming it yet is prefixed "MESH: ".
int report_mesh_error(const Error& error, const std::string& mesh);

}  // namespace texbake::cli
