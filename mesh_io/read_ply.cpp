// PLY (ASCII, binary little and big endian): a header of elements and
// their properties, then the data. texbake parses it here because OpenMesh
// 9.0's PLYReader (PLYReader.cc, checked with read_openmesh.cpp's importer
// on a test file) loses data silently:
//  - its ASCII path reads with istream >>: a "nan" or garbage token sets the
//    stream's failbit and every later vertex becomes (0,0,0) with the last
//    colour, and the read still succeeds, so NaN cannot even be detected;
//  - it truncates float colours to 8 bits (0.5 -> 127/255) before the
//    importer sees them;
//  - it does not report a truncated binary file.
// It is also slower: the 830k-triangle binary PLY of issue #3 takes 0.109 s
// through OpenMesh's reader with this importer and 0.045 s here (both
// including triangulation and issue counting, warm cache, best of 5).
// The parser checks the header's counts against the file size before it
// allocates anything and names the element where a truncated file ends.
#include <algorithm>
#include <bit>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>

#include "mesh_io/byte_order.h"
#include "mesh_io/read_mesh_internal.h"
#include "mesh_io/text_scan.h"

namespace texbake::read_detail {
namespace fs = std::filesystem;

namespace {

enum class PlyType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

std::optional<PlyType> ply_type(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::kInt8;
  if (s == "uchar" || s == "uint8") return PlyType::kUInt8;
  if (s == "short" || s == "int16") return PlyType::kInt16;
  if (s == "ushort" || s == "uint16") return PlyType::kUInt16;
  if (s == "int" || s == "int32") return PlyType::kInt32;
  if (s == "uint" || s == "uint32") return PlyType::kUInt32;
  if (s == "float" || s == "float32") return PlyType::kFloat32;
  if (s == "double" || s == "float64") return PlyType::kFloat64;
  return std::nullopt;
}

std::size_t ply_size(PlyType t) {
  switch (t) {
    case PlyType::kInt8:
    case PlyType::kUInt8:
      return 1;
    case PlyType::kInt16:
    case PlyType::kUInt16:
      return 2;
    case PlyType::kInt32:
    case PlyType::kUInt32:
    case PlyType::kFloat32:
      return 4;
    case PlyType::kFloat64:
      return 8;
  }
  return 0;
}

bool ply_is_integer(PlyType t) {
  return t != PlyType::kFloat32 && t != PlyType::kFloat64;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;
  bool is_list = false;
  PlyType count_type = PlyType::kUInt8;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
  std::size_t header_line = 0;
};

enum class PlyFormat { kAscii, kBinaryLE, kBinaryBE };

struct PlyHeader {
  PlyFormat format = PlyFormat::kAscii;
  std::vector<PlyElement> elements;
  std::size_t data_offset = 0;  // first byte after "end_header\n"
  std::size_t data_line = 0;    // line number of the first data line (ASCII)
};

Expected<PlyHeader> parse_ply_header(const fs::path& path, std::string_view bytes) {
  PlyHeader h;
  std::size_t pos = 0, line_no = 0;
  bool have_format = false;
  auto next_line = [&](std::string_view& line) {
    if (pos >= bytes.size()) return false;
    std::size_t end = bytes.find('\n', pos);
    if (end == std::string_view::npos) end = bytes.size();
    line = bytes.substr(pos, end - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    pos = std::min(end + 1, bytes.size() + 1);
    ++line_no;
    return true;
  };
  std::string_view line;
  if (!next_line(line) || trim(line) != "ply")
    return parse_error(path, "not a PLY file (no 'ply' magic)");
  while (true) {
    if (!next_line(line)) return parse_error(path, "truncated PLY header (no 'end_header')");
    const std::string at = "line " + std::to_string(line_no) + ": ";
    const auto t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "end_header") break;
    if (t[0] == "format") {
      if (t.size() < 2) return parse_error(path, at + "bad format line");
      if (t[1] == "ascii")
        h.format = PlyFormat::kAscii;
      else if (t[1] == "binary_little_endian")
        h.format = PlyFormat::kBinaryLE;
      else if (t[1] == "binary_big_endian")
        h.format = PlyFormat::kBinaryBE;
      else
        return parse_error(path, at + "unknown PLY format '" + std::string(t[1]) + "'");
      have_format = true;
    } else if (t[0] == "element") {
      unsigned long long count = 0;
      if (t.size() != 3 || !parse_int(t[2], count) ||
          count > std::numeric_limits<uint32_t>::max()) {
        return parse_error(path, at + "bad element line '" + std::string(line) + "'");
      }
      h.elements.push_back({std::string(t[1]), static_cast<std::size_t>(count), {}, line_no});
    } else if (t[0] == "property") {
      if (h.elements.empty()) return parse_error(path, at + "property before any element");
      PlyProperty p;
      if (t.size() == 5 && t[1] == "list") {
        auto ct = ply_type(t[2]);
        auto vt = ply_type(t[3]);
        if (!ct || !vt || !ply_is_integer(*ct))
          return parse_error(path, at + "bad list property '" + std::string(line) + "'");
        p = {std::string(t[4]), *vt, true, *ct};
      } else if (t.size() == 3) {
        auto vt = ply_type(t[1]);
        if (!vt) return parse_error(path, at + "unknown property type '" + std::string(t[1]) + "'");
        p = {std::string(t[2]), *vt, false, PlyType::kUInt8};
      } else {
        return parse_error(path, at + "bad property line '" + std::string(line) + "'");
      }
      h.elements.back().properties.push_back(p);
    } else {
      return parse_error(path, at + "unknown header keyword '" + std::string(t[0]) + "'");
    }
  }
  if (!have_format) return parse_error(path, "PLY header has no 'format' line");
  h.data_offset = std::min(pos, bytes.size());
  h.data_line = line_no + 1;
  return h;
}

// Reads one value of type T from binary data, byte-swapping if needed.
template <class T>
inline T load(const char* p, bool swap) {
  T v;
  std::memcpy(&v, p, sizeof(T));
  if (swap) {
    if constexpr (sizeof(T) == 2) {
      uint16_t u;
      std::memcpy(&u, &v, 2);
      u = byte_swap(u);
      std::memcpy(&v, &u, 2);
    } else if constexpr (sizeof(T) == 4) {
      uint32_t u;
      std::memcpy(&u, &v, 4);
      u = byte_swap(u);
      std::memcpy(&v, &u, 4);
    } else if constexpr (sizeof(T) == 8) {
      uint64_t u;
      std::memcpy(&u, &v, 8);
      u = byte_swap(u);
      std::memcpy(&v, &u, 8);
    }
  }
  return v;
}

inline double load_as_double(PlyType t, const char* p, bool swap) {
  switch (t) {
    case PlyType::kInt8:
      return load<int8_t>(p, swap);
    case PlyType::kUInt8:
      return load<uint8_t>(p, swap);
    case PlyType::kInt16:
      return load<int16_t>(p, swap);
    case PlyType::kUInt16:
      return load<uint16_t>(p, swap);
    case PlyType::kInt32:
      return load<int32_t>(p, swap);
    case PlyType::kUInt32:
      return load<uint32_t>(p, swap);
    case PlyType::kFloat32:
      return load<float>(p, swap);
    case PlyType::kFloat64:
      return load<double>(p, swap);
  }
  return 0;
}

// What a vertex property feeds.
enum class VTarget { kNone, kX, kY, kZ, kNx, kNy, kNz, kR, kG, kB, kA, kU, kV };

VTarget vertex_target(const std::string& n) {
  if (n == "x") return VTarget::kX;
  if (n == "y") return VTarget::kY;
  if (n == "z") return VTarget::kZ;
  if (n == "nx") return VTarget::kNx;
  if (n == "ny") return VTarget::kNy;
  if (n == "nz") return VTarget::kNz;
  if (n == "red" || n == "r" || n == "diffuse_red") return VTarget::kR;
  if (n == "green" || n == "g" || n == "diffuse_green") return VTarget::kG;
  if (n == "blue" || n == "b" || n == "diffuse_blue") return VTarget::kB;
  if (n == "alpha" || n == "a" || n == "diffuse_alpha") return VTarget::kA;
  if (n == "s" || n == "u" || n == "texture_u" || n == "texture_s") return VTarget::kU;
  if (n == "t" || n == "v" || n == "texture_v" || n == "texture_t") return VTarget::kV;
  return VTarget::kNone;
}

// Integer colours are divided by their type's maximum (uchar 255, ushort 65535).
float colour_divisor(PlyType t) {
  switch (t) {
    case PlyType::kUInt8:
    case PlyType::kInt8:
      return 255.f;
    case PlyType::kUInt16:
    case PlyType::kInt16:
      return 65535.f;
    case PlyType::kUInt32:
    case PlyType::kInt32:
      return 4294967295.f;
    default:
      return 1.f;
  }
}

struct VertexLayout {
  std::vector<VTarget> targets;  // per property
  bool has_normals = false, has_colors = false, has_uvs = false, has_alpha = false;
  bool has_xyz = false;
};

VertexLayout vertex_layout(const PlyElement& e) {
  VertexLayout l;
  bool x = false, y = false, z = false, u = false, v = false, n = false, c = false;
  for (const auto& p : e.properties) {
    VTarget t = p.is_list ? VTarget::kNone : vertex_target(p.name);
    l.targets.push_back(t);
    x |= t == VTarget::kX;
    y |= t == VTarget::kY;
    z |= t == VTarget::kZ;
    n |= t == VTarget::kNx || t == VTarget::kNy || t == VTarget::kNz;
    c |= t == VTarget::kR || t == VTarget::kG || t == VTarget::kB;
    l.has_alpha |= t == VTarget::kA;
    u |= t == VTarget::kU;
    v |= t == VTarget::kV;
  }
  l.has_xyz = x && y && z;
  l.has_normals = n;
  l.has_colors = c || l.has_alpha;
  l.has_uvs = u && v;
  return l;
}

// The vertex values of one vertex, filled property by property.
struct VertexValues {
  float p[3] = {0, 0, 0}, n[3] = {0, 0, 0}, c[4] = {0, 0, 0, 1}, uv[2] = {0, 0};
  void set(VTarget t, double value, float cdiv) {
    switch (t) {
      case VTarget::kX:
        p[0] = static_cast<float>(value);
        break;
      case VTarget::kY:
        p[1] = static_cast<float>(value);
        break;
      case VTarget::kZ:
        p[2] = static_cast<float>(value);
        break;
      case VTarget::kNx:
        n[0] = static_cast<float>(value);
        break;
      case VTarget::kNy:
        n[1] = static_cast<float>(value);
        break;
      case VTarget::kNz:
        n[2] = static_cast<float>(value);
        break;
      case VTarget::kR:
        c[0] = static_cast<float>(value) / cdiv;
        break;
      case VTarget::kG:
        c[1] = static_cast<float>(value) / cdiv;
        break;
      case VTarget::kB:
        c[2] = static_cast<float>(value) / cdiv;
        break;
      case VTarget::kA:
        c[3] = static_cast<float>(value) / cdiv;
        break;
      case VTarget::kU:
        uv[0] = static_cast<float>(value);
        break;
      case VTarget::kV:
        uv[1] = static_cast<float>(value);
        break;
      case VTarget::kNone:
        break;
    }
  }
};

struct PlyReadState {
  const fs::path& path;
  const PlyHeader& header;
  MeshData mesh;
  std::vector<Float3> vertex_normals;
  std::vector<Float2> vertex_uvs;
  VertexLayout layout;
  const PlyElement* vertex_element = nullptr;
  const PlyElement* face_element = nullptr;
  std::size_t face_property = 0;
};

void store_vertex(PlyReadState& s, std::size_t i, const VertexValues& v) {
  s.mesh.positions[i] = {v.p[0], v.p[1], v.p[2]};
  if (s.layout.has_normals) s.vertex_normals[i] = {v.n[0], v.n[1], v.n[2]};
  if (s.layout.has_colors) s.mesh.vertex_colors[i] = {v.c[0], v.c[1], v.c[2], v.c[3]};
  if (s.layout.has_uvs) s.vertex_uvs[i] = {v.uv[0], v.uv[1]};
}

Status read_ply_binary(PlyReadState& s, std::string_view bytes, bool swap) {
  const char* p = bytes.data() + s.header.data_offset;
  const char* end = bytes.data() + bytes.size();
  for (const PlyElement& e : s.header.elements) {
    // Nothing to read (and a huge count must not cost a loop: the fuzzer
    // found "element x 1899460386" without properties running for minutes).
    if (e.properties.empty()) continue;
    const bool is_vertex = &e == s.vertex_element;
    const bool is_face = &e == s.face_element;
    // Fixed-size records (no lists): one bounds check per element.
    bool fixed = true;
    std::size_t record = 0;
    for (const auto& prop : e.properties) {
      if (prop.is_list)
        fixed = false;
      else
        record += ply_size(prop.type);
    }
    if (fixed && static_cast<std::size_t>(end - p) / std::max<std::size_t>(record, 1) < e.count &&
        record > 0) {
      const std::size_t whole = static_cast<std::size_t>(end - p) / record;
      return parse_error(s.path, "truncated: element '" + e.name + "' declares " +
                                     std::to_string(e.count) +
                                     " records, the file ends in record " + std::to_string(whole));
    }
    if (is_vertex && !swap && e.properties.size() == 3 &&
        std::all_of(e.properties.begin(), e.properties.end(),
                    [](const PlyProperty& q) { return q.type == PlyType::kFloat32; }) &&
        s.layout.targets == std::vector<VTarget>{VTarget::kX, VTarget::kY, VTarget::kZ}) {
      // The usual vertex element, x y z as floats in this machine's byte
      // order: its records are the positions' own bytes (Float3), copied
      // whole. (The bounds were checked above; the coordinates are checked
      // for finiteness after reading, as for every format.)
      static_assert(sizeof(Float3) == 12);
      std::memcpy(s.mesh.positions.data(), p, e.count * sizeof(Float3));
      p += e.count * sizeof(Float3);
      continue;
    }
    if (is_face && e.properties.size() == 1 && s.face_property == 0 && !swap &&
        e.properties[0].is_list && e.properties[0].count_type == PlyType::kUInt8 &&
        (e.properties[0].type == PlyType::kInt32 || e.properties[0].type == PlyType::kUInt32)) {
      // The usual face element, one list of a uchar count and 32-bit
      // indices in this machine's byte order: the loop below without its
      // per-value type dispatch, with the same checks and messages.
      const auto nv = static_cast<uint32_t>(s.mesh.positions.size());
      const bool is_signed = e.properties[0].type == PlyType::kInt32;
      auto truncated = [&](std::size_t i) {
        return parse_error(s.path, "truncated: the file ends in " + e.name + " " +
                                       std::to_string(i) + " of " + std::to_string(e.count));
      };
      for (std::size_t i = 0; i < e.count; ++i) {
        if (p == end) return truncated(i);
        const auto n = static_cast<uint8_t>(*p++);
        if (static_cast<std::size_t>(end - p) / 4 < n) return truncated(i);
        for (uint32_t j = 0; j < n; ++j, p += 4) {
          uint32_t idx;
          std::memcpy(&idx, p, 4);
          if (idx >= nv) {  // a negative int32 is >= nv as unsigned
            const long long shown = is_signed ? static_cast<long long>(static_cast<int32_t>(idx))
                                              : static_cast<long long>(idx);
            return parse_error(s.path, "face " + std::to_string(i) + " refers to vertex " +
                                           std::to_string(shown) + " but there are " +
                                           std::to_string(nv) + " vertices");
          }
          s.mesh.face_vertices.push_back(idx);
        }
        s.mesh.face_offsets.push_back(static_cast<uint32_t>(s.mesh.face_vertices.size()));
      }
      continue;
    }
    std::vector<float> cscale(e.properties.size());
    for (std::size_t k = 0; k < e.properties.size(); ++k)
      cscale[k] = colour_divisor(e.properties[k].type);
    for (std::size_t i = 0; i < e.count; ++i) {
      VertexValues v;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& prop = e.properties[k];
        if (!prop.is_list) {
          // Records with a list have no up-front bounds check: check each
          // value (found by the fuzzer: a vertex element with a list).
          if (!fixed && end - p < static_cast<std::ptrdiff_t>(ply_size(prop.type))) {
            return parse_error(s.path, "truncated: the file ends in " + e.name + " " +
                                           std::to_string(i) + " of " + std::to_string(e.count));
          }
          if (is_vertex) v.set(s.layout.targets[k], load_as_double(prop.type, p, swap), cscale[k]);
          p += ply_size(prop.type);
          continue;
        }
        const std::size_t cs = ply_size(prop.count_type);
        if (end - p < static_cast<std::ptrdiff_t>(cs)) {
          return parse_error(s.path, "truncated: the file ends in " + e.name + " " +
                                         std::to_string(i) + " of " + std::to_string(e.count));
        }
        const double n_d = load_as_double(prop.count_type, p, swap);
        p += cs;
        if (n_d < 0)
          return parse_error(s.path,
                             e.name + " " + std::to_string(i) + " has a negative list length");
        const std::size_t n = static_cast<std::size_t>(n_d);
        if (is_face && k == s.face_property && n > kMaxFaceCorners)
          return parse_error(s.path, e.name + " " + std::to_string(i) + " " + too_many_corners(n));
        const std::size_t vs = ply_size(prop.type);
        if (static_cast<std::size_t>(end - p) / vs < n) {
          return parse_error(s.path, "truncated: the file ends in " + e.name + " " +
                                         std::to_string(i) + " of " + std::to_string(e.count));
        }
        if (is_face && k == s.face_property) {
          if (!ply_is_integer(prop.type))
            return parse_error(s.path, "face vertex indices are not integers");
          for (std::size_t j = 0; j < n; ++j) {
            const double idx = load_as_double(prop.type, p + j * vs, swap);
            if (idx < 0 || idx >= static_cast<double>(s.mesh.positions.size())) {
              return parse_error(s.path, "face " + std::to_string(i) + " refers to vertex " +
                                             std::to_string(static_cast<long long>(idx)) +
                                             " but there are " +
                                             std::to_string(s.mesh.positions.size()) + " vertices");
            }
            s.mesh.face_vertices.push_back(static_cast<uint32_t>(idx));
          }
          s.mesh.face_offsets.push_back(static_cast<uint32_t>(s.mesh.face_vertices.size()));
        }
        p += n * vs;
      }
      if (is_vertex) store_vertex(s, i, v);
    }
  }
  // Bytes after the last element mean the header's counts are too small.
  for (const char* q = p; q < end; ++q) {
    if (!std::isspace(static_cast<unsigned char>(*q)) && *q != '\0') {
      return parse_error(
          s.path, std::to_string(end - p) +
                      " bytes follow the last element: the header's counts do not match the data");
    }
  }
  return ok_status();
}

Status read_ply_ascii(PlyReadState& s, std::string_view bytes) {
  TokenCursor cur{bytes.substr(s.header.data_offset), 0, s.header.data_line};
  std::string_view tok;
  auto at = [&] { return "line " + std::to_string(cur.line) + ": "; };
  auto number = [&](const std::string& what, std::size_t i,
                    const PlyElement& e) -> Expected<double> {
    if (!cur.next(tok)) {
      return parse_error(s.path, "truncated: the file ends in " + e.name + " " + std::to_string(i) +
                                     " of " + std::to_string(e.count) + " (line " +
                                     std::to_string(cur.line) + ")");
    }
    std::optional<double> v = parse_number(tok);
    if (!v) return parse_error(s.path, at() + what + " '" + std::string(tok) + "' is not a number");
    return *v;
  };
  for (const PlyElement& e : s.header.elements) {
    // Nothing to read (and a huge count must not cost a loop: the fuzzer
    // found "element x 1899460386" without properties running for minutes).
    if (e.properties.empty()) continue;
    const bool is_vertex = &e == s.vertex_element;
    const bool is_face = &e == s.face_element;
    std::vector<float> cscale(e.properties.size());
    for (std::size_t k = 0; k < e.properties.size(); ++k)
      cscale[k] = colour_divisor(e.properties[k].type);
    for (std::size_t i = 0; i < e.count; ++i) {
      VertexValues v;
      for (std::size_t k = 0; k < e.properties.size(); ++k) {
        const PlyProperty& prop = e.properties[k];
        if (!prop.is_list) {
          Expected<double> x = number("value of '" + prop.name + "'", i, e);
          if (!x) return x.error();
          if (is_vertex) {
            const VTarget t = s.layout.targets[k];
            if ((t == VTarget::kX || t == VTarget::kY || t == VTarget::kZ) &&
                !std::isfinite(static_cast<float>(*x))) {
              return parse_error(s.path, at() + "vertex " + std::to_string(i) + " coordinate '" +
                                             std::string(tok) + "' is not a finite number");
            }
            v.set(t, *x, cscale[k]);
          }
          continue;
        }
        Expected<double> n_d = number("list length", i, e);
        if (!n_d) return n_d.error();
        if (*n_d < 0 || *n_d != std::floor(*n_d) || *n_d > 1e6) {
          return parse_error(s.path, at() + "bad list length '" + std::string(tok) + "'");
        }
        if (is_face && k == s.face_property && *n_d > static_cast<double>(kMaxFaceCorners)) {
          return parse_error(s.path, at() + e.name + " " + std::to_string(i) + " " +
                                         too_many_corners(static_cast<std::size_t>(*n_d)));
        }
        const std::size_t n = static_cast<std::size_t>(*n_d);
        for (std::size_t j = 0; j < n; ++j) {
          Expected<double> idx = number("list value", i, e);
          if (!idx) return idx.error();
          if (is_face && k == s.face_property) {
            if (*idx < 0 || *idx >= static_cast<double>(s.mesh.positions.size()) ||
                *idx != std::floor(*idx)) {
              return parse_error(s.path, at() + "face " + std::to_string(i) + " refers to vertex " +
                                             std::string(tok) + " but there are " +
                                             std::to_string(s.mesh.positions.size()) + " vertices");
            }
            s.mesh.face_vertices.push_back(static_cast<uint32_t>(*idx));
          }
        }
        if (is_face && k == s.face_property) {
          s.mesh.face_offsets.push_back(static_cast<uint32_t>(s.mesh.face_vertices.size()));
        }
      }
      if (is_vertex) store_vertex(s, i, v);
    }
  }
  if (cur.next(tok)) {
    return parse_error(s.path, at() + "data after the last element ('" + std::string(tok) +
                                   "'): the header's counts do not match the data");
  }
  return ok_status();
}

}  // namespace

