// STL, ASCII and binary. ASCII: "solid [name]", then per triangle
// "facet normal ni nj nk", "outer loop", three "vertex x y z", "endloop",
// "endfacet", and "endsolid [name]" (keywords in any case; several solids may
// follow one another). Binary: an 80-byte header, a little-endian uint32
// triangle count, 50 bytes per triangle (normal, three corners of 3 floats, a
// 2-byte attribute).
//
// Which one a .stl is: binary if its size is exactly 84 + 50 x count (OpenMesh
// 9.0's own rule, STLReader.cc check_stl_type; many binary exporters start
// the header with "solid" too); else ASCII if it starts with "solid" (after
// whitespace) and holds no NUL byte; else a binary STL whose size does not
// match its count, which is an error.
//
// ASCII STL is parsed here, not by OpenMesh: OpenMesh 9.0's reader
// (read_stla) reads the numbers with istream >> and never checks the stream,
// so a "nan", "zz" or 1e39 coordinate leaves the vertex as memory it never
// wrote (it changes from run to run; issue #12), a missing vertex line takes
// the next line ("endloop") as a vertex, a truncated file is accepted as far
// as it goes, and any line containing "outer" (a solid named
// "outer_shell") starts a triangle. Here every keyword is checked in order,
// every number is a finite decimal float, and errors name the file and line.
// Binary STL is still parsed by OpenMesh (read_openmesh.cpp), after
// check_binary has made sure every corner is finite (OpenMesh's vertex map
// compares a NaN as equal to anything and would merge it into another
// vertex, so the later finiteness check could not see it).
//
// Both merge corners at equal positions into one vertex, numbered in order of
// first appearance, and drop the triangles that then repeat a vertex: STL has
// no shared vertices, and this is what OpenMesh's reader does for both (the
// ASCII parser below does the same so that reading a file as ASCII or binary
// gives the same mesh).
#include <array>
#include <bit>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>

#include "mesh_io/read_mesh_internal.h"
#include "mesh_io/text_scan.h"

namespace texbake::read_detail {
namespace fs = std::filesystem;

namespace {

constexpr std::size_t kBinaryHeader = 84, kBinaryTriangle = 50;

uint32_t binary_count(std::string_view bytes) {
  return load_le32(bytes.data() + 80);
}

bool same_keyword(std::string_view tok, std::string_view keyword) {
  if (tok.size() != keyword.size()) return false;
  for (std::size_t i = 0; i < tok.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(tok[i])) != keyword[i]) return false;
  }
  return true;
}

// The first five non-blank characters are "solid", in any case (OpenMesh's
// test for ASCII, strnicmp).
bool starts_with_solid(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  return same_keyword(bytes.substr(i, 5), "solid");
}

// A token for an error message: quoted, cut after 40 characters.
std::string quoted(std::string_view tok) {
  std::string q(1, '\'');
  q.append(tok.substr(0, 40));
  q += tok.size() > 40 ? "...'" : "'";
  return q;
}

// OpenMesh's vertex map order (STLReader.cc, CmpVec with its eps_ = FLT_MIN):
// corners closer than FLT_MIN in every coordinate are the same vertex (so 0
// and -0 are).
struct CornerOrder {
  bool operator()(const std::array<float, 3>& a, const std::array<float, 3>& b) const {
    constexpr float eps = std::numeric_limits<float>::min();
    if (std::fabs(a[0] - b[0]) <= eps) {
      if (std::fabs(a[1] - b[1]) <= eps) return a[2] < b[2] - eps;
      return a[1] < b[1] - eps;
    }
    return a[0] < b[0] - eps;
  }
};

// Builds the mesh from STL triangles as OpenMesh's reader does (see the top).
class CornerWelder {
 public:
  CornerWelder() { mesh_.face_offsets = {0}; }
  void add_triangle(const std::array<std::array<float, 3>, 3>& corners) {
    uint32_t v[3];
    for (int k = 0; k < 3; ++k) {
      // find, then insert: the same map operations as OpenMesh's reader.
      const auto it = vertex_of_.find(corners[k]);
      if (it != vertex_of_.end()) {
        v[k] = it->second;
        continue;
      }
      v[k] = static_cast<uint32_t>(mesh_.positions.size());
      mesh_.positions.push_back({corners[k][0], corners[k][1], corners[k][2]});
      vertex_of_[corners[k]] = v[k];
    }
    if (v[0] == v[1] || v[0] == v[2] || v[1] == v[2]) return;
    mesh_.face_vertices.insert(mesh_.face_vertices.end(), v, v + 3);
    mesh_.face_offsets.push_back(static_cast<uint32_t>(mesh_.face_vertices.size()));
  }
  MeshData take() { return std::move(mesh_); }

 private:
  MeshData mesh_;
  std::map<std::array<float, 3>, uint32_t, CornerOrder> vertex_of_;
};

// The strict ASCII parser (see the top for why not OpenMesh's).
class AsciiStlParser {
 public:
  AsciiStlParser(const fs::path& path, std::string_view text) : path_(path), cursor_{text, 0, 1} {}

  Expected<MeshData> parse() {
    std::string_view tok;
    if (Status s = expect("solid", "at the start of an ASCII STL"); !s) return s.error();
    cursor_.rest_of_line();  // the solid's name
    while (true) {
      if (!next(tok)) return truncated("before 'endsolid'");
      if (same_keyword(tok, "endsolid")) {
        cursor_.rest_of_line();
        if (!next(tok)) break;
        if (same_keyword(tok, "solid")) {
          cursor_.rest_of_line();
          continue;
        }
        return error("expected 'solid' or the end of the file after 'endsolid', got " +
                     quoted(tok));
      }
      if (!same_keyword(tok, "facet"))
        return error("expected 'facet' or 'endsolid', got " + quoted(tok));
      in_facet_ = true;
      if (Status s = facet(); !s) return s.error();
      in_facet_ = false;
      ++facet_;
    }
    return welder_.take();
  }

