// texbake compare: placeholder until its issue lands.
#include "bake/cli/commands.h"

namespace texbake::cli {

RunFunction add_compare_command(CLI::App& app) {
  app.add_subcommand("compare", "(not implemented yet)");
  return [] { return report_error(ErrorCode::kUnsupported, "'compare' is not implemented yet"); };
}

}  // namespace texbake::cli
