// Mesh readers. OBJ, binary OFF and STL go through OpenMesh's readers with a custom
// importer (ArrayImporter) that fills MeshData directly: OpenMesh's halfedge
// TriMesh/PolyMesh would refuse non-manifold faces ("complex edge") and reorder
// nothing but lose faces, which SPEC section 8 forbids.
//
// ASCII OFF has its own parser (read_off_ascii, see there why), and every
// file OpenMesh reads is checked first (check_obj, check_off_binary,
// check_stl) so that OpenMesh never sees input it mishandles (the fuzzers
// in tests/fuzz found an assertion abort and a 2 GB allocation there).
//
// PLY has its own parser here (read_ply below), because OpenMesh 9.0's
// PLYReader (PLYReader.cc, checked with this importer on a test file) loses
// data silently:
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
#include "mesh_io/read_mesh.h"

#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string_view>

#include "mesh_io/byte_order.h"
#include "mesh_io/file_name.h"

namespace texbake {
namespace fs = std::filesystem;

namespace {

// Work limits for small hostile files (issue #7: no small input may run for
// minutes). A polygon may have at most kMaxFaceCorners corners: OpenMesh's
// OBJ reader removes repeated corners in O(n^2) per face (a 2 MB line of
// "1 1 1 ..." would take minutes). Real meshes' largest polygons (caps of
// scanned or CAD cylinders) have hundreds to a few thousand corners.
// Non-convex polygons above kMaxEarClipCorners are fanned instead of ear
// clipped (ear clipping is O(n^3) in the worst case).
constexpr std::size_t kMaxFaceCorners = 16384;
constexpr uint32_t kMaxEarClipCorners = 512;

std::string too_many_corners(std::size_t n) {
  return "has " + std::to_string(n) + " corners; texbake reads polygons of at most " +
         std::to_string(kMaxFaceCorners);
}

Error parse_error(const fs::path& path, const std::string& what) {
  return make_error(ErrorCode::kParse, path.string() + ": " + what);
}
Error io_error(const fs::path& path, const std::string& what) {
  return make_error(ErrorCode::kIo, path.string() + ": " + what);
}

// Whole-file read: the PLY parser and the pre-scans work on memory.
Expected<std::string> read_file_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return io_error(path, std::string("cannot open (") + std::strerror(errno) + ")");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) return io_error(path, "cannot read");
  std::string bytes(static_cast<std::size_t>(size), '\0');
  in.seekg(0, std::ios::beg);
  if (size > 0 && !in.read(bytes.data(), size)) return io_error(path, "cannot read");
  return bytes;
}

// ---------------------------------------------------------------------------
// Triangulation and issues.

double area2(const Float3& a, const Float3& b, const Float3& c, double* longest_edge2) {
  const double ux = double(b.x) - a.x, uy = double(b.y) - a.y, uz = double(b.z) - a.z;
  const double vx = double(c.x) - a.x, vy = double(c.y) - a.y, vz = double(c.z) - a.z;
  const double wx = double(c.x) - b.x, wy = double(c.y) - b.y, wz = double(c.z) - b.z;
  const double cx = uy * vz - uz * vy, cy = uz * vx - ux * vz, cz = ux * vy - uy * vx;
  *longest_edge2 = std::max(
      {ux * ux + uy * uy + uz * uz, vx * vx + vy * vy + vz * vz, wx * wx + wy * wy + wz * wz});
  return std::sqrt(cx * cx + cy * cy + cz * cz);
}

// Zero area relative to the triangle's own size (scale-free): a triangle
// whose height is below 1e-12 of its longest edge takes no part in ray
// tracing. Exactly repeated or exactly collinear vertices give 0.
bool is_degenerate(const Float3& a, const Float3& b, const Float3& c) {
  double longest2 = 0;
  const double twice_area = area2(a, b, c, &longest2);
  return !(twice_area > 1e-12 * longest2);
}

