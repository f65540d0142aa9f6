// Helpers for mesh_io tests: a fresh temporary folder per test and small
// file writers. Header-only; the test binary globs only *.cpp.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <string>

namespace texbake::test {

inline std::filesystem::path fresh_temp_dir(const std::string& name) {
  std::random_device rd;
  auto dir = std::filesystem::temp_directory_path() /
             ("texbake-test-" + name + "-" + std::to_string(rd()));
  std::filesystem::create_directories(dir);
  return dir;
}

inline std::filesystem::path write_text(const std::filesystem::path& path,
                                        const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

inline std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

inline std::filesystem::path bad_dir() {
  return std::filesystem::path(TEXBAKE_SOURCE_DIR) / "tests" / "data" / "bad";
}

}  // namespace texbake::test
