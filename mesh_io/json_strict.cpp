#include "mesh_io/json_strict.h"

#include <set>
#include <vector>

namespace texbake {

namespace {

using nlohmann::json;

json parse_tracking_keys(std::string_view text, std::string* duplicate, std::string* last_key) {
  std::vector<std::set<std::string>> keys_per_depth;
  json::parser_callback_t callback = [&](int depth, json::parse_event_t event, json& parsed) {
    const auto d = static_cast<std::size_t>(depth);
    if (keys_per_depth.size() <= d + 1) keys_per_depth.resize(d + 2);
    if (event == json::parse_event_t::object_start) {
      keys_per_depth[d + 1].clear();
    } else if (event == json::parse_event_t::key) {
      *last_key = parsed.get<std::string>();
      if (!keys_per_depth[d].insert(*last_key).second && duplicate->empty()) *duplicate = *last_key;
    }
    return true;
  };
  return json::parse(text.begin(), text.end(), callback);
}

}  // namespace

Expected<json> parse_json_object(std::string_view text, const std::string& source) {
  json root;
  std::string duplicate, last_key;
  try {
    root = parse_tracking_keys(text, &duplicate, &last_key);
  } catch (const json::out_of_range& e) {
    // 406: a number beyond double's range (1e999), which would be infinity.
    return make_error(
        ErrorCode::kParse,
        source + ": key '" + last_key + "' holds a number that is not finite (" + e.what() + ")");
  } catch (const json::exception& e) {
    // e.what() names the line and column: "[json.exception.parse_error.101]
    // parse error at line 3, column 12: ..."
    return make_error(ErrorCode::kParse, source + ": not valid JSON: " + e.what());
  }
  if (!duplicate.empty()) {
    return make_error(ErrorCode::kParse, source + ": duplicate key '" + duplicate + "'");
  }
  if (!root.is_object()) {
    return make_error(ErrorCode::kParse,
                      source + ": expected a JSON object, not " + root.type_name());
  }
  return root;
}

}  // namespace texbake
