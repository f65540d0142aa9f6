#include "bake/cli/file_checks.h"

#include <iostream>

#include "mesh_io/atomic_file.h"

namespace texbake::cli {

Status check_job_before_work(const JobFileNames& job) {
  if (Status s = check_job_files(job); !s) return s;
  for (const NamedFile& f : job_outputs(job)) {
    if (Status s = check_writable(f.path); !s) return s;
  }
  return ok_status();
}

void warn_nonfinite(const Image& image, const std::string& name) {
  if (image.nonfinite_values > 0) {
    std::cerr << "texbake: warning: " << name << ": " << image.nonfinite_values
              << " NaN or infinite values read as 0\n";
  }
}

void warn_color_space(const Image& image, const std::string& name) {
  if (!image.unrecognised_color_space.empty()) {
    const bool linear = image.color_space == ColorSpace::kLinear;
    std::cerr << "texbake: warning: " << name << ": colour space '"
              << image.unrecognised_color_space << "' is neither sRGB nor linear: read as "
              << (linear ? "linear (float data)" : "sRGB (integer data)")
              << " (--texture-colorspace sets it)\n";
  }
}

}  // namespace texbake::cli
