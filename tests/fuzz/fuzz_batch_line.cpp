// libFuzzer target for one line of a batch jobs file (texbake/job_options.h):
// any text is either settings of known keys that job_from_settings turns
// into a job or an error, or an error itself; nothing runs, no file is read
// (a line naming a proxy_file is only parsed).
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "texbake/job_options.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view line(reinterpret_cast<const char*>(data), size);
  const texbake::Expected<std::vector<texbake::JobSetting>> settings =
      texbake::job_settings_from_json(line, "");
  if (!settings) {
    if (settings.error().message.empty()) std::abort();
    return 0;
  }
  for (const texbake::JobSetting& s : *settings) {
    if (!texbake::find_job_option(s.key)) std::abort();  // every key an option
    if (s.key == "proxy_file") return 0;                 // would read the file
  }
  const texbake::Expected<texbake::Job> job = texbake::job_from_settings(*settings);
  if (!job && job.error().message.empty()) std::abort();
  if (job && (job->mesh.empty() || job->output.empty())) std::abort();
  return 0;
}
