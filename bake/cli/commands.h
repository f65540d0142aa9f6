// The texbake subcommands. Each add_* function registers its CLI11
// subcommand on `app` and returns the function that runs it after parsing.
// A run function returns the process exit code (SPEC section 5: 0 success,
// 1 the work failed, 2 usage error) and prints errors as
// "texbake: error: ..." on stderr.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <string>

#include "mapping/error.h"

namespace texbake::cli {

using RunFunction = std::function<int()>;

RunFunction add_map_command(CLI::App& app);
RunFunction add_bake_command(CLI::App& app);
RunFunction add_fit_command(CLI::App& app);
RunFunction add_render_command(CLI::App& app);
RunFunction add_compare_command(CLI::App& app);
RunFunction add_info_command(CLI::App& app);

// Prints "texbake: error: <message>" to stderr and returns the exit code for
// the error's kind (2 for kInvalidArgument/kUnsupported, else 1).
int report_error(const Error& error);
int report_error(ErrorCode code, const std::string& message);

}  // namespace texbake::cli
