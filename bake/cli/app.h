// The texbake command line as a value: the CLI11 app with every subcommand
// registered, parsed separately from running, so that main() and the
// command-line fuzzer (tests/fuzz/fuzz_cli.cpp) share one setup.
#pragma once

#include <CLI/CLI.hpp>
#include <map>
#include <memory>
#include <optional>

#include "bake/cli/commands.h"

namespace texbake::cli {

struct CliApp {
  CLI::App app{"texbake: bake 2D images onto 3D meshes through analytic proxy shapes", "texbake"};
  // The run function of each registered subcommand.
  std::map<const CLI::App*, RunFunction> runs;
};

// A fresh app with all subcommands registered (bake, fit, map, render,
// compare, info, batch). Each call gives independent option storage.
// `hooks` go to the commands that take them (bake).
std::unique_ptr<CliApp> make_cli_app(const CliHooks& hooks = {});

// Parses argv (argv[0] is the program name). Returns the exit code when
// parsing ends the run (--help, --version: 0; a usage error: 2, printed as
// "texbake: error: ..."), or nullopt when a subcommand is ready to run.
std::optional<int> parse_cli(CliApp& cli, int argc, const char* const* argv);

// The subcommand chosen by a successful parse_cli (nullptr if none).
const CLI::App* parsed_subcommand(const CliApp& cli);

// Runs the parsed subcommand and returns its exit code; exceptions escaping
// it become errors (out of memory: exit 1; anything else: exit 1, internal).
int run_parsed(CliApp& cli);

}  // namespace texbake::cli
