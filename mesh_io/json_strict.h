// Strict JSON for texbake's own files (proxy files, camera lists, layers):
// nlohmann-json with the checks it lacks. Internal to mesh_io (names a
// third-party type; no public header includes it).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "mapping/error.h"

namespace texbake {

// Parses `text` as one JSON object. Errors (kParse, starting with `source`):
// "not valid JSON: ..." (with nlohmann's line and column), "duplicate key
// 'K'" (JSON leaves duplicates undefined; nlohmann would keep the last), "key
// 'K' holds a number that is not finite" (1e999), "expected a JSON object,
// not array".
Expected<nlohmann::json> parse_json_object(std::string_view text, const std::string& source);

}  // namespace texbake