Expected<MeshData> read_ply(const fs::path& path, std::string_view bytes) {
  Expected<PlyHeader> header = parse_ply_header(path, bytes);
  if (!header) return header.error();
  PlyReadState s{path, *header, {}, {}, {}, {}, nullptr, nullptr, 0};
  for (const PlyElement& e : header->elements) {
    if (e.name == "vertex" && !s.vertex_element) s.vertex_element = &e;
    if (e.name == "face" && !s.face_element) s.face_element = &e;
  }
  if (!s.vertex_element) return parse_error(path, "PLY header has no 'vertex' element");
  s.layout = vertex_layout(*s.vertex_element);
  if (!s.layout.has_xyz) return parse_error(path, "PLY vertex element lacks x, y or z");
  if (s.face_element) {
    bool found = false;
    for (std::size_t k = 0; k < s.face_element->properties.size(); ++k) {
      const auto& p = s.face_element->properties[k];
      if (p.is_list && (p.name == "vertex_indices" || p.name == "vertex_index")) {
        s.face_property = k;
        found = true;
        break;
      }
    }
    if (!found) return parse_error(path, "PLY face element has no vertex_indices list");
  }
  // Reject a lying header before allocating: every record needs at least
  // this many bytes (binary: its fixed part plus a 3-index list; ASCII: one
  // character and one separator per value).
  const bool binary = header->format != PlyFormat::kAscii;
  double needed = 0;
  for (const PlyElement& e : header->elements) {
    double rec = 0;
    for (const auto& p : e.properties) {
      if (binary)
        rec += p.is_list ? ply_size(p.count_type) : ply_size(p.type);
      else
        rec += 2;
    }
    if (&e == s.face_element)
      rec += binary ? 3.0 * ply_size(e.properties[s.face_property].type) : 6.0;
    needed += rec * static_cast<double>(e.count);
  }
  const double available = static_cast<double>(bytes.size() - header->data_offset);
  if (needed > available) {
    return parse_error(
        path, "truncated or lying header: the elements declared need at least " +
                  std::to_string(static_cast<long long>(needed)) + " bytes, the file has " +
                  std::to_string(static_cast<long long>(available)) + " after the header");
  }
  const std::size_t nv = s.vertex_element->count;
  s.mesh.positions.resize(nv);
  if (s.layout.has_normals) s.vertex_normals.resize(nv);
  if (s.layout.has_colors) s.mesh.vertex_colors.resize(nv);
  if (s.layout.has_uvs) s.vertex_uvs.resize(nv);
  s.mesh.face_offsets = {0};
  if (s.face_element) {
    s.mesh.face_offsets.reserve(s.face_element->count + 1);
    s.mesh.face_vertices.reserve(3 * s.face_element->count);
  }
  Status st = ok_status();
  switch (header->format) {
    case PlyFormat::kAscii:
      st = read_ply_ascii(s, bytes);
      break;
    case PlyFormat::kBinaryLE:
      st = read_ply_binary(s, bytes, std::endian::native != std::endian::little);
      break;
    case PlyFormat::kBinaryBE:
      st = read_ply_binary(s, bytes, std::endian::native != std::endian::big);
      break;
  }
  if (!st) return st.error();
  MeshData& mesh = s.mesh;
  // Per-vertex normals/UVs become per-corner tables indexed by the vertex.
  if (s.layout.has_normals) {
    mesh.normals = std::move(s.vertex_normals);
    mesh.corner_normal.assign(mesh.face_vertices.begin(), mesh.face_vertices.end());
  }
  if (s.layout.has_uvs) {
    mesh.uvs = std::move(s.vertex_uvs);
    mesh.corner_uv.assign(mesh.face_vertices.begin(), mesh.face_vertices.end());
  }
  return std::move(mesh);
}

}  // namespace texbake::read_detail
