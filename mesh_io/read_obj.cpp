// OBJ (Wavefront: v, vt, vn, f with v/t/n corners, mtllib and the
// material's map_Kd texture). OpenMesh 9.0's OBJ reader parses it (through
// the importer of read_openmesh.cpp); check_obj below first checks every line
// that reader acts on, because the reader trusts its input (see check_obj
// for what it gets wrong). After the read, the vertex count is compared with
// the `v` lines (a number strtod reads but OpenMesh's istream does not would
// shift every index) and the texture of the faces' material is resolved.
#include <cmath>
#include <optional>

#include "mesh_io/read_mesh_internal.h"
#include "mesh_io/regular_file.h"
#include "mesh_io/text_scan.h"

namespace texbake::read_detail {
namespace fs = std::filesystem;

namespace {

// OBJ checks made before OpenMesh reads the file. OpenMesh 9.0's OBJ reader
// (OBJReader.cc) reads face corners with istream >> into an int it neither
// initialises nor checks: a corner without its vertex part ("/1/2") trips an
// assertion (abort; found by the fuzzer: tests/fuzz/regressions/
// fuzz_mesh_obj), a part that is not a number keeps the previous corner's
// value, an index past INT_MAX overflows. It silently skips `v` and `vn`
// lines whose numbers do not parse (nan, inf, garbage) but still counts them
// for relative indices, which shifts every later index. And it opens
// whatever `mtllib` names relative to the OBJ (a device such as /dev/zero
// would be read forever). So every line OpenMesh acts on is checked here
// first, split the way OpenMesh splits it (lines at '\n', the keyword is the
// first token):
// - v: three finite numbers (colours after them are OpenMesh's business);
//   vn: three numbers;
// - f: every corner is v, v/t, v/t/n or v//n with integer parts, v present;
//   an index is 1-based, positive ones within the file's count of its kind,
//   negative ones within the count so far (OBJ's relative indices);
// - mtllib: the file named, if it exists, is a regular file of at most
//   kMaxTextFileBytes (OpenMesh reads it whole, line by line).
// Returns the number of `v` lines.
Expected<std::size_t> check_obj(const fs::path& path, std::string_view text) {
  struct Counts {
    long long v = 0, vt = 0, vn = 0;
  };
  Counts total;
  std::optional<Error> err;
  auto fail = [&](std::size_t no, const std::string& what) {
    err = parse_error(path, "line " + std::to_string(no) + ": " + what);
    return false;
  };
  // Pass 1: vertex data, as OpenMesh's read_vertices.
  for_each_line(text, [&](std::string_view line, std::size_t no) {
    const auto t = tokens(line);
    if (t.empty() || t[0].front() == '#') return true;
    const bool is_v = t[0] == "v", is_vn = t[0] == "vn";
    if (t[0] == "vt") ++total.vt;
    if (!is_v && !is_vn) return true;
    ++(is_v ? total.v : total.vn);
    for (std::size_t i = 1; i < 4; ++i) {
      std::optional<double> x = i < t.size() ? parse_number(t[i]) : std::nullopt;
      if (!x || !std::isfinite(static_cast<float>(*x))) {
        return fail(no, std::string(is_v ? "vertex coordinate '" : "normal coordinate '") +
                            (i < t.size() ? std::string(t[i]) : std::string("(missing)")) +
                            "' is not a finite number");
      }
    }
    return true;
  });
  if (err) return *err;
  // Pass 2: faces and material libraries, as OpenMesh's second pass.
  Counts so_far;
  const std::string dir = path.has_parent_path() ? path.parent_path().string() : ".";
  for_each_line(text, [&](std::string_view line, std::size_t no) {
    const auto t = tokens(line);
    if (t.empty() || t[0].front() == '#') return true;
    if (t[0] == "v") ++so_far.v;
    if (t[0] == "vt") ++so_far.vt;
    if (t[0] == "vn") ++so_far.vn;
    if (t[0] == "mtllib") {
      const std::string_view rest = trim(line.substr(line.find("mtllib") + 6));
      // OpenMesh opens it as the OBJ's folder + the name; a missing library
      // is only a missing texture (OpenMesh warns).
      const fs::path lib = dir + "/" + std::string(rest);
      std::error_code ec;
      if (fs::exists(lib, ec)) {
        if (Status s = check_text_file(lib, "a material library"); !s) {
          // kIo: not a regular file; kParse: over the size limit.
          return fail(no, "material library '" + std::string(rest) + "' " +
                              (s.error().code == ErrorCode::kIo
                                   ? std::string("is not a regular file")
                                   : "is larger than texbake reads (" +
                                         std::to_string(kMaxTextFileBytes >> 20) + " MiB)"));
        }
      }
    }
    if (t[0] != "f") return true;
    if (t.size() - 1 > kMaxFaceCorners) return fail(no, "face " + too_many_corners(t.size() - 1));
    for (std::size_t i = 1; i < t.size(); ++i) {
      const std::string_view corner = t[i];
      std::string_view part[3];
      std::size_t parts = 0, start = 0;
      while (true) {
        const std::size_t slash = corner.find('/', start);
        if (parts == 3)
          return fail(no, "face corner '" + std::string(corner) + "' has more than 3 parts");
        part[parts++] =
            corner.substr(start, slash == std::string_view::npos ? slash : slash - start);
        if (slash == std::string_view::npos) break;
        start = slash + 1;
      }
      static constexpr const char* kWhat[3] = {"face index", "texture coordinate index",
                                               "normal index"};
      const long long count[3] = {total.v, total.vt, total.vn};
      const long long before[3] = {so_far.v, so_far.vt, so_far.vn};
      for (std::size_t k = 0; k < parts; ++k) {
        if (part[k].empty()) {
          if (k == 0)
            return fail(no, "face corner '" + std::string(corner) + "' has no vertex index");
          continue;
        }
        long long idx = 0;
        if (!parse_int(part[k], idx)) {
          return fail(no,
                      std::string(kWhat[k]) + " '" + std::string(part[k]) + "' is not an integer");
        }
        const long long resolved = idx < 0 ? before[k] + idx + 1 : idx;
        if (idx == 0 || resolved < 1 || resolved > (idx < 0 ? before[k] : count[k])) {
          return fail(no, std::string(kWhat[k]) + " " + std::string(part[k]) +
                              " is out of range (" +
                              std::to_string(idx < 0 ? before[k] : count[k]) +
                              (idx < 0 ? " so far" : " in the file") +
                              "; OBJ indices are 1-based, negative ones count back from the last)");
        }
      }
    }
    return true;
  });
  if (err) return *err;
  return static_cast<std::size_t>(total.v);
}

}  // namespace

Expected<MeshData> read_obj(const fs::path& path, std::string_view bytes) {
  Expected<std::size_t> v_lines = check_obj(path, bytes);
  if (!v_lines) return v_lines.error();
  Expected<OpenMeshRead> read = read_with_openmesh(path, NormalsAt::kCorner);
  if (!read) return read.error();
  MeshData& mesh = read->mesh;
  // A number strtod reads but OpenMesh's istream does not (e.g. hex
  // floats) makes OpenMesh skip the vertex and shift the indices.
  if (*v_lines != mesh.vertex_count()) {
    return parse_error(path, "has " + std::to_string(*v_lines) + " vertex lines but " +
                                 std::to_string(mesh.vertex_count()) +
                                 " vertices could be read (numbers texbake cannot read?)");
  }
  // map_Kd of the material the faces use (else the first one defined).
  const auto& tex = read->textures;
  if (!tex.empty()) {
    std::string name = tex.front().second;
    for (const auto& [id, n] : tex) {
      if (id == read->first_face_texindex) name = n;
    }
    fs::path p(name);
    mesh.texture_path = (p.is_absolute() ? p : path.parent_path() / p).lexically_normal().string();
  }
  return mesh_without_negative_index(path, std::move(*read));
}

}  // namespace texbake::read_detail