// Ear clipping of one polygon (corner indices first..first+n-1) projected on
// the plane of its Newell normal. O(n^2); used only for non-convex polygons
// with more than three corners. Falls back to a fan if no ear is found
// (self-intersecting input), so no corner is lost.
void triangulate_polygon(const MeshData& mesh, uint32_t first, uint32_t n,
                         std::vector<std::array<uint32_t, 3>>& out) {
  auto pos = [&](uint32_t corner) { return mesh.positions[mesh.face_vertices[corner]]; };
  double nx = 0, ny = 0, nz = 0;  // Newell's normal
  for (uint32_t i = 0; i < n; ++i) {
    const Float3 p = pos(first + i), q = pos(first + (i + 1) % n);
    nx += (double(p.y) - q.y) * (double(p.z) + q.z);
    ny += (double(p.z) - q.z) * (double(p.x) + q.x);
    nz += (double(p.x) - q.x) * (double(p.y) + q.y);
  }
  // Drop the dominant axis of the normal; keep orientation positive.
  const double ax = std::abs(nx), ay = std::abs(ny), az = std::abs(nz);
  int drop = (ax >= ay && ax >= az) ? 0 : (ay >= az ? 1 : 2);
  const double sign = (drop == 0 ? nx : drop == 1 ? ny : nz) >= 0 ? 1.0 : -1.0;
  std::vector<std::array<double, 2>> p2(n);
  for (uint32_t i = 0; i < n; ++i) {
    const Float3 p = pos(first + i);
    if (drop == 0)
      p2[i] = {p.y, p.z};
    else if (drop == 1)
      p2[i] = {p.z, p.x};
    else
      p2[i] = {p.x, p.y};
  }
  auto cross2 = [&](uint32_t a, uint32_t b, uint32_t c) {
    return sign * ((p2[b][0] - p2[a][0]) * (p2[c][1] - p2[a][1]) -
                   (p2[b][1] - p2[a][1]) * (p2[c][0] - p2[a][0]));
  };
  bool convex = true;
  for (uint32_t i = 0; i < n && convex; ++i) {
    if (cross2(i, (i + 1) % n, (i + 2) % n) < 0) convex = false;
  }
  if (convex || n > kMaxEarClipCorners) {
    for (uint32_t i = 1; i + 1 < n; ++i) out.push_back({first, first + i, first + i + 1});
    return;
  }
  std::vector<uint32_t> ring(n);
  for (uint32_t i = 0; i < n; ++i) ring[i] = i;
  while (ring.size() > 3) {
    bool clipped = false;
    const std::size_t m = ring.size();
    for (std::size_t i = 0; i < m; ++i) {
      const uint32_t a = ring[(i + m - 1) % m], b = ring[i], c = ring[(i + 1) % m];
      if (cross2(a, b, c) <= 0) continue;  // reflex or flat corner
      bool inside = false;
      for (uint32_t k : ring) {
        if (k == a || k == b || k == c) continue;
        if (cross2(a, b, k) >= 0 && cross2(b, c, k) >= 0 && cross2(c, a, k) >= 0) {
          inside = true;
          break;
        }
      }
      if (inside) continue;
      out.push_back({first + a, first + b, first + c});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(i));
      clipped = true;
      break;
    }
    if (!clipped) {  // no ear: self-intersecting polygon, fan the rest
      for (std::size_t i = 1; i + 1 < ring.size(); ++i)
        out.push_back({first + ring[0], first + ring[i], first + ring[i + 1]});
      return;
    }
  }
  out.push_back({first + ring[0], first + ring[1], first + ring[2]});
}

// Edges shared by more than two faces, counted without a hash map: a counting
// sort of the edges by their smaller vertex, then a small sort per bucket.
std::size_t count_non_manifold_edges(const MeshData& mesh) {
  const std::size_t nv = mesh.vertex_count();
  const std::size_t nf = mesh.face_count();
  std::vector<uint32_t> bucket_start(nv + 1, 0);
  auto for_each_edge = [&](auto&& fn) {
    for (std::size_t f = 0; f < nf; ++f) {
      const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
      for (uint32_t c = b; c < e; ++c) {
        const uint32_t v0 = mesh.face_vertices[c];
        const uint32_t v1 = mesh.face_vertices[c + 1 < e ? c + 1 : b];
        if (v0 != v1) fn(std::min(v0, v1), std::max(v0, v1));
      }
    }
  };
  for_each_edge([&](uint32_t lo, uint32_t) { ++bucket_start[lo + 1]; });
  for (std::size_t v = 0; v < nv; ++v) bucket_start[v + 1] += bucket_start[v];
  std::vector<uint32_t> other(bucket_start[nv]);
  std::vector<uint32_t> fill(bucket_start.begin(), bucket_start.end() - 1);
  for_each_edge([&](uint32_t lo, uint32_t hi) { other[fill[lo]++] = hi; });
  std::size_t count = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    auto b = other.begin() + bucket_start[v], e = other.begin() + bucket_start[v + 1];
    std::sort(b, e);
    for (auto it = b; it != e;) {
      auto run = std::find_if(it, e, [&](uint32_t x) { return x != *it; });
      if (run - it > 2) ++count;
      it = run;
    }
  }
  return count;
}

}  // namespace

