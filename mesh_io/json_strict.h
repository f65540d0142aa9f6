// Strict, bounded JSON for every JSON text texbake reads (proxy files,
// cameras and camera lists, layers files, batch lines, glTF): nlohmann-json
// with the checks it lacks. Internal to mesh_io and the CLI (names a
// third-party type; no public header includes it).
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "mapping/error.h"

namespace texbake {

// The deepest nesting of arrays and objects any JSON reader of texbake
// accepts (the outermost value is level 1). Building, copying or printing a
// value recurses once per level, so a text nested 100,000 deep would
// overflow the stack; texbake's own files nest at most 6 levels, glTF
// documents about 8 (extras may nest more).
constexpr int kMaxJsonDepth = 128;

// Checks `text` before any value is built (one SAX pass): nesting at most
// kMaxJsonDepth levels. Errors (kParse) start with `source` (no prefix when it
// is empty) and name the key and place: "key 'layers.proxy.center' nests
// deeper than 128 levels (line 3, column 41)". Text that is not valid JSON
// passes: the reader that follows reports it (read_gltf: tinygltf).
Status check_json_depth(std::string_view text, const std::string& source);

// Parses `text` as one JSON object after the checks nlohmann lacks. Errors
// (kParse, starting with `source` as above): "not valid JSON: parse error at
// line L, column C: ...", "key 'K' nests deeper than 128 levels (line L,
// column C)", "key 'K' holds a number that is not finite (1e999 at line L,
// column C)", "duplicate key 'K' (line L, column C)" (JSON leaves duplicates
// undefined; nlohmann would keep the last), "expected a JSON object, not
// array". K is the path of keys to the place ("layers.proxy.radius").
// Json is nlohmann::json (keys sorted) or nlohmann::ordered_json (keys in
// the text's order).
template <class Json = nlohmann::json>
Expected<Json> parse_json_object(std::string_view text, const std::string& source);

extern template Expected<nlohmann::json> parse_json_object(std::string_view, const std::string&);
extern template Expected<nlohmann::ordered_json> parse_json_object(std::string_view,
                                                                   const std::string&);

}  // namespace texbake
