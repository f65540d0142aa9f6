// A CLI11 option that takes exactly one of a fixed set of names.
//
// Not CLI::CheckedTransformer: CLI11 2.1's also accepts the enum's integer
// values (e.g. "--filter 1") and lists them in --help and in its messages.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

namespace texbake::cli {

// Adds `flag` to `cmd`: its value must be one of the names in `names`, and
// sets `target` to the matching value; anything else is a CLI::ValidationError
// "unknown value 'x' (expected a, b or c)" (exit 2). `target` must outlive
// parsing.
template <class T>
CLI::Option* add_choice_option(CLI::App& cmd, const std::string& flag, T& target,
                               const std::vector<std::pair<std::string, T>>& names,
                               const std::string& help) {
  std::string expected, type_name;
  for (std::size_t i = 0; i < names.size(); ++i) {
    expected += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + names[i].first;
    type_name += (i == 0 ? "" : "|") + names[i].first;
  }
  return cmd
      .add_option_function<std::string>(
          flag,
          [&target, flag, names, expected](const std::string& value) {
            for (const auto& [name, v] : names) {
              if (value == name) {
                target = v;
                return;
              }
            }
            throw CLI::ValidationError(flag,
                                       "unknown value '" + value + "' (expected " + expected + ")");
          },
          help)
      ->type_name(type_name);
}

}  // namespace texbake::cli
