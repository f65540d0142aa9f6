#include "bake/cli/file_checks.h"

#include <iostream>
#include <system_error>

#include "mesh_io/atomic_file.h"

namespace texbake::cli {
namespace fs = std::filesystem;

namespace {

// The path with links and "." / ".." resolved as far as it exists.
fs::path normal_path(const fs::path& p) {
  std::error_code ec;
  fs::path r = fs::weakly_canonical(fs::absolute(p, ec), ec);
  return ec ? p.lexically_normal() : r;
}

bool same_target(const fs::path& a, const fs::path& b) {
  return same_file(a, b) || normal_path(a) == normal_path(b);
}

Error same_file_error(const NamedFile& out, const NamedFile& other, const char* why) {
  return make_error(ErrorCode::kInvalidArgument, out.flag + " " + out.path.string() + " and " +
                                                     other.flag + " " + other.path.string() +
                                                     " are the same file: " + why);
}

}  // namespace

Status check_distinct_files(const std::vector<NamedFile>& inputs,
                            const std::vector<NamedFile>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const NamedFile& out = outputs[i];
    if (out.path.empty()) continue;
    for (const NamedFile& in : inputs) {
      if (!in.path.empty() && same_target(out.path, in.path)) {
        return same_file_error(out, in, "texbake never overwrites an input");
      }
    }
    for (std::size_t j = 0; j < i; ++j) {
      if (!outputs[j].path.empty() && same_target(out.path, outputs[j].path)) {
        return same_file_error(out, outputs[j], "two outputs cannot share one file");
      }
    }
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
