// Checks and warnings about the files a command reads and writes. The rule
// that no output is an input or another output is the library's
// (texbake/texbake.h, check_job_files and job_inputs / job_outputs).
#pragma once

#include <string>

#include "mesh_io/image_io.h"
#include "texbake/texbake.h"

namespace texbake::cli {

// Before any work: check_job_files(job) (an output that is an input or
// another output: kInvalidArgument, exit 2), then every output of
// job_outputs(job) writable (mesh_io/atomic_file.h check_writable: exit 1).
Status check_job_before_work(const JobFileNames& job);

// Prints "texbake: warning: W" for each warning W of image_warnings
// (texbake/job.h: NaN or infinite values read as 0, a colour space read
// as neither sRGB nor linear).
void warn_image(const Image& image, const std::string& name);

}  // namespace texbake::cli
