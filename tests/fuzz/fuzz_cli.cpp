// libFuzzer target for the command line: the input is split at newlines into
// argv (argv[0] = "texbake") and parsed by the real CLI11 setup
// (bake/cli/app.h). Only `map` is then run: it is pure math. The other
// commands read and write files, so for them only the parsing is fuzzed
// (including every flag's value checks, which run during parsing).
// Output (help texts, map results, error messages) goes to /dev/null.
#include <cstdint>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "bake/cli/app.h"

namespace {

std::ostringstream& sink() {
  static std::ostringstream s;
  s.str({});
  return s;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // printf-based output of `map`; std::cout/cerr are redirected per input.
  if (!std::freopen("/dev/null", "w", stdout)) return 0;
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::vector<std::string> args{"texbake"};
  std::size_t pos = 0;
  while (pos <= text.size() && args.size() < 64) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    args.push_back(text.substr(pos, end - pos));
    pos = end + 1;
  }
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());

  std::streambuf* out = std::cout.rdbuf(sink().rdbuf());
  std::streambuf* err = std::cerr.rdbuf(sink().rdbuf());
  {
    std::unique_ptr<texbake::cli::CliApp> cli = texbake::cli::make_cli_app();
    const std::optional<int> code =
        texbake::cli::parse_cli(*cli, static_cast<int>(argv.size()), argv.data());
    if (!code) {
      const CLI::App* sub = texbake::cli::parsed_subcommand(*cli);
      if (sub && sub->get_name() == "map") (void)texbake::cli::run_parsed(*cli);
    }
  }
  std::cout.rdbuf(out);
  std::cerr.rdbuf(err);
  return 0;
}
