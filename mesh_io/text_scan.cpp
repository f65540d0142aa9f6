#include "mesh_io/text_scan.h"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <string>

namespace texbake::read_detail {

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

std::vector<std::string_view> tokens(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
    std::size_t j = i;
    while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
  return out;
}

std::optional<double> parse_number(std::string_view tok) {
  std::string s(tok);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') return std::nullopt;
  return v;
}

std::optional<float> parse_decimal_float(std::string_view tok) {
  std::size_t i = 0;
  auto digits = [&] {
    const std::size_t from = i;
    while (i < tok.size() && tok[i] >= '0' && tok[i] <= '9') ++i;
    return i > from;
  };
  if (i < tok.size() && (tok[i] == '+' || tok[i] == '-')) ++i;
  const bool whole = digits();
  bool fraction = false;
  if (i < tok.size() && tok[i] == '.') {
    ++i;
    fraction = digits();
  }
  if (!whole && !fraction) return std::nullopt;
  if (i < tok.size() && (tok[i] == 'e' || tok[i] == 'E')) {
    ++i;
    if (i < tok.size() && (tok[i] == '+' || tok[i] == '-')) ++i;
    if (!digits()) return std::nullopt;
  }
  if (i != tok.size()) return std::nullopt;
  // The syntax is strtof's decimal form, so strtof reads the whole token.
  const std::string s(tok);
  const float v = std::strtof(s.c_str(), nullptr);
  if (!std::isfinite(v)) return std::nullopt;
  return v;
}

bool TokenCursor::next(std::string_view& tok) {
  while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos]))) {
    if (text[pos] == '\n') ++line;
    ++pos;
  }
  if (pos >= text.size()) return false;
  const std::size_t b = pos;
  while (pos < text.size() && !std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
  tok = text.substr(b, pos - b);
  return true;
}

std::string_view TokenCursor::rest_of_line() {
  const std::size_t b = pos;
  while (pos < text.size() && text[pos] != '\n') ++pos;
  return text.substr(b, pos - b);
}

std::string percent_decode(const std::string& uri) {
  std::string out;
  auto hex = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
  };
  for (std::size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out.push_back(static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2])));
      i += 2;
    } else {
      out.push_back(uri[i]);
    }
  }
  return out;
}

}  // namespace texbake::read_detail
