// texbake render: placeholder until its issue lands.
#include "bake/cli/commands.h"

namespace texbake::cli {

RunFunction add_render_command(CLI::App& app) {
  app.add_subcommand("render", "(not implemented yet)");
  return [] { return report_error(ErrorCode::kUnsupported, "'render' is not implemented yet"); };
}

}  // namespace texbake::cli
