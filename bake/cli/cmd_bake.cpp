// texbake bake: placeholder until its issue lands.
#include "bake/cli/commands.h"

namespace texbake::cli {

RunFunction add_bake_command(CLI::App& app) {
  app.add_subcommand("bake", "(not implemented yet)");
  return [] { return report_error(ErrorCode::kUnsupported, "'bake' is not implemented yet"); };
}

}  // namespace texbake::cli