MeshIssues triangulate_faces(MeshData& mesh) {
  MeshIssues issues;
  mesh.triangles.clear();
  mesh.triangle_corners.clear();
  mesh.triangle_face.clear();
  const std::size_t nf = mesh.face_count();
  mesh.triangle_corners.reserve(
      mesh.face_vertices.size() >= 2 * nf ? mesh.face_vertices.size() - 2 * nf : 0);
  std::vector<std::array<uint32_t, 3>> scratch;
  for (std::size_t f = 0; f < nf; ++f) {
    const uint32_t first = mesh.face_offsets[f];
    const uint32_t n = mesh.face_offsets[f + 1] - first;
    if (n < 3) {  // a face of one or two corners has no area
      ++issues.degenerate_triangles;
      continue;
    }
    scratch.clear();
    if (n == 3)
      scratch.push_back({first, first + 1, first + 2});
    else
      triangulate_polygon(mesh, first, n, scratch);
    for (const auto& t : scratch) {
      const uint32_t a = mesh.face_vertices[t[0]], b = mesh.face_vertices[t[1]],
                     c = mesh.face_vertices[t[2]];
      if (a == b || b == c || a == c ||
          is_degenerate(mesh.positions[a], mesh.positions[b], mesh.positions[c])) {
        ++issues.degenerate_triangles;
        continue;
      }
      mesh.triangles.push_back({a, b, c});
      mesh.triangle_corners.push_back(t);
      mesh.triangle_face.push_back(static_cast<uint32_t>(f));
    }
  }
  std::vector<char> used(mesh.vertex_count(), 0);
  for (uint32_t v : mesh.face_vertices) used[v] = 1;
  issues.unreferenced_vertices = static_cast<std::size_t>(std::count(used.begin(), used.end(), 0));
  issues.non_manifold_edges = count_non_manifold_edges(mesh);
  return issues;
}

namespace {

// Checks shared by every format once the arrays are filled.
Status validate(const fs::path& path, const MeshData& mesh) {
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) {
    const Float3& p = mesh.positions[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) {
      return parse_error(path, "vertex " + std::to_string(v) + " has a non-finite coordinate");
    }
  }
  const std::size_t nv = mesh.positions.size();
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    for (uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
      if (mesh.face_vertices[c] >= nv) {
        return parse_error(path, "face " + std::to_string(f) + " refers to vertex " +
                                     std::to_string(mesh.face_vertices[c]) + " but there are " +
                                     std::to_string(nv) + " vertices");
      }
    }
  }
  if (mesh.face_count() == 0) return parse_error(path, "the mesh has no faces");
  return ok_status();
}

// ---------------------------------------------------------------------------
// OpenMesh importer: fills MeshData, never builds halfedges.

class ArrayImporter final : public OpenMesh::IO::BaseImporter {
 public:
  enum class Normals { kPerVertex, kPerCorner };
  explicit ArrayImporter(Normals normals) : normals_mode_(normals) { mesh_.face_offsets = {0}; }

  MeshData& mesh() { return mesh_; }
  // First bad face index seen (negative or past the vertex count), if any.
  std::optional<std::pair<std::size_t, long long>> bad_index() const { return bad_index_; }
  const std::vector<std::pair<int, std::string>>& textures() const { return textures_; }
  int first_face_texindex() const { return first_face_texindex_; }

  using VH = OpenMesh::VertexHandle;
  using FH = OpenMesh::FaceHandle;
  using HH = OpenMesh::HalfedgeHandle;
  using EH = OpenMesh::EdgeHandle;

  VH add_vertex(const OpenMesh::Vec3f& p) override {
    mesh_.positions.push_back({p[0], p[1], p[2]});
    return VH(static_cast<int>(mesh_.positions.size() - 1));
  }
  VH add_vertex() override { return add_vertex(OpenMesh::Vec3f(0, 0, 0)); }
  HH add_edge(VH, VH) override { return HH(); }

