// texbake's entry point: parse (CLI11), run one subcommand, map the result to
// the exit codes of SPEC section 5. CLI11 itself exits 100+ on parse errors,
// so ParseError is caught here and mapped to 2 (--help stays 0).
#include <clocale>
#include <iostream>
#include <map>

#include "bake/cli/commands.h"

namespace texbake::cli {

int report_error(ErrorCode code, const std::string& message) {
  std::cerr << "texbake: error: " << message << "\n";
  return (code == ErrorCode::kInvalidArgument || code == ErrorCode::kUnsupported) ? 2 : 1;
}

int report_error(const Error& error) { return report_error(error.code, error.message); }

}  // namespace texbake::cli

int main(int argc, char** argv) {
  using namespace texbake::cli;
  std::setlocale(LC_ALL, "C");  // numbers in and out always use '.'

  CLI::App app{"texbake: bake 2D images onto 3D meshes through analytic proxy shapes", "texbake"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "texbake 0.1.0");

  std::map<const CLI::App*, RunFunction> runs;
  auto add = [&](RunFunction (*adder)(CLI::App&)) {
    const std::size_t before = app.get_subcommands({}).size();
    RunFunction run = adder(app);
    runs[app.get_subcommands({})[before]] = std::move(run);
  };
  add(add_bake_command);
  add(add_fit_command);
  add(add_map_command);
  add(add_render_command);
  add(add_compare_command);
  add(add_info_command);

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "texbake: error: " << e.what() << "\n";
    std::cerr << "Run 'texbake --help' or 'texbake <command> --help' for usage.\n";
    return 2;
  }

  for (const CLI::App* sub : app.get_subcommands()) {
    try {
      return runs.at(sub)();
    } catch (const std::bad_alloc&) {
      return report_error(texbake::ErrorCode::kIo, "out of memory");
    } catch (const std::exception& e) {
      return report_error(texbake::ErrorCode::kInternal, std::string("unexpected failure: ") + e.what());
    }
  }
  return 2;
}
