// texbake info: placeholder until its issue lands.
#include "bake/cli/commands.h"

namespace texbake::cli {

RunFunction add_info_command(CLI::App& app) {
  app.add_subcommand("info", "(not implemented yet)");
  return [] { return report_error(ErrorCode::kUnsupported, "'info' is not implemented yet"); };
}

}  // namespace texbake::cli
