#include "bake/cli/file_checks.h"

#include <iostream>

#include "mesh_io/atomic_file.h"
#include "texbake/job.h"

namespace texbake::cli {

Status check_job_before_work(const JobFileNames& job) {
  if (Status s = check_job_files(job); !s) return s;
  for (const NamedFile& f : job_outputs(job)) {
    if (Status s = check_writable(f.path); !s) return s;
  }
  return ok_status();
}

void warn_image(const Image& image, const std::string& name) {
  for (const std::string& w : image_warnings(image, name)) {
    std::cerr << "texbake: warning: " << w << "\n";
  }
}

}  // namespace texbake::cli
