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

// Prints "texbake: warning: TEXTURE: N NaN or infinite values read as 0"
// when the image had any (mesh_io/image_io.h, Image::nonfinite_values).
void warn_nonfinite(const Image& image, const std::string& name);

// Prints "texbake: warning: TEXTURE: colour space 'X' is neither sRGB nor
// linear: read as linear (float data) (--texture-colorspace sets it)" when
// read_image could not place the file's oiio:ColorSpace
// (Image::unrecognised_color_space).
void warn_color_space(const Image& image, const std::string& name);

}  // namespace texbake::cli
