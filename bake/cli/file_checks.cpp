#include "bake/cli/file_checks.h"

#include <iostream>

namespace texbake::cli {

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
