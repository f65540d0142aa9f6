// texbake map: placeholder until its issue lands.
#include "bake/cli/commands.h"

namespace texbake::cli {

RunFunction add_map_command(CLI::App& app) {
  app.add_subcommand("map", "(not implemented yet)");
  return [] { return report_error(ErrorCode::kUnsupported, "'map' is not implemented yet"); };
}

}  // namespace texbake::cli
