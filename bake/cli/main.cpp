// texbake's entry point: parse (CLI11), run one subcommand, map the result to
// the exit codes of SPEC section 5 (bake/cli/app.h has the shared setup).
#include <clocale>

#include "bake/cli/app.h"
#include "mesh_io/atomic_file.h"

int main(int argc, char** argv) {
  using namespace texbake::cli;
  std::setlocale(LC_ALL, "C");  // numbers in and out always use '.'
  // SIGINT/SIGTERM/SIGHUP remove the temporaries of writes in progress.
  texbake::install_signal_cleanup();
  std::unique_ptr<CliApp> cli = make_cli_app();
  if (std::optional<int> code = parse_cli(*cli, argc, argv)) return *code;
  return run_parsed(*cli);
}
