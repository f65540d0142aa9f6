// A CLI11 option that takes exactly one of a fixed set of names.
//
// Not CLI::CheckedTransformer: CLI11 2.1's also accepts the enum's integer
// values (e.g. "--filter 1") and lists them in --help and in its messages.
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "texbake/texbake.h"

namespace texbake::cli {

// Adds `flag` to `cmd`: its value must be one of the names in `names`, and
// sets `target` to the matching value; anything else is a CLI::ValidationError
// with the library's message, "--flag: unknown value 'x' (expected a, b or
// c)" (texbake::unknown_choice; exit 2). `target` must outlive parsing.
template <class T>
CLI::Option* add_choice_option(CLI::App& cmd, const std::string& flag, T& target,
                               const std::vector<std::pair<std::string, T>>& names,
                               const std::string& help) {
  std::string type_name;
  for (std::size_t i = 0; i < names.size(); ++i) type_name += (i == 0 ? "" : "|") + names[i].first;
  return cmd
      .add_option_function<std::string>(
          flag,
          [&target, flag, names](const std::string& value) {
            std::vector<const char*> expected;
            for (const auto& [name, v] : names) {
              if (value == name) {
                target = v;
                return;
              }
              expected.push_back(name.c_str());
            }
            throw CLI::ValidationError(unknown_choice(flag, value, expected).message);
          },
          help)
      ->type_name(type_name);
}

// The same with the library's names of E's values (texbake::choices), e.g.
// add_choice_option<VertexFilter>(cmd, "--filter", filter, help); `target`
// is an E or a std::optional<E>.
template <class E, class T>
CLI::Option* add_choice_option(CLI::App& cmd, const std::string& flag, T& target,
                               const std::string& help) {
  std::vector<std::pair<std::string, T>> names;
  for (const Choice<E>& c : choices(E{})) names.emplace_back(c.name, c.value);
  return add_choice_option(cmd, flag, target, names, help);
}

}  // namespace texbake::cli
