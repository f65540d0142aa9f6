// Checks on the files a command names, made before any work (issue #12):
// no output may be an input or another output, and warnings about inputs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "mapping/error.h"
#include "mesh_io/image_io.h"

namespace texbake::cli {

// A file and how the command line named it ("-o", "MESH", "--texture",
// "the atlas image of -o").
struct NamedFile {
  std::string flag;
  std::filesystem::path path;
};

// kInvalidArgument (exit 2) when an output is the same file as an input
// (device and inode after links, mesh_io/atomic_file.h same_file) or two
// outputs name the same path (after links, existing or not):
//   "-o out.ply and MESH out.ply are the same file: texbake never overwrites
//    an input"
// Empty paths are skipped.
Status check_distinct_files(const std::vector<NamedFile>& inputs,
                            const std::vector<NamedFile>& outputs);

// Prints "texbake: warning: TEXTURE: N NaN or infinite values read as 0"
// when the image had any (mesh_io/image_io.h, Image::nonfinite_values).
void warn_nonfinite(const Image& image, const std::string& name);

// Prints "texbake: warning: TEXTURE: colour space 'X' is neither sRGB nor
// linear: read as linear (float data) (--texture-colorspace sets it)" when
// read_image could not place the file's oiio:ColorSpace
// (Image::unrecognised_color_space).
void warn_color_space(const Image& image, const std::string& name);

}  // namespace texbake::cli