  FH add_face(const VHandles& vs) override {
    const std::size_t f = mesh_.face_count();
    for (const VH& v : vs) {
      // Indices are checked once the file is read (vertices may come later in
      // no format OpenMesh reads, but the count is only final then).
      if (v.idx() < 0 && !bad_index_) bad_index_ = {f, v.idx()};
      mesh_.face_vertices.push_back(static_cast<uint32_t>(std::max(v.idx(), 0)));
      if (v.idx() < 0) mesh_.face_vertices.back() = std::numeric_limits<uint32_t>::max();
    }
    mesh_.face_offsets.push_back(static_cast<uint32_t>(mesh_.face_vertices.size()));
    // OBJ: the reader reports a corner's normal through set_normal(vertex)
    // while it parses the face, before add_face; keep them per corner.
    if (normals_mode_ == Normals::kPerCorner) {
      if (!pending_normals_.empty() || !mesh_.corner_normal.empty()) {
        pad_corner_normals(mesh_.face_vertices.size() - vs.size());
        for (std::size_t i = 0; i < vs.size(); ++i) {
          if (i < pending_normals_.size()) {
            mesh_.corner_normal.push_back(static_cast<uint32_t>(mesh_.normals.size()));
            mesh_.normals.push_back(pending_normals_[i]);
          } else {
            mesh_.corner_normal.push_back(default_normal());
          }
        }
      }
      pending_normals_.clear();
    }
    return FH(static_cast<int>(f));
  }
  FH add_face(HH) override { return FH(); }

  void add_face_texcoords(FH fh, VH, const std::vector<OpenMesh::Vec2f>& tcs) override {
    if (tcs.empty()) return;
    const std::size_t f = static_cast<std::size_t>(fh.idx());
    const uint32_t b = mesh_.face_offsets[f], e = mesh_.face_offsets[f + 1];
    // Faces before the first textured one get a (0,0) UV.
    if (mesh_.corner_uv.size() < b) {
      const uint32_t zero = zero_uv();
      mesh_.corner_uv.resize(b, zero);
    }
    // OpenMesh drops repeated vertices of a face (f 1 2 2 3) but not their
    // texcoords; such a face is degenerate anyway, keep the first n UVs.
    for (uint32_t c = b; c < e; ++c) {
      const std::size_t i = c - b;
      const OpenMesh::Vec2f t = i < tcs.size() ? tcs[i] : tcs.back();
      mesh_.corner_uv.push_back(static_cast<uint32_t>(mesh_.uvs.size()));
      mesh_.uvs.push_back({t[0], t[1]});
    }
  }
  void add_face_texcoords(FH, VH, const std::vector<OpenMesh::Vec3f>&) override {}
  void set_face_texindex(FH, int id) override {
    if (first_face_texindex_ == 0 && id != 0) first_face_texindex_ = id;
  }
  void add_texture_information(int id, std::string name) override {
    textures_.emplace_back(id, std::move(name));
  }

  void set_point(VH v, const OpenMesh::Vec3f& p) override {
    if (valid(v)) mesh_.positions[v.idx()] = {p[0], p[1], p[2]};
  }
  void set_halfedge(VH, HH) override {}

  void set_normal(VH v, const OpenMesh::Vec3f& n) override {
    if (normals_mode_ == Normals::kPerCorner) {
      pending_normals_.push_back({n[0], n[1], n[2]});
    } else if (valid(v)) {
      if (vertex_normals_.size() < mesh_.positions.size())
        vertex_normals_.resize(mesh_.positions.size());
      vertex_normals_[v.idx()] = {n[0], n[1], n[2]};
      has_vertex_normals_ = true;
    }
  }
  void set_normal(VH v, const OpenMesh::Vec3d& n) override { set_normal(v, OpenMesh::Vec3f(n)); }

  void set_color(VH v, const OpenMesh::Vec3uc& c) override {
    set_vertex_color(v, {c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, 1.f});
  }
  void set_color(VH v, const OpenMesh::Vec4uc& c) override {
    set_vertex_color(v, {c[0] / 255.f, c[1] / 255.f, c[2] / 255.f, c[3] / 255.f});
  }
  void set_color(VH v, const OpenMesh::Vec3f& c) override {
    set_vertex_color(v, {c[0], c[1], c[2], 1.f});
  }
  void set_color(VH v, const OpenMesh::Vec4f& c) override {
    set_vertex_color(v, {c[0], c[1], c[2], c[3]});
  }

