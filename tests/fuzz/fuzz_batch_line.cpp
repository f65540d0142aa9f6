// libFuzzer target for one line of a batch jobs file (bake/cli/batch_job.h):
// any text is either a job whose argv is `texbake bake`, its options as
// --K or --K=VALUE and the mesh after "--", or an error; nothing runs.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "bake/cli/batch_job.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  const texbake::Expected<texbake::cli::BatchJob> job = texbake::cli::parse_batch_line(line, 2);
  if (!job) {
    if (job.error().message.empty()) std::abort();
    return 0;
  }
  const std::vector<std::string>& argv = job->argv;
  if (argv.size() < 3 || argv[0] != "texbake" || argv[1] != "bake") std::abort();
  bool quiet = false;
  for (std::size_t i = 2; i < argv.size(); ++i) {
    if (argv[i] == "--") {
      if (i + 2 != argv.size()) std::abort();  // the mesh alone follows "--"
      break;
    }
    // Every option a long name, never "--help", "--version" or a bare value.
    if (argv[i].rfind("--", 0) != 0 || argv[i].size() < 3) std::abort();
    const std::string name = argv[i].substr(2, argv[i].find('=') - 2);
    if (name == "help" || name == "version" || name == "help-all") std::abort();
    quiet = quiet || argv[i] == "--quiet";
  }
  if (!quiet) std::abort();
  return 0;
}
