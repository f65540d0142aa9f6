#include "bake/cli/batch_job.h"

#include <algorithm>
#include <map>
#include <memory>

#include "bake/cli/app.h"
#include "mesh_io/json_strict.h"

namespace texbake::cli {

namespace {

using nlohmann::ordered_json;

// The keys of a job: every long name of `texbake bake`'s options
// (underscores for hyphens) and whether it is a flag (takes no value); not
// --help, not --quiet (the batch's own: it prints a line per job).
const std::map<std::string, bool>& bake_keys() {
  static const std::map<std::string, bool> keys = [] {
    std::map<std::string, bool> k;
    const std::unique_ptr<CliApp> cli = make_cli_app();
    const CLI::App* bake = cli->app.get_subcommand("bake");
    for (const CLI::Option* opt : bake->get_options()) {
      if (opt == bake->get_help_ptr() || opt == bake->get_help_all_ptr()) continue;
      for (std::string name : opt->get_lnames()) {
        std::replace(name.begin(), name.end(), '-', '_');
        k[name] = opt->get_expected_max() == 0;
      }
    }
    k.erase("quiet");
    return k;
  }();
  return keys;
}

Error bad_key(const std::string& key) {
  std::string why = "is not an option of texbake bake";
  if (key == "quiet") {
    why = "is the batch's option (texbake batch --quiet), not a job's";
  } else if (std::string k = key;
             std::replace(k.begin(), k.end(), '-', '_'), bake_keys().count(k)) {
    why += " (did you mean '" + k + "'?)";
  }
  return make_error(ErrorCode::kInvalidArgument, "key '" + key + "' " + why);
}

// A JSON value as the text of an option's value: a string as it is, a
// number as JSON prints it, an array of numbers "x,y,z", an array of arrays
// "x,y,z;x,y,z;..." (--corners). Error naming the key for other values.
Expected<std::string> flag_value(const std::string& key, const ordered_json& v) {
  if (v.is_string()) return v.get<std::string>();
  if (v.is_number()) return v.dump();
  auto bad = [&] {
    return make_error(ErrorCode::kInvalidArgument,
                      "key '" + key + "': " + v.dump() +
                          " is not a value of the command line (a string, a number, an array "
                          "of numbers or of arrays of numbers)");
  };
  if (!v.is_array() || v.empty()) return bad();
  std::string text;
  for (const ordered_json& e : v) {
    if (e.is_array()) {
      Expected<std::string> inner = flag_value(key, e);
      if (!inner || inner->find(';') != std::string::npos) return bad();
      text += (text.empty() ? "" : ";") + *inner;
    } else if (e.is_number()) {
      text += (text.empty() ? "" : ",") + e.dump();
    } else {
      return bad();
    }
  }
  return text;
}

}  // namespace

Expected<BatchJob> parse_batch_line(std::string_view line, int threads) {
  Expected<ordered_json> keys = parse_json_object<ordered_json>(line, "");
  if (!keys) return keys.error();
  BatchJob job{std::move(keys).value(), {"texbake", "bake"}};
  std::vector<std::string> mesh;
  for (const auto& [key, value] : job.keys.items()) {
    if (key == "mesh") {
      Expected<std::string> v = flag_value(key, value);
      if (!v) return v.error();
      mesh = {"--", *v};
      continue;
    }
    const auto it = bake_keys().find(key);
    if (it == bake_keys().end()) return bad_key(key);
    std::string flag = "--" + key;
    std::replace(flag.begin(), flag.end(), '_', '-');
    const bool is_flag = it->second;
    if (is_flag != value.is_boolean()) {
      return make_error(ErrorCode::kInvalidArgument,
                        "key '" + key + "': " + value.dump() +
                            (is_flag ? " is not true or false (a flag)"
                                     : " is not a value of the command line (the option takes "
                                       "one, not a flag's true or false)"));
    }
    if (is_flag) {
      if (value.get<bool>()) job.argv.push_back(flag);
      continue;
    }
    Expected<std::string> v = flag_value(key, value);
    if (!v) return v.error();
    job.argv.push_back(flag + "=" + *v);
  }
  job.argv.push_back("--quiet");
  if (!job.keys.contains("threads") && threads > 0)
    job.argv.push_back("--threads=" + std::to_string(threads));
  job.argv.insert(job.argv.end(), mesh.begin(), mesh.end());
  return job;
}

}  // namespace texbake::cli