 private:
  // One facet after its "facet" keyword, through "endfacet".
  Status facet() {
    std::array<std::array<float, 3>, 3> corners;
    std::array<float, 3> normal;  // checked, not kept (texbake computes normals)
    if (Status s = expect("normal", "after 'facet'"); !s) return s;
    if (Status s = numbers("facet normal component", normal); !s) return s;
    if (Status s = expect("outer", "after the facet normal"); !s) return s;
    if (Status s = expect("loop", "after 'outer'"); !s) return s;
    for (auto& corner : corners) {
      if (Status s = expect("vertex", "(a facet has 3 vertices)"); !s) return s;
      if (Status s = numbers("vertex coordinate", corner); !s) return s;
    }
    if (Status s = expect("endloop", "after the third vertex"); !s) return s;
    if (Status s = expect("endfacet", "after 'endloop'"); !s) return s;
    welder_.add_triangle(corners);
    return ok_status();
  }

  // Three finite floats.
  Status numbers(const char* what, std::array<float, 3>& out) {
    std::string_view tok;
    for (float& x : out) {
      if (!next(tok)) return truncated(std::string("before a ") + what);
      const std::optional<float> v = parse_decimal_float(tok);
      if (!v) {
        return error(std::string(what) + " " + quoted(tok) +
                     " is not a finite decimal number within float range");
      }
      x = *v;
    }
    return ok_status();
  }

  // The next token is `keyword` (any case); `where` completes the message.
  Status expect(std::string_view keyword, const std::string& where) {
    std::string_view tok;
    if (!next(tok)) return truncated("before '" + std::string(keyword) + "'");
    if (!same_keyword(tok, keyword)) {
      return error("expected '" + std::string(keyword) + "' " + where + ", got " + quoted(tok));
    }
    return ok_status();
  }

  // The next token; at the end of the text, false and the line stays that of
  // the last token (not past the final line break).
  bool next(std::string_view& tok) {
    const std::size_t line = cursor_.line;
    if (cursor_.next(tok)) return true;
    cursor_.line = line;
    return false;
  }

  Error error(const std::string& what) const {
    return parse_error(path_, "line " + std::to_string(cursor_.line) + ": " + in_facet() + what);
  }
  Error truncated(const std::string& where) const {
    return parse_error(path_, "line " + std::to_string(cursor_.line) + ": " + in_facet() +
                                  "truncated: the file ends " + where);
  }
  // "facet F: " while a facet is being read (facets count from 0).
  std::string in_facet() const {
    return in_facet_ ? "facet " + std::to_string(facet_) + ": " : std::string();
  }

  const fs::path& path_;
  TokenCursor cursor_;
  CornerWelder welder_;
  std::size_t facet_ = 0;
  bool in_facet_ = false;
};

// A binary STL for OpenMesh: every corner finite (the size was checked).
Status check_binary(const fs::path& path, std::string_view bytes) {
  const uint32_t count = binary_count(bytes);
  for (uint32_t t = 0; t < count; ++t) {
    const char* corners = bytes.data() + kBinaryHeader + kBinaryTriangle * t + 12;
    for (int k = 0; k < 9; ++k) {
      const float x = std::bit_cast<float>(load_le32(corners + 4 * k));
      if (!std::isfinite(x)) {
        return parse_error(path, "binary STL triangle " + std::to_string(t) + " vertex " +
                                     std::to_string(k / 3) + " has a non-finite coordinate (" +
                                     std::to_string(x) + ")");
      }
    }
  }
  return ok_status();
}

// The error for a file that is neither ASCII nor a binary STL of its size.
Error bad_binary_size(const fs::path& path, std::string_view bytes) {
  if (bytes.size() < kBinaryHeader) {
    return parse_error(path, "truncated binary STL (" + std::to_string(bytes.size()) +
                                 " bytes; an ASCII STL starts with 'solid')");
  }
  const uint32_t count = binary_count(bytes);
  const unsigned long long expected = kBinaryHeader + 1ull * kBinaryTriangle * count;
  if (bytes.size() < expected) {
    return parse_error(path, "truncated binary STL: header declares " + std::to_string(count) +
                                 " triangles (" + std::to_string(expected) + " bytes), file has " +
                                 std::to_string(bytes.size()) + " bytes");
  }
  return parse_error(path, "binary STL header declares " + std::to_string(count) + " triangles (" +
                               std::to_string(expected) + " bytes), file has " +
                               std::to_string(bytes.size()) +
                               " bytes (data after the triangles, or not an STL file; an ASCII "
                               "STL starts with 'solid')");
}

}  // namespace

Expected<MeshData> read_stl(const fs::path& path, std::string_view bytes) {
  const bool binary = bytes.size() >= kBinaryHeader &&
                      bytes.size() == kBinaryHeader + 1ull * kBinaryTriangle * binary_count(bytes);
  if (!binary) {
    if (!starts_with_solid(bytes) || bytes.find('\0') != std::string_view::npos)
      return bad_binary_size(path, bytes);
    return AsciiStlParser(path, bytes).parse();
  }
  if (Status s = check_binary(path, bytes); !s) return s.error();
  Expected<OpenMeshRead> read = read_with_openmesh(path, NormalsAt::kVertex);
  if (!read) return read.error();
  return mesh_without_negative_index(path, std::move(*read));
}

}  // namespace texbake::read_detail
