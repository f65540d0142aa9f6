// OFF (geomview's format: a "[ST][C][N][4][n]OFF" keyword, the counts
// "vertices faces edges", one vertex per line "x y z [nx ny nz] [colour]
// [s t]", one face per line "n i0 .. in-1 [colour]", '#' comments).
// ASCII OFF is parsed here, not by OpenMesh: OpenMesh 9.0's reader
// (OFFReader.cc, read_ascii) reads counts and indices with istream >> into
// uninitialised variables and never checks the stream, so a short or garbled
// file makes it loop over garbage counts (the fuzzer found a 15-byte file that
// made it allocate 2 GB: tests/fuzz/regressions/fuzz_mesh_off), it does not
// skip comments, and it ignores counts written on the keyword line.
// Binary OFF ("OFF BINARY") still goes through OpenMesh (read_openmesh.cpp),
// after check_off_binary has walked the file exactly as OpenMesh will read it.
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "mesh_io/read_mesh_internal.h"
#include "mesh_io/text_scan.h"

namespace texbake::read_detail {
namespace fs = std::filesystem;

namespace {

struct OffKeyword {
  bool normals = false, colors = false, texcoords = false, high_dimension = false;
};

std::optional<OffKeyword> off_keyword(std::string_view tok) {
  if (tok.size() < 3 || tok.substr(tok.size() - 3) != "OFF") return std::nullopt;
  std::string_view p = tok.substr(0, tok.size() - 3);
  OffKeyword k;
  auto take = [&](std::string_view prefix, bool& flag) {
    if (p.substr(0, prefix.size()) == prefix) {
      flag = true;
      p.remove_prefix(prefix.size());
    }
  };
  take("ST", k.texcoords);
  take("C", k.colors);
  take("N", k.normals);
  take("4", k.high_dimension);
  take("n", k.high_dimension);
  if (!p.empty()) return std::nullopt;
  return k;
}

// Walks a binary OFF as OpenMesh's read_binary does (little-endian 32-bit
// values after the keyword line; vertex: xyz [normal] [colour as 3 floats,
// we ask for ColorFloat] [st]; face: n, then n indices; no face colours, we
// do not ask for them) and checks that every value it reads is in the file
// and every index in range, so OpenMesh never reads past the end.
Status check_off_binary(const fs::path& path, std::string_view bytes, const OffKeyword& k) {
  std::size_t pos = bytes.find('\n');
  if (pos == std::string_view::npos) return parse_error(path, "truncated binary OFF (no data)");
  ++pos;
  const auto left = [&] { return static_cast<unsigned long long>(bytes.size() - pos); };
  if (left() < 12) return parse_error(path, "truncated binary OFF: no vertex/face counts");
  const unsigned long long nv = load_le32(bytes.data() + pos),
                           nf = load_le32(bytes.data() + pos + 4);
  pos += 12;
  const unsigned long long record =
      4ull * (3 + (k.normals ? 3 : 0) + (k.colors ? 3 : 0) + (k.texcoords ? 2 : 0));
  if (nv * record + nf * 4 > left()) {
    return parse_error(path, "binary OFF header declares " + std::to_string(nv) + " vertices and " +
                                 std::to_string(nf) +
                                 " faces, more than the file can hold (truncated or lying header)");
  }
  pos += static_cast<std::size_t>(nv * record);
  for (unsigned long long f = 0; f < nf; ++f) {
    if (left() < 4)
      return parse_error(path, "truncated binary OFF: ends in face " + std::to_string(f));
    const unsigned long long n = load_le32(bytes.data() + pos);
    pos += 4;
    if (n > kMaxFaceCorners)
      return parse_error(path, "face " + std::to_string(f) + " " + too_many_corners(n));
    if (n * 4 > left()) {
      return parse_error(path, "truncated binary OFF: face " + std::to_string(f) + " declares " +
                                   std::to_string(n) + " corners, the file ends first");
    }
    for (unsigned long long c = 0; c < n; ++c, pos += 4) {
      const uint32_t idx = load_le32(bytes.data() + pos);
      if (idx >= nv) {
        return parse_error(path, "face " + std::to_string(f) + " refers to vertex " +
                                     std::to_string(idx) + " but there are " + std::to_string(nv) +
                                     " vertices");
      }
    }
  }
  return ok_status();
}

Expected<MeshData> read_off_ascii(const fs::path& path, std::string_view text) {
  // Content lines: comments ('#' to the end of the line) and blank lines skipped.
  std::size_t pos = 0, line_no = 0;
  std::vector<std::string_view> t;
  auto next_line = [&]() -> bool {
    while (pos < text.size()) {
      std::size_t end = text.find('\n', pos);
      if (end == std::string_view::npos) end = text.size();
      std::string_view line = text.substr(pos, end - pos);
      pos = end + 1;
      ++line_no;
      t = tokens(line.substr(0, line.find('#')));
      if (!t.empty()) return true;
    }
    return false;
  };
  auto at = [&] { return "line " + std::to_string(line_no) + ": "; };
  if (!next_line()) return parse_error(path, "no 'OFF' keyword (the file has no content)");
  const std::optional<OffKeyword> k = off_keyword(t[0]);
  if (!k)
    return parse_error(path, at() + "not an OFF file (expected the keyword 'OFF', got '" +
                                 std::string(t[0]) + "')");
  if (k->high_dimension) {
    return parse_error(
        path, at() + "'" + std::string(t[0]) + "': 4D and n-dimensional OFF are not supported");
  }
  t.erase(t.begin());
  if (t.empty() && !next_line()) return parse_error(path, "no vertex/face counts after 'OFF'");
  unsigned long long nv = 0, nf = 0;
  if (t.size() < 2 || !parse_int(t[0], nv) || !parse_int(t[1], nf)) {
    return parse_error(path, at() + "expected 'vertices faces edges' counts");
  }
  // Every vertex line needs at least "x y z\n" (6 bytes), every face "n\n"
  // (2 bytes): reject a lying header before allocating anything.
  if (static_cast<double>(nv) * 6 + static_cast<double>(nf) * 2 >
      static_cast<double>(text.size()) + 1) {
    return parse_error(path, at() + "header declares " + std::to_string(nv) + " vertices and " +
                                 std::to_string(nf) +
                                 " faces, more than the file can hold (truncated or lying header)");
  }
  auto truncated = [&](unsigned long long vertices, unsigned long long faces) {
    return parse_error(path, "truncated: header declares " + std::to_string(nv) + " vertices and " +
                                 std::to_string(nf) + " faces, the file ends after " +
                                 std::to_string(vertices) + " vertices and " +
                                 std::to_string(faces) + " faces (line " + std::to_string(line_no) +
                                 ")");
  };
  MeshData mesh;
  mesh.positions.reserve(nv);
  if (k->normals) mesh.normals.reserve(nv);
  const std::size_t fixed = 3 + (k->normals ? 3 : 0);
  for (unsigned long long i = 0; i < nv; ++i) {
    if (!next_line()) return truncated(i, 0);
    double x[6] = {0, 0, 0, 0, 0, 0};
    for (std::size_t j = 0; j < fixed; ++j) {
      std::optional<double> v = j < t.size() ? parse_number(t[j]) : std::nullopt;
      if (!v || !std::isfinite(static_cast<float>(*v))) {
        return parse_error(path, at() + (j < 3 ? "vertex coordinate '" : "vertex normal '") +
                                     (j < t.size() ? std::string(t[j]) : std::string("(missing)")) +
                                     "' is not a finite number");
      }
      x[j] = *v;
    }
    mesh.positions.push_back(
        {static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2])});
    if (k->normals) {
      mesh.normals.push_back(
          {static_cast<float>(x[3]), static_cast<float>(x[4]), static_cast<float>(x[5])});
    }
    // Colour: 3 or 4 values after the coordinates (and before s t), floats in
    // [0, 1] if written with a '.' or exponent, else integers in [0, 255]; a
    // single colour-map index is ignored (there is no map).
    const std::size_t extra = t.size() - fixed - (k->texcoords && t.size() >= fixed + 2 ? 2 : 0);
    if (k->colors && (extra == 3 || extra == 4)) {
      std::array<float, 4> c = {0, 0, 0, 1};
      bool is_float = false;
      for (std::size_t j = 0; j < extra; ++j)
        is_float |= t[fixed + j].find_first_of(".eE") != std::string_view::npos;
      for (std::size_t j = 0; j < extra; ++j) {
        std::optional<double> v = parse_number(t[fixed + j]);
        if (!v || !std::isfinite(*v)) {
          return parse_error(
              path, at() + "vertex colour '" + std::string(t[fixed + j]) + "' is not a number");
        }
        c[j] = static_cast<float>(is_float ? *v : *v / 255.0);
      }
      if (mesh.vertex_colors.empty()) mesh.vertex_colors.resize(nv, {1, 1, 1, 1});
      mesh.vertex_colors[i] = c;
    }
  }
  mesh.face_offsets.reserve(nf + 1);
  mesh.face_offsets.push_back(0);
  for (unsigned long long f = 0; f < nf; ++f) {
    if (!next_line()) return truncated(nv, f);
    unsigned long long n = 0;
    if (!parse_int(t[0], n) || n + 1 > t.size()) {
      return parse_error(path, at() + "face has fewer indices than its count");
    }
    if (n > kMaxFaceCorners) return parse_error(path, at() + "face " + too_many_corners(n));
    for (unsigned long long c = 1; c <= n; ++c) {
      unsigned long long idx = 0;
      if (!parse_int(t[c], idx) || idx >= nv) {
        return parse_error(path, at() + "face index '" + std::string(t[c]) + "' is out of range (" +
                                     std::to_string(nv) + " vertices)");
      }
      mesh.face_vertices.push_back(static_cast<uint32_t>(idx));
    }
    mesh.face_offsets.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
  }
  if (k->normals) mesh.corner_normal.assign(mesh.face_vertices.begin(), mesh.face_vertices.end());
  return mesh;
}

}  // namespace

Expected<MeshData> read_off(const fs::path& path, std::string_view b) {
  // Binary exactly as OpenMesh's OFFReader::can_u_read detects it: the
  // keyword at the start of the file, one character, "BINARY".
  const auto first = tokens(b.substr(0, std::min(b.find('\n'), b.size())));
  const std::optional<OffKeyword> k =
      first.empty() || first[0].data() != b.data() ? std::nullopt : off_keyword(first[0]);
  if (!k || first[0].size() + 1 > b.size() || b.substr(first[0].size() + 1, 6) != "BINARY")
    return read_off_ascii(path, b);
  if (k->high_dimension) return parse_error(path, "4D and n-dimensional OFF are not supported");
  if (Status s = check_off_binary(path, b, *k); !s) return s.error();
  Expected<OpenMeshRead> read = read_with_openmesh(path, NormalsAt::kVertex);
  if (!read) return read.error();
  return mesh_without_negative_index(path, std::move(*read));
}

}  // namespace texbake::read_detail
