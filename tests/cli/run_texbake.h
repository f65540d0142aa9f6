// Runs the built texbake executable (TEXBAKE_BINARY) and captures its exit
// code, stdout and stderr, for the CLI tests.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace texbake::testing_cli {

struct RunResult {
  int exit_code = -1;
  std::string out, err;
};

// Single-quotes every argument for /bin/sh.
inline std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += (c == '\'') ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A path quoted for the shell.
inline std::string quoted(const std::filesystem::path& p) {
  return shell_quote(p.string());
}

// The whole content of a file, bytes as they are ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh, empty folder for the running test:
// TMP/texbake_<prefix>_<pid>_<test name>. The caller removes it.
inline std::filesystem::path fresh_test_dir(const std::string& prefix) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() /
      ("texbake_" + prefix + "_" + std::to_string(::getpid()) + "_" +
       ::testing::UnitTest::GetInstance()->current_test_info()->name());
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// Writes a binary PPM (P6) of w x h pixels, `rgb` holding 3 bytes per pixel,
// top row first: a small texture any image reader takes.
inline void write_ppm(const std::filesystem::path& path, int w, int h,
                      const std::vector<unsigned char>& rgb) {
  std::ofstream out(path, std::ios::binary);
  out << "P6\n" << w << " " << h << "\n255\n";
  out.write(reinterpret_cast<const char*>(rgb.data()), static_cast<std::streamsize>(rgb.size()));
}

// Runs a shell command line (its arguments quoted), capturing as run_texbake.
inline RunResult run_command(const std::string& command_quoted) {
  static int counter = 0;
  const std::filesystem::path err_file =
      std::filesystem::temp_directory_path() /
      ("texbake_cli_stderr_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string command = command_quoted + " 2>" + shell_quote(err_file.string());
  RunResult r;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (!pipe) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) r.out.append(buf, n);
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(err_file);
  std::ostringstream text;
  text << err.rdbuf();
  r.err = text.str();
  std::filesystem::remove(err_file);
  return r;
}

inline RunResult run_texbake(const std::string& args_quoted) {
  return run_command(shell_quote(TEXBAKE_BINARY) + " " + args_quoted);
}

// The photographs of the photo tests: the bunny with the Earth map through
// its fitted sphere (+Y up, written to DIR/s.json), rendered unlit from
// `views` views of `size` pixels ("320x240"; `extra` more render flags) as a
// COLMAP workspace DIR/ws. The fit's or the render's result when one fails.
inline RunResult render_bunny_workspace(const std::filesystem::path& dir, int views,
                                        const std::string& size, const std::string& extra = "") {
  const std::string bunny = shell_quote(std::string(TEXBAKE_DATA_DIR) + "/bunny00.off");
  RunResult fit =
      run_texbake("fit " + bunny + " --proxy sphere --up y -o " + quoted(dir / "s.json"));
  if (fit.exit_code != 0) return fit;
  return run_texbake("render " + bunny + " --texture " +
                     shell_quote(std::string(TEXBAKE_DATA_DIR) + "/earth.jpg") + " --proxy-file " +
                     quoted(dir / "s.json") + " --up y --unlit --views " + std::to_string(views) +
                     extra + " --size " + size + " --colmap " + quoted(dir / "ws"));
}

}  // namespace texbake::testing_cli
