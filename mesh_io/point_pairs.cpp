#include "mesh_io/point_pairs.h"

#include <cmath>
#include <optional>
#include <string>

#include "mesh_io/regular_file.h"
#include "mesh_io/text_scan.h"

namespace texbake {

Expected<PointPairs> point_pairs_from_text(std::string_view text, const std::string& where) {
  // A UTF-8 byte order mark (a spreadsheet's "CSV UTF-8" export) is not text.
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  PointPairs pairs;
  std::optional<Error> error;
  bool header_allowed = true;  // until the first line that is not empty or a comment
  read_detail::for_each_line(text, [&](std::string_view raw, std::size_t line) {
    const std::string_view l = read_detail::trim(raw);
    if (l.empty() || l.front() == '#') return true;
    const bool may_be_header = header_allowed;
    header_allowed = false;
    std::string spaced(l);
    for (char& c : spaced) {
      if (c == ',' || c == ';') c = ' ';
    }
    const std::vector<std::string_view> toks = read_detail::tokens(spaced);
    std::vector<double> v;
    for (std::string_view t : toks) {
      const std::optional<double> x = read_detail::parse_number(t);
      if (!x || !std::isfinite(*x)) {
        // A header line (no number at all) may open the file.
        bool any_number = false;
        for (std::string_view u : toks) any_number = any_number || read_detail::parse_number(u);
        if (may_be_header && !any_number) return true;
        error = Error{ErrorCode::kParse, where + ":" + std::to_string(line) + ": '" +
                                             std::string(t) + "' is not a finite number"};
        return false;
      }
      v.push_back(*x);
    }
    if (v.size() != 6) {
      error = Error{ErrorCode::kParse,
                    where + ":" + std::to_string(line) +
                        ": expected 6 numbers (the model's x y z, then the mesh's), got " +
                        std::to_string(v.size())};
      return false;
    }
    pairs.model.push_back({v[0], v[1], v[2]});
    pairs.mesh.push_back({v[3], v[4], v[5]});
    pairs.lines.push_back(line);
    return true;
  });
  if (error) return *error;
  return pairs;
}

Expected<PointPairs> read_point_pairs(const std::filesystem::path& path) {
  Expected<std::string> text = read_text_file(path, "a correspondences file");
  if (!text) return text.error();
  return point_pairs_from_text(*text, path.string());
}

}  // namespace texbake
