// Text scanning shared by texbake's own mesh parsers (read_obj.cpp's checks,
// read_off.cpp, read_ply.cpp's ASCII data, read_stl.cpp): lines, whitespace
// tokens, numbers, and a token cursor that counts lines for error messages.
// Hand-written rather than istream >> because the readers must see every
// token and every failure (OpenMesh's istream-based readers are where NaN,
// garbage and truncation went unnoticed), and report the line it was on.
// Not a public API (read_mesh.h is).
#pragma once

#include <charconv>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace texbake::read_detail {

// Splits text into lines at '\n' (a '\r' before it is dropped) and calls
// fn(line, line_number) for each, numbers from 1, until fn returns false.
// A final line without '\n' is passed too; an empty text has no lines.
template <class Fn>
void for_each_line(std::string_view text, Fn&& fn) {
  std::size_t line = 1, pos = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view l = text.substr(pos, end - pos);
    if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
    if (!fn(l, line)) return;
    pos = end + 1;
    ++line;
  }
}

// `s` without leading and trailing whitespace (std::isspace).
std::string_view trim(std::string_view s);

// The whitespace-separated tokens of `s`, in order (views into `s`).
std::vector<std::string_view> tokens(std::string_view s);

// A whole token as a number, strtod's syntax (decimal, hex, inf, nan; so a
// caller sees NaN and rejects it, where an istream would silently fail).
// nullopt if the token is empty or has anything after the number.
std::optional<double> parse_number(std::string_view tok);

// A whole token as a float, strictly: decimal syntax only
// ([+-]digits[.[digits]] or [+-].digits, then optionally (e|E)[+-]digits;
// no hex, inf or nan), rounded once to float (strtof, as an istream would),
// and finite: nullopt otherwise, 1e39 (above float's range) included. Values
// below float's smallest normal become denormals or 0, as with strtof.
std::optional<float> parse_decimal_float(std::string_view tok);

// A whole token as an integer of type Int (std::from_chars: no sign for
// unsigned types, no '+', no spaces). False if it does not parse or fit.
template <class Int>
bool parse_int(std::string_view tok, Int& out) {
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

// Whitespace-separated tokens of a text, one at a time, with the number of
// the line the last token is on (`line` starts at the line number of the
// text's first character).
struct TokenCursor {
  std::string_view text;
  std::size_t pos = 0;
  std::size_t line = 1;
  // The next token into `tok`; false (tok untouched) at the end of the text.
  // Line breaks before the token are counted in `line`.
  bool next(std::string_view& tok);
  // The rest of the current line (up to '\n' or the end of the text, not
  // included), consumed: free text after a keyword, such as an STL solid's
  // name. Empty if the cursor is at a line break.
  std::string_view rest_of_line();
};

// RFC 3986 percent-decoding of a URI reference (a glTF's URIs): each %XX
// of two hex digits is that byte; anything else is kept as it is.
std::string percent_decode(const std::string& uri);

}  // namespace texbake::read_detail
