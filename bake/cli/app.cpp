// The CLI11 app setup shared by main() and the command-line fuzzer. CLI11
// itself exits 100+ on parse errors, so ParseError is caught here and mapped
// to 2 (--help stays 0).
#include "bake/cli/app.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <new>

namespace texbake::cli {

int report_error(const Error& error) {
  std::cerr << "texbake: error: " << error.message << "\n";
  return exit_code(error);
}

int report_error(ErrorCode code, const std::string& message) {
  return report_error(make_error(code, message));
}

int report_mesh_error(const Error& error, const std::string& mesh) {
  if (category(error) != ErrorCategory::kInput || error.message.find(mesh) != std::string::npos) {
    return report_error(error);
  }
  return report_error(make_error(error.code, mesh + ": " + error.message));
}

std::unique_ptr<CliApp> make_cli_app(const CliHooks& hooks) {
  auto cli = std::make_unique<CliApp>();
  CLI::App& app = cli->app;
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("texbake ") + texbake::version());
  auto add = [&](const std::function<RunFunction(CLI::App&)>& adder) {
    const std::size_t before = app.get_subcommands({}).size();
    RunFunction run = adder(app);
    cli->runs[app.get_subcommands({})[before]] = std::move(run);
  };
  add([&](CLI::App& a) { return add_bake_command(a, hooks); });
  add(add_fit_command);
  add(add_map_command);
  add(add_render_command);
  add(add_compare_command);
  add(add_info_command);
  add(add_batch_command);
  add(add_cameras_command);
  return cli;
}

std::optional<int> parse_cli(CliApp& cli, int argc, const char* const* argv) {
  try {
    cli.app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return cli.app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return cli.app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return cli.app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "texbake: error: " << e.what() << "\n";
    std::cerr << "Run 'texbake --help' or 'texbake <command> --help' for usage.\n";
    return 2;
  }
  if (!parsed_subcommand(cli)) return 2;
  return std::nullopt;
}

const CLI::App* parsed_subcommand(const CliApp& cli) {
  for (const CLI::App* sub : cli.app.get_subcommands()) {
    if (cli.runs.count(sub)) return sub;
  }
  return nullptr;
}

int run_parsed(CliApp& cli) {
  const CLI::App* sub = parsed_subcommand(cli);
  if (!sub) return 2;
  try {
    const int code = cli.runs.at(sub)();
    // Results printed to a full or closed stdout are lost: that is a failure
    // (map, fit and info print their results; issue #12).
    std::cout.flush();
    if (std::fflush(stdout) != 0 || std::ferror(stdout) || !std::cout) {
      const int err = errno;
      if (code == 0) {
        return report_error(
            texbake::ErrorCode::kIo,
            std::string("cannot write to standard output (") + std::strerror(err) + ")");
      }
    }
    return code;
  } catch (const std::bad_alloc&) {
    return report_error(texbake::ErrorCode::kInternal, "out of memory");
  } catch (const std::exception& e) {
    return report_error(texbake::ErrorCode::kInternal,
                        std::string("unexpected failure: ") + e.what());
  }
}

}  // namespace texbake::cli
