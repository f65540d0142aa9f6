// texbake fit: placeholder until its issue lands.
#include "bake/cli/commands.h"

namespace texbake::cli {

RunFunction add_fit_command(CLI::App& app) {
  app.add_subcommand("fit", "(not implemented yet)");
  return [] { return report_error(ErrorCode::kUnsupported, "'fit' is not implemented yet"); };
}

}  // namespace texbake::cli