  void set_texcoord(VH, const OpenMesh::Vec2f&) override {}
  void set_status(VH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_next(HH, HH) override {}
  void set_face(HH, FH) override {}
  void request_face_texcoords2D() override {}
  void set_texcoord(HH, const OpenMesh::Vec2f&) override {}
  void set_texcoord(VH, const OpenMesh::Vec3f&) override {}
  void set_texcoord(HH, const OpenMesh::Vec3f&) override {}
  void set_status(HH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_color(EH, const OpenMesh::Vec3uc&) override {}
  void set_color(EH, const OpenMesh::Vec4uc&) override {}
  void set_color(EH, const OpenMesh::Vec3f&) override {}
  void set_color(EH, const OpenMesh::Vec4f&) override {}
  void set_status(EH, const OpenMesh::Attributes::StatusInfo&) override {}
  void set_normal(FH, const OpenMesh::Vec3f&) override {}
  void set_normal(FH, const OpenMesh::Vec3d&) override {}
  void set_color(FH, const OpenMesh::Vec3uc&) override {}
  void set_color(FH, const OpenMesh::Vec4uc&) override {}
  void set_color(FH, const OpenMesh::Vec3f&) override {}
  void set_color(FH, const OpenMesh::Vec4f&) override {}
  void set_status(FH, const OpenMesh::Attributes::StatusInfo&) override {}

  void reserve(unsigned int nv, unsigned int, unsigned int nf) override {
    // Counts come from file headers: cap what a lying header can make us
    // allocate up front (the arrays still grow as the data really arrives).
    mesh_.positions.reserve(std::min(nv, 1u << 24));
    mesh_.face_offsets.reserve(std::min(nf, 1u << 24) + 1u);
  }
  size_t n_vertices() const override { return mesh_.positions.size(); }
  size_t n_faces() const override { return mesh_.face_count(); }
  size_t n_edges() const override { return 0; }

  // Completes the optional per-corner / per-vertex arrays to full length.
  void complete() {
    if (!mesh_.corner_uv.empty()) mesh_.corner_uv.resize(mesh_.face_vertices.size(), zero_uv());
    if (normals_mode_ == Normals::kPerCorner) {
      if (!mesh_.corner_normal.empty()) pad_corner_normals(mesh_.face_vertices.size());
    } else if (has_vertex_normals_) {
      vertex_normals_.resize(mesh_.positions.size(), Float3{0, 0, 0});
      mesh_.normals = std::move(vertex_normals_);
      mesh_.corner_normal.assign(mesh_.face_vertices.begin(), mesh_.face_vertices.end());
    }
    // OpenMesh's OBJ reader colours only vertices a face refers to; the rest
    // stay opaque white.
    if (!mesh_.vertex_colors.empty())
      mesh_.vertex_colors.resize(mesh_.positions.size(), {1, 1, 1, 1});
  }

 private:
  bool valid(VH v) const {
    return v.idx() >= 0 && static_cast<std::size_t>(v.idx()) < mesh_.positions.size();
  }
  void set_vertex_color(VH v, std::array<float, 4> c) {
    if (!valid(v)) return;
    if (mesh_.vertex_colors.size() < mesh_.positions.size()) {
      mesh_.vertex_colors.resize(mesh_.positions.size(), {1, 1, 1, 1});
    }
    mesh_.vertex_colors[v.idx()] = c;
  }
  uint32_t zero_uv() {
    if (!zero_uv_) {
      zero_uv_ = static_cast<uint32_t>(mesh_.uvs.size());
      mesh_.uvs.push_back({0, 0});
    }
    return *zero_uv_;
  }
  uint32_t default_normal() {
    if (!default_normal_) {
      default_normal_ = static_cast<uint32_t>(mesh_.normals.size());
      mesh_.normals.push_back({0, 0, 0});
    }
    return *default_normal_;
  }
  void pad_corner_normals(std::size_t corners) {
    if (mesh_.corner_normal.size() < corners) {
      const uint32_t d = default_normal();
      mesh_.corner_normal.resize(corners, d);
    }
  }

  MeshData mesh_;
  Normals normals_mode_;
  std::vector<Float3> pending_normals_;
  std::vector<Float3> vertex_normals_;
  bool has_vertex_normals_ = false;
  std::optional<uint32_t> zero_uv_, default_normal_;
  std::optional<std::pair<std::size_t, long long>> bad_index_;
  std::vector<std::pair<int, std::string>> textures_;
  int first_face_texindex_ = 0;
};

// OpenMesh's readers are process-wide singletons with per-read state, and its
// log streams are global: one read at a time, logs off (errors are ours).
std::mutex& openmesh_mutex() {
  static std::mutex m;
  return m;
}

bool read_with_openmesh(const fs::path& path, ArrayImporter& importer) {
  std::lock_guard<std::mutex> lock(openmesh_mutex());
  static const bool silenced = [] {
    omerr().disable();
    omout().disable();
    omlog().disable();
    return true;
  }();
  (void)silenced;
  OpenMesh::IO::Options opt;
  opt += OpenMesh::IO::Options::VertexColor;
  opt += OpenMesh::IO::Options::VertexNormal;
  opt += OpenMesh::IO::Options::FaceTexCoord;
  opt += OpenMesh::IO::Options::ColorFloat;
  return OpenMesh::IO::IOManager().read(path.string(), importer, opt);
}

// Splits text into lines; calls fn(line, line_number) for each.
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

std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

// Splits on whitespace.
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

// strtod-based (accepts nan/inf, which the readers' istreams silently refuse).
std::optional<double> parse_number(std::string_view tok) {
  std::string s(tok);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  if (end == s.c_str() || *end != '\0') return std::nullopt;
  return v;
}

template <class Int>
bool parse_int(std::string_view tok, Int& out) {
  const auto r = std::from_chars(tok.data(), tok.data() + tok.size(), out);
  return r.ec == std::errc() && r.ptr == tok.data() + tok.size();
}

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
// - mtllib: the file named, if it exists, is a regular file.
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
      std::error_code ec;
      const fs::file_status st = fs::status(dir + "/" + std::string(rest), ec);
      if (!ec && fs::exists(st) && !fs::is_regular_file(st)) {
        return fail(no, "material library '" + std::string(rest) + "' is not a regular file");
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

// OFF (geomview's format: a "[ST][C][N][4][n]OFF" keyword, the counts
// "vertices faces edges", one vertex per line "x y z [nx ny nz] [colour]
// [s t]", one face per line "n i0 .. in-1 [colour]", '#' comments).
// ASCII OFF is parsed here, not by OpenMesh: OpenMesh 9.0's reader
// (OFFReader.cc, read_ascii) reads counts and indices with istream >> into
// uninitialised variables and never checks the stream, so a short or garbled
// file makes it loop over garbage counts (the fuzzer found a 15-byte file that
// made it allocate 2 GB: tests/fuzz/regressions/fuzz_mesh_off), it does not
// skip comments, and it ignores counts written on the keyword line.
// Binary OFF ("OFF BINARY") still goes through OpenMesh, after
// check_off_binary has walked the file exactly as OpenMesh will read it.
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

inline uint32_t load_le32(const char* p) {
  uint32_t v;
  std::memcpy(&v, p, 4);
  if constexpr (std::endian::native == std::endian::big) v = byte_swap(v);
  return v;
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

// Binary STL is 80 + 4 + 50 * count bytes; OpenMesh reads past a short file.
Status check_stl(const fs::path& path, std::string_view bytes) {
  const bool looks_ascii = bytes.size() >= 5 && bytes.substr(0, 5) == "solid" &&
                           bytes.find("facet", 0) != std::string_view::npos &&
                           bytes.find("facet") < 1000;
  if (looks_ascii) return ok_status();
  if (bytes.size() < 84)
    return parse_error(path, "truncated binary STL (" + std::to_string(bytes.size()) + " bytes)");
  uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);
  if constexpr (std::endian::native == std::endian::big) count = byte_swap(count);
  const unsigned long long expected = 84ull + 50ull * count;
  if (bytes.size() < expected) {
    return parse_error(path, "truncated binary STL: header declares " + std::to_string(count) +
                                 " triangles (" + std::to_string(expected) + " bytes), file has " +
                                 std::to_string(bytes.size()) + " bytes");
  }
  return ok_status();
}

Expected<MeshData> read_through_openmesh(const fs::path& path, const std::string& ext) {
  Expected<std::string> bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  if (bytes->empty()) return parse_error(path, "the file is empty");
  if (ext == ".off") {
    // Binary exactly as OpenMesh's OFFReader::can_u_read detects it: the
    // keyword at the start of the file, one character, "BINARY".
    const std::string_view b = *bytes;
    const auto first = tokens(b.substr(0, std::min(b.find('\n'), b.size())));
    const std::optional<OffKeyword> k =
        first.empty() || first[0].data() != b.data() ? std::nullopt : off_keyword(first[0]);
    if (!k || first[0].size() + 1 > b.size() || b.substr(first[0].size() + 1, 6) != "BINARY")
      return read_off_ascii(path, b);
    if (k->high_dimension) return parse_error(path, "4D and n-dimensional OFF are not supported");
    if (Status s = check_off_binary(path, b, *k); !s) return s.error();
  } else if (ext == ".stl") {
    if (Status s = check_stl(path, *bytes); !s) return s.error();
  }
  std::size_t obj_v_lines = 0;
  if (ext == ".obj") {
    Expected<std::size_t> v = check_obj(path, *bytes);
    if (!v) return v.error();
    obj_v_lines = *v;
  }
  ArrayImporter importer(ext == ".obj" ? ArrayImporter::Normals::kPerCorner
                                       : ArrayImporter::Normals::kPerVertex);
  if (!read_with_openmesh(path, importer)) {
    return parse_error(path, "OpenMesh cannot parse it as " + ext.substr(1) + " (malformed file)");
  }
  importer.complete();
  MeshData& mesh = importer.mesh();
  if (ext == ".obj") {
    // A number strtod reads but OpenMesh's istream does not (e.g. hex
    // floats) makes OpenMesh skip the vertex and shift the indices.
    if (obj_v_lines != mesh.vertex_count()) {
      return parse_error(path, "has " + std::to_string(obj_v_lines) + " vertex lines but " +
                                   std::to_string(mesh.vertex_count()) +
                                   " vertices could be read (numbers texbake cannot read?)");
    }
    // map_Kd of the material the faces use (else the first one defined).
    const auto& tex = importer.textures();
    if (!tex.empty()) {
      std::string name = tex.front().second;
      for (const auto& [id, n] : tex) {
        if (id == importer.first_face_texindex()) name = n;
      }
      fs::path p(name);
      mesh.texture_path =
          (p.is_absolute() ? p : path.parent_path() / p).lexically_normal().string();
    }
  }
  if (importer.bad_index()) {
    return parse_error(path, "face " + std::to_string(importer.bad_index()->first) +
                                 " has a negative vertex index");
  }
  return std::move(mesh);
}

// ---------------------------------------------------------------------------
// PLY (see the file comment for why not OpenMesh's reader).

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

// Minimal ASCII tokenizer over the data section, tracking line numbers.
struct AsciiCursor {
  std::string_view text;
  std::size_t pos = 0;
  std::size_t line = 1;
  bool next(std::string_view& tok) {
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
};

Status read_ply_ascii(PlyReadState& s, std::string_view bytes) {
  AsciiCursor cur{bytes.substr(s.header.data_offset), 0, s.header.data_line};
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

Expected<MeshData> read_ply(const fs::path& path) {
  Expected<std::string> file = read_file_bytes(path);
  if (!file) return file.error();
  if (file->empty()) return parse_error(path, "the file is empty");
  const std::string_view bytes = *file;
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

}  // namespace

Expected<LoadedMesh> read_mesh(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || !fs::exists(st)) return io_error(path, "no such file");
  if (fs::is_directory(st)) return io_error(path, "is a folder, not a mesh file");
  const std::string ext = lower_extension(path);
  Expected<MeshData> mesh = make_error(ErrorCode::kInternal, "");
  if (ext == ".ply") {
    mesh = read_ply(path);
  } else if (ext == ".obj" || ext == ".off" || ext == ".stl") {
    mesh = read_through_openmesh(path, ext);
  } else {
    return parse_error(path,
                       "unknown mesh format '" + ext + "' (texbake reads .obj, .ply, .off, .stl)");
  }
  if (!mesh) return mesh.error();
  if (Status s = validate(path, *mesh); !s) return s.error();
  LoadedMesh out;
  out.mesh = std::move(*mesh);
  out.issues = triangulate_faces(out.mesh);
  return out;
}

}  // namespace texbake
