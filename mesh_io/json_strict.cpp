#include "mesh_io/json_strict.h"

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <set>
#include <vector>

namespace texbake {

namespace {

using nlohmann::json;

// A character iterator that publishes how far the parser has read: nlohmann's
// SAX events carry no position, and the parser reads no further than the
// token it reports ('[' or '{' for a container's start).
class TrackedChars {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  TrackedChars(const char* at, const char** read) : at_(at), read_(read) {}
  reference operator*() const { return *at_; }
  TrackedChars& operator++() {
    *read_ = ++at_;
    return *this;
  }
  TrackedChars operator++(int) {
    TrackedChars before = *this;
    ++*this;
    return before;
  }
  bool operator==(const TrackedChars& o) const { return at_ == o.at_; }
  bool operator!=(const TrackedChars& o) const { return at_ != o.at_; }

 private:
  const char* at_;
  const char** read_;
};

// The SAX pass of the checks: builds nothing, keeps one frame per open
// container (its current key and, when strict, the keys seen) and stops at
// the first problem with its message in error().
class Checker {
 public:
  Checker(std::string_view text, const char* const* read, bool strict)
      : text_(text), read_(read), strict_(strict) {}

  bool null() { return true; }
  bool boolean(bool) { return true; }
  bool number_integer(json::number_integer_t) { return true; }
  bool number_unsigned(json::number_unsigned_t) { return true; }
  bool number_float(json::number_float_t, const json::string_t&) { return true; }
  bool string(json::string_t&) { return true; }
  bool binary(json::binary_t&) { return true; }
  bool start_object(std::size_t) { return open(true); }
  bool start_array(std::size_t) { return open(false); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(json::string_t& key) {
    Frame& f = frames_.back();
    f.key = key;
    if (strict_ && !f.keys.insert(key).second) {
      error_ = "duplicate key '" + key_path() + "' " + place(offset());
      return false;
    }
    return true;
  }
  bool parse_error(std::size_t position, const std::string& token,
                   const nlohmann::detail::exception& e) {
    if (!strict_) return false;  // the reader that follows reports it
    if (e.id == 406) {           // out_of_range: a number beyond double's range
      error_ = place_name() + " holds a number that is not finite (" + ascii(token) + " at " +
               place(position - std::min(position, token.size()) + 1).substr(1);
    } else {
      // Without nlohmann's "[json.exception.parse_error.101] " prefix; the
      // message names the line and column.
      const std::string what = e.what();
      const std::size_t end = what.find("] ");
      error_ = "not valid JSON: " + ascii(end == std::string::npos ? what : what.substr(end + 2));
    }
    return false;
  }

  const std::string& error() const { return error_; }

 private:
  struct Frame {
    bool object = false;
    std::string key;             // objects: the key of the value being read
    std::set<std::string> keys;  // objects, when strict: the keys seen
  };

  bool open(bool object) {
    if (frames_.size() >= static_cast<std::size_t>(kMaxJsonDepth)) {
      error_ = place_name() + " nests deeper than " + std::to_string(kMaxJsonDepth) + " levels " +
               place(offset());
      return false;
    }
    frames_.push_back({object, {}, {}});
    return true;
  }
  bool close() {
    frames_.pop_back();
    return true;
  }

  std::size_t offset() const { return static_cast<std::size_t>(*read_ - text_.data()); }

  // "(line L, column C)" of the character before byte offset `end`.
  std::string place(std::size_t end) const {
    end = std::min(end, text_.size());
    const std::string_view before = text_.substr(0, end);
    const std::size_t line =
        1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
    const std::size_t start = before.rfind('\n');
    const std::size_t column = start == std::string_view::npos ? end : end - start - 1;
    return "(line " + std::to_string(line) + ", column " + std::to_string(column) + ")";
  }

  // "key 'a.b'" for the value being read, "the value" outside any object.
  std::string place_name() const {
    const std::string path = key_path();
    return path.empty() ? std::string("the value") : "key '" + path + "'";
  }

  // The keys from the outermost object to the place, joined by '.'; past 8
  // keys, the first 4 and the last 4 around "...".
  std::string key_path() const {
    std::vector<std::string> keys;
    for (const Frame& f : frames_) {
      if (f.object) keys.push_back(f.key);
    }
    const auto join = [&](std::size_t from, std::size_t to) {
      std::string s;
      for (std::size_t i = from; i < to; ++i) s += (i == from ? "" : ".") + keys[i];
      return s;
    };
    if (keys.size() <= 8) return join(0, keys.size());
    return join(0, 4) + "..." + join(keys.size() - 4, keys.size());
  }

  // nlohmann quotes the bytes it read; a message must stay valid UTF-8
  // (results files, Python's str), so bytes past ASCII become '?'.
  static std::string ascii(std::string s) {
    for (char& c : s) {
      if (static_cast<unsigned char>(c) >= 0x80) c = '?';
    }
    return s;
  }

  std::string_view text_;
  const char* const* read_;
  bool strict_;
  std::vector<Frame> frames_;
  std::string error_;
};

// The checks' message ("" when the text passes).
std::string check(std::string_view text, bool strict) {
  const char* read = text.data();
  Checker checker(text, &read, strict);
  json::sax_parse(TrackedChars(text.data(), &read), TrackedChars(text.data() + text.size(), &read),
                  &checker);
  return checker.error();
}

Error parse_failure(const std::string& source, const std::string& message) {
  return make_error(ErrorCode::kParse, source.empty() ? message : source + ": " + message);
}

}  // namespace

Status check_json_depth(std::string_view text, const std::string& source) {
  if (const std::string e = check(text, false); !e.empty()) return parse_failure(source, e);
  return ok_status();
}

template <class Json>
Expected<Json> parse_json_object(std::string_view text, const std::string& source) {
  if (const std::string e = check(text, true); !e.empty()) return parse_failure(source, e);
  Json root;
  try {
    root = Json::parse(text.begin(), text.end());
  } catch (const nlohmann::json::exception& e) {
    return parse_failure(source, std::string("not valid JSON: ") + e.what());  // checked above
  }
  if (!root.is_object()) {
    return parse_failure(source, std::string("expected a JSON object, not ") + root.type_name());
  }
  return root;
}

template Expected<nlohmann::json> parse_json_object(std::string_view, const std::string&);
template Expected<nlohmann::ordered_json> parse_json_object(std::string_view, const std::string&);

}  // namespace texbake
