// The shared bounded, strict JSON parse (mesh_io/json_strict.h) every JSON
// reader calls: the depth limit at its exact boundary, the place and key path
// of each error (columns counted by hand in the texts below), numbers beyond
// double's range, duplicate keys, and messages that stay ASCII.
#include "mesh_io/json_strict.h"

#include <gtest/gtest.h>

#include <string>

namespace texbake {
namespace {

using nlohmann::json;

// {"a": [[...]]} with `n` arrays: n + 1 levels.
std::string nested_in_a(int n) {
  return R"({"a":)" + std::string(n, '[') + std::string(n, ']') + "}";
}

std::string error_of(const std::string& text, const std::string& source = "S") {
  Expected<json> j = parse_json_object(text, source);
  EXPECT_FALSE(j) << text.substr(0, 80);
  if (j) return "";
  EXPECT_EQ(j.error().code, ErrorCode::kParse);
  return j.error().message;
}

TEST(JsonStrict, DepthLimitIsExactly128Levels) {
  ASSERT_EQ(kMaxJsonDepth, 128);
  // 127 arrays in the root object: 128 levels, read.
  Expected<json> ok = parse_json_object(nested_in_a(127), "S");
  ASSERT_TRUE(ok) << ok.error().message;
  EXPECT_TRUE((*ok)["a"].is_array());
  // 128 arrays: the 128th '[' opens level 129. `{"a":` is 5 characters, so
  // that '[' is column 5 + 128.
  EXPECT_EQ(error_of(nested_in_a(128)),
            "S: key 'a' nests deeper than 128 levels (line 1, column 133)");
  // 100,000 levels (what crashed): the same error, nothing built.
  EXPECT_EQ(error_of(nested_in_a(100000)),
            "S: key 'a' nests deeper than 128 levels (line 1, column 133)");
  // Unclosed, and objects: the limit counts both kinds of container.
  std::string objects;
  for (int i = 0; i < 200; ++i) objects += R"({"k":)";
  EXPECT_EQ(error_of(objects).substr(0, 39), "S: key 'k.k.k.k...k.k.k.k' nests deeper");
  EXPECT_NE(error_of(objects).find("(line 1, column 641)"), std::string::npos)  // 128 * 5 + 1
      << error_of(objects);
}

TEST(JsonStrict, DepthErrorsNameTheLineAndThePathOfKeys) {
  // Levels: root, "layers" array, the layer, "proxy", "center" = 4 + the
  // arrays of "center"; the 125th '[' is level 129. Line 3 starts with
  // `  {"proxy": {"center": ` (23 characters).
  const std::string text =
      "{\n \"layers\": [\n  {\"proxy\": {\"center\": " + std::string(125, '[') +
      std::string(125, ']') + "}}]}";
  EXPECT_EQ(error_of(text, "L.json"),
            "L.json: key 'layers.proxy.center' nests deeper than 128 levels (line 3, column 148)");
  // A root that is not an object: no key to name.
  EXPECT_EQ(check_json_depth(std::string(100000, '['), "x.gltf").error().message,
            "x.gltf: the value nests deeper than 128 levels (line 1, column 129)");
}

TEST(JsonStrict, CheckJsonDepthLeavesOtherErrorsToTheReader) {
  // check_json_depth (glTF: tinygltf reports syntax) passes text that is
  // not JSON but stays shallow, and refuses depth even after an error-free
  // prefix; no source gives no prefix.
  EXPECT_TRUE(check_json_depth("{\"a\": nope", "x.gltf"));
  EXPECT_TRUE(check_json_depth("{\"a\": 1e999, \"a\": 2}", "x.gltf"));
  EXPECT_TRUE(check_json_depth(nested_in_a(127), "x.gltf"));
  EXPECT_EQ(check_json_depth(nested_in_a(128), "").error().message,
            "key 'a' nests deeper than 128 levels (line 1, column 133)");
}

TEST(JsonStrict, NumbersBeyondDoubleNameTheirKeyAndPlace) {
  // `{"kind":"sphere","center":[0,` is 29 characters: -1e400 starts at 30.
  EXPECT_EQ(error_of(R"({"kind":"sphere","center":[0,-1e400,0]})"),
            "S: key 'center' holds a number that is not finite (-1e400 at line 1, column 30)");
  EXPECT_EQ(error_of("{\"samples\":\n 1e999}"),
            "S: key 'samples' holds a number that is not finite (1e999 at line 2, column 2)");
  // An integer too long for 64 bits is read as a double: 400 digits is inf.
  EXPECT_NE(error_of(R"({"n":1)" + std::string(400, '0') + "}").find("key 'n' holds a number"),
            std::string::npos);
  // Small ones underflow to zero, which is finite.
  Expected<json> tiny = parse_json_object(R"({"n":1e-999})", "S");
  ASSERT_TRUE(tiny);
  EXPECT_EQ((*tiny)["n"].get<double>(), 0.0);
}

TEST(JsonStrict, DuplicateKeysAndShapes) {
  EXPECT_EQ(error_of(R"({"a":{"b":1,"b":2}})").rfind("S: duplicate key 'a.b' (line 1, column ", 0),
            0u);
  // The same key in two objects is no duplicate.
  EXPECT_TRUE(parse_json_object(R"({"a":{"b":1},"c":{"b":2}})", "S"));
  EXPECT_EQ(error_of("[1, 2]"), "S: expected a JSON object, not array");
  EXPECT_EQ(error_of("").rfind("S: not valid JSON: parse error at line 1, column 1", 0), 0u);
  EXPECT_EQ(error_of(R"({"a":1} x)").rfind("S: not valid JSON: parse error at line 1, column 9", 0),
            0u);
}

TEST(JsonStrict, MessagesStayAscii) {
  // nlohmann quotes the bytes it read; a byte that is not UTF-8 must not
  // reach a message (results files, Python's str).
  const std::string message = error_of("{\"a\": \xff\xfe}");
  EXPECT_NE(message.find("not valid JSON"), std::string::npos);
  for (char c : message) EXPECT_LT(static_cast<unsigned char>(c), 0x80) << message;
}

TEST(JsonStrict, OrderedJsonKeepsTheTextsOrder) {
  Expected<nlohmann::ordered_json> j =
      parse_json_object<nlohmann::ordered_json>(R"({"z":1,"a":2,"m":3})", "S");
  ASSERT_TRUE(j);
  std::string keys;
  for (const auto& [key, value] : j->items()) keys += key;
  EXPECT_EQ(keys, "zam");
}

}  // namespace
}  // namespace texbake
