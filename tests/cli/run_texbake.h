// Runs the built texbake executable (TEXBAKE_BINARY) and captures its exit
// code, stdout and stderr, for the CLI tests.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

// The whole content of a file, bytes as they are ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline RunResult run_texbake(const std::string& args_quoted) {
  static int counter = 0;
  const std::filesystem::path err_file =
      std::filesystem::temp_directory_path() /
      ("texbake_cli_stderr_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string command =
      shell_quote(TEXBAKE_BINARY) + " " + args_quoted + " 2>" + shell_quote(err_file.string());
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

}  // namespace texbake::testing_cli
