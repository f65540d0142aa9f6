// read_mesh: the dispatcher (the format comes from the extension; each
// format's reader is in its own file, see read_mesh_internal.h for the map
// and each file's top comment for what it parses and why texbake has its own
// parser where it does), the checks every format shares, and the
// triangulation of the faces with the issues counted on the way.
#include "mesh_io/read_mesh.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>

#include "mesh_io/file_name.h"
#include "mesh_io/read_mesh_internal.h"
#include "mesh_io/regular_file.h"

namespace texbake {
namespace fs = std::filesystem;

namespace read_detail {

std::string too_many_corners(std::size_t n) {
  return "has " + std::to_string(n) + " corners; texbake reads polygons of at most " +
         std::to_string(kMaxFaceCorners);
}

Error parse_error(const fs::path& path, const std::string& what) {
  return make_error(ErrorCode::kParse, path.string() + ": " + what);
}

}  // namespace read_detail

namespace {

using read_detail::parse_error;

// Non-convex polygons above kMaxEarClipCorners are fanned instead of ear
// clipped (ear clipping is O(n^3) in the worst case; issue #7).
constexpr uint32_t kMaxEarClipCorners = 512;

Error io_error(const fs::path& path, const std::string& what) {
  return make_error(ErrorCode::kIo, path.string() + ": " + what);
}

// Whole-file read: every reader parses or checks the file in memory.
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
  // n - 2 triangles per face of n >= 3 corners: an upper bound when every
  // face has three or more.
  const std::size_t expected =
      mesh.face_vertices.size() >= 2 * nf ? mesh.face_vertices.size() - 2 * nf : 0;
  mesh.triangles.reserve(expected);
  mesh.triangle_corners.reserve(expected);
  mesh.triangle_face.reserve(expected);
  auto keep = [&](const std::array<uint32_t, 3>& t, std::size_t f) {
    const uint32_t a = mesh.face_vertices[t[0]], b = mesh.face_vertices[t[1]],
                   c = mesh.face_vertices[t[2]];
    if (a == b || b == c || a == c ||
        is_degenerate(mesh.positions[a], mesh.positions[b], mesh.positions[c])) {
      ++issues.degenerate_triangles;
      return;
    }
    mesh.triangles.push_back({a, b, c});
    mesh.triangle_corners.push_back(t);
    mesh.triangle_face.push_back(static_cast<uint32_t>(f));
  };
  std::vector<std::array<uint32_t, 3>> scratch;
  for (std::size_t f = 0; f < nf; ++f) {
    const uint32_t first = mesh.face_offsets[f];
    const uint32_t n = mesh.face_offsets[f + 1] - first;
    if (n < 3) {  // a face of one or two corners has no area
      ++issues.degenerate_triangles;
    } else if (n == 3) {
      keep({first, first + 1, first + 2}, f);
    } else {
      scratch.clear();
      triangulate_polygon(mesh, first, n, scratch);
      for (const auto& t : scratch) keep(t, f);
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

}  // namespace

Expected<LoadedMesh> read_mesh(const fs::path& path) {
  // Before anything opens it: a FIFO would block, a device never end.
  if (Status s = check_regular_file(path, "a mesh file"); !s) return s.error();
  const std::string ext = lower_extension(path);
  Expected<MeshData> (*reader)(const fs::path&, std::string_view) = nullptr;
  if (ext == ".ply") {
    reader = read_detail::read_ply;
  } else if (ext == ".obj") {
    reader = read_detail::read_obj;
  } else if (ext == ".off") {
    reader = read_detail::read_off;
  } else if (ext == ".stl") {
    reader = read_detail::read_stl;
  } else if (ext != ".glb" && ext != ".gltf") {
    return parse_error(path, "unknown mesh format '" + ext +
                                 "' (texbake reads .obj, .ply, .off, .stl, .glb, .gltf)");
  }
  Expected<std::string> bytes = read_file_bytes(path);
  if (!bytes) return bytes.error();
  if (bytes->empty()) return parse_error(path, "the file is empty");
  std::size_t other_materials = 0;
  Expected<MeshData> mesh =
      reader ? reader(path, *bytes) : read_detail::read_gltf(path, *bytes, &other_materials);
  if (!mesh) return mesh.error();
  if (Status s = validate(path, *mesh); !s) return s.error();
  LoadedMesh out;
  out.mesh = std::move(*mesh);
  out.issues = triangulate_faces(out.mesh);
  out.issues.other_material_primitives = other_materials;
  return out;
}

}  // namespace texbake
