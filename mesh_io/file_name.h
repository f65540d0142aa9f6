// Small helpers on file names shared by the readers, the writers and the CLI.
#pragma once

#include <cctype>
#include <filesystem>
#include <string>

namespace texbake {

// The extension of `path` in lower case, with its dot (".obj"; "" if none):
// formats are chosen by extension, case-insensitively.
inline std::string lower_extension(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext;
}

}  // namespace texbake
