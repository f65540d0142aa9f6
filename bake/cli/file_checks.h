// Warnings about the files a command reads. The rule that no output is an
// input or another output is the library's (texbake/texbake.h,
// check_distinct_files and job_inputs / job_outputs).
#pragma once

#include <string>

#include "mesh_io/image_io.h"

namespace texbake::cli {

// Prints "texbake: warning: TEXTURE: N NaN or infinite values read as 0"
// when the image had any (mesh_io/image_io.h, Image::nonfinite_values).
void warn_nonfinite(const Image& image, const std::string& name);

// Prints "texbake: warning: TEXTURE: colour space 'X' is neither sRGB nor
// linear: read as linear (float data) (--texture-colorspace sets it)" when
// read_image could not place the file's oiio:ColorSpace
// (Image::unrecognised_color_space).
void warn_color_space(const Image& image, const std::string& name);

}  // namespace texbake::cli
