// One line of a jobs file (texbake batch, SPEC section 12) as a job of
// `texbake bake`: read without running anything, so the batch and the line's
// fuzzer (tests/fuzz/fuzz_batch_line.cpp) share it.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "texbake/texbake.h"

namespace texbake::cli {

struct BatchJob {
  nlohmann::ordered_json keys;    // the line's object, keys in its order
  std::vector<std::string> argv;  // "texbake", "bake", the options, "--", MESH
};

// The line's object (mesh_io/json_strict.h: valid JSON, nested at most 128
// levels, numbers finite, no duplicate key; errors kParse) and the argv of
// `texbake bake` for it. Every key is an option of `texbake bake` by its long
// name (underscores for hyphens: "proxy_file" is --proxy-file) or "mesh" (the
// positional MESH); "help" and "quiet" (the batch's own) are not job keys.
// A flag's value is true (the flag) or false (left out); any other option's
// value is a string, a number, an array of numbers ("x,y,z") or of arrays of
// numbers ("x,y,z;x,y,z;...", --corners). Values are passed as --K=VALUE and
// MESH after "--", so no value is read as a flag ("--help" is a file name).
// --quiet is added, and --threads=`threads` when the job has no "threads"
// and `threads` > 0. Errors (kInvalidArgument, a usage error as the single
// command's) name the key: "key 'help' is not an option of texbake bake".
Expected<BatchJob> parse_batch_line(std::string_view line, int threads);

}  // namespace texbake::cli
