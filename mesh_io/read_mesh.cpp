// read_mesh: the dispatcher (the format comes from the extension; each
// format's reader is in its own file, see read_mesh_internal.h for the map
// and each file's top comment for what it parses and why texbake has its own
// parser where it does), the checks every format shares, and the
// triangulation of the faces with the issues counted on the way.
#include "mesh_io/read_mesh.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <memory>
#include <string_view>

#include "mesh_io/file_name.h"
#include "mesh_io/read_mesh_internal.h"
#include "mesh_io/regular_file.h"
#include "mesh_io/tsan_fork_join.h"

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

// Whole-file read: every reader parses or checks the file in memory. The
// file is mapped read-only (its pages are the page cache's own: no copy and
// no fresh zeroed memory, which costs most on a virtual machine, where a
// first-touch page fault is dear), pre-faulted with MAP_POPULATE; where
// mapping fails (a file system without mmap), it is read into memory. A
// file truncated by another process while it is mapped would fault on the
// lost pages: texbake's inputs are not written while it reads them.
class FileBytes {
 public:
  FileBytes() = default;
  FileBytes(const FileBytes&) = delete;
  FileBytes& operator=(const FileBytes&) = delete;
  ~FileBytes() {
    if (mapped_) munmap(mapped_, size_);
  }
  std::string_view view() const {
    return mapped_ ? std::string_view(static_cast<const char*>(mapped_), size_)
                   : std::string_view(copy_);
  }

  static Expected<std::unique_ptr<FileBytes>> read(const fs::path& path) {
    auto out = std::make_unique<FileBytes>();
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) return io_error(path, std::string("cannot open (") + std::strerror(errno) + ")");
    struct stat st {};
    if (::fstat(fd, &st) != 0 || st.st_size < 0) {
      ::close(fd);
      return io_error(path, "cannot read");
    }
    const auto size = static_cast<std::size_t>(st.st_size);
    if (size > 0) {
      void* m = ::mmap(nullptr, size, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
      if (m != MAP_FAILED) {
        ::madvise(m, size, MADV_SEQUENTIAL);
        out->mapped_ = m;
        out->size_ = size;
      } else {
        out->copy_.resize(size);
        std::size_t done = 0;
        while (done < size) {
          const ssize_t got = ::read(fd, out->copy_.data() + done, size - done);
          if (got < 0 && errno == EINTR) continue;
          if (got <= 0) {
            ::close(fd);
            return io_error(path, "cannot read");
          }
          done += static_cast<std::size_t>(got);
        }
      }
    }
    ::close(fd);
    return out;
  }

 private:
  void* mapped_ = nullptr;
  std::size_t size_ = 0;
  std::string copy_;
};

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

// The loops below run on oneTBB in fixed blocks of faces or vertices: every
// count is a sum and every output is written in face order, so the results
// never depend on the thread count (callers limit it with a task arena).
constexpr std::size_t kBlock = 1 << 14;

// fn(begin, end) for ranges [begin, end) covering [0, n), in parallel
// (ForkJoin: the loop's fork and join, for ThreadSanitizer).
template <class Fn>
void parallel_ranges(std::size_t n, Fn&& fn) {
  ForkJoin fork_join;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      fork_join.begin_body();
                      fn(r.begin(), r.end());
                      fork_join.end_body();
                    });
  fork_join.join();
}

template <class Fn>  // fn(block, begin, end) for the blocks of [0, n)
void for_blocks(std::size_t n, Fn&& fn) {
  parallel_ranges((n + kBlock - 1) / kBlock, [&](std::size_t first, std::size_t last) {
    for (std::size_t b = first; b != last; ++b) fn(b, b * kBlock, std::min(n, (b + 1) * kBlock));
  });
}

// Edges shared by more than two faces, counted without a hash map by a
// two-level counting sort of the edges on their smaller vertex. The first
// level streams each edge into the coarse bucket of its vertex's range of
// kRange vertices (few enough buckets that their write positions stay in
// cache); the second sorts one coarse bucket at a time, in cache, by vertex,
// then each vertex's few other ends. A one-level sort scatters its writes
// over all the vertices: a cache miss per edge, most of the time.
std::size_t count_non_manifold_edges(const MeshData& mesh) {
  constexpr unsigned kRangeBits = 10;
  constexpr uint32_t kRange = 1u << kRangeBits;
  const std::size_t nv = mesh.vertex_count();
  const std::size_t nf = mesh.face_count();
  const std::size_t ranges = (nv >> kRangeBits) + 1;
  // The faces in at most 64 fixed chunks, so that the chunks' write
  // positions (chunks x ranges) stay small however large the mesh.
  const std::size_t chunks = std::clamp<std::size_t>(nf / kBlock, 1, 64);
  auto for_chunks = [&](auto&& fn) {  // fn(chunk, begin, end), in parallel
    parallel_ranges(chunks, [&](std::size_t first, std::size_t last) {
      for (std::size_t c = first; c != last; ++c) fn(c, nf * c / chunks, nf * (c + 1) / chunks);
    });
  };
  // fn(lo, hi) for the edges of faces [begin, end) (lo < hi).
  auto for_each_edge = [&](std::size_t begin, std::size_t end, auto&& fn) {
    for (std::size_t f = begin; f < end; ++f) {
      const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
      for (uint32_t c = b; c < e; ++c) {
        const uint32_t v0 = mesh.face_vertices[c];
        const uint32_t v1 = mesh.face_vertices[c + 1 < e ? c + 1 : b];
        if (v0 != v1) fn(std::min(v0, v1), std::max(v0, v1));
      }
    }
  };
  // First level: where each chunk of faces writes into each range, ranges
  // in order and chunks in order within one.
  std::vector<uint64_t> at(chunks * ranges, 0);  // [chunk][range]
  for_chunks([&](std::size_t chunk, std::size_t begin, std::size_t end) {
    uint64_t* mine = at.data() + chunk * ranges;
    for_each_edge(begin, end, [&](uint32_t lo, uint32_t) { ++mine[lo >> kRangeBits]; });
  });
  std::vector<uint64_t> range_start(ranges + 1, 0);
  {
    uint64_t total = 0;
    for (std::size_t r = 0; r < ranges; ++r) {
      range_start[r] = total;
      for (std::size_t chunk = 0; chunk < chunks; ++chunk)
        total += std::exchange(at[chunk * ranges + r], total);
    }
    range_start[ranges] = total;
  }
  // (offset of lo in its range, hi) per edge. Not zeroed first: the scatter
  // writes every entry, and touching the fresh pages there spreads their
  // (costly) first-touch faults over the threads.
  const std::unique_ptr<uint64_t[]> edges(new uint64_t[range_start[ranges]]);
  for_chunks([&](std::size_t chunk, std::size_t begin, std::size_t end) {
    uint64_t* mine = at.data() + chunk * ranges;
    for_each_edge(begin, end, [&](uint32_t lo, uint32_t hi) {
      edges[mine[lo >> kRangeBits]++] = (uint64_t{lo & (kRange - 1)} << 32) | hi;
    });
  });
  at = {};
  // Second level, one range per task.
  std::atomic<std::size_t> count{0};
  parallel_ranges(ranges, [&](std::size_t first, std::size_t last) {
    std::size_t mine = 0;
    std::vector<uint32_t> start(kRange + 1), other;
    for (std::size_t range = first; range != last; ++range) {
      const uint64_t* b = edges.get() + range_start[range];
      const uint64_t* e = edges.get() + range_start[range + 1];
      std::fill(start.begin(), start.end(), 0);
      for (const uint64_t* k = b; k != e; ++k) ++start[(*k >> 32) + 1];
      for (uint32_t v = 0; v < kRange; ++v) start[v + 1] += start[v];
      other.resize(static_cast<std::size_t>(e - b));
      for (const uint64_t* k = b; k != e; ++k) other[start[*k >> 32]++] = static_cast<uint32_t>(*k);
      // start[v] is now the end of vertex v's other ends.
      uint32_t from = 0;
      for (uint32_t v = 0; v < kRange; ++v) {
        auto vb = other.begin() + from, ve = other.begin() + start[v];
        from = start[v];
        std::sort(vb, ve);
        for (auto it = vb; it != ve;) {
          auto run = std::find_if(it, ve, [&](uint32_t x) { return x != *it; });
          if (run - it > 2) ++mine;
          it = run;
        }
      }
    }
    count.fetch_add(mine, std::memory_order_relaxed);
  });
  return count.load();
}

}  // namespace

MeshIssues triangulate_faces(MeshData& mesh) {
  MeshIssues issues;
  const std::size_t nf = mesh.face_count();
  // Calls keep(triangle's corners) for the triangles of faces [begin, end)
  // that are not degenerate, in order; returns the number of degenerate ones
  // (a face of one or two corners counts as one).
  auto triangles_of = [&](std::size_t begin, std::size_t end, auto&& keep) {
    std::size_t degenerate = 0;
    std::vector<std::array<uint32_t, 3>> scratch;
    auto offer = [&](const std::array<uint32_t, 3>& t, std::size_t f) {
      const uint32_t a = mesh.face_vertices[t[0]], b = mesh.face_vertices[t[1]],
                     c = mesh.face_vertices[t[2]];
      if (a == b || b == c || a == c ||
          is_degenerate(mesh.positions[a], mesh.positions[b], mesh.positions[c])) {
        ++degenerate;
      } else {
        keep(std::array<uint32_t, 3>{a, b, c}, t, f);
      }
    };
    for (std::size_t f = begin; f < end; ++f) {
      const uint32_t first = mesh.face_offsets[f];
      const uint32_t n = mesh.face_offsets[f + 1] - first;
      if (n < 3) {  // a face of one or two corners has no area
        ++degenerate;
      } else if (n == 3) {
        offer({first, first + 1, first + 2}, f);
      } else {
        scratch.clear();
        triangulate_polygon(mesh, first, n, scratch);
        for (const auto& t : scratch) offer(t, f);
      }
    }
    return degenerate;
  };
  // Two passes over fixed blocks of faces: count each block's triangles,
  // then write them at the block's offset (the polygons are triangulated
  // twice; most meshes have triangles only). Both passes run the same pure
  // code (triangles_of: no state, the same floating-point operations), so
  // the second keeps exactly the triangles the first counted.
  const std::size_t blocks = (nf + kBlock - 1) / kBlock;
  std::vector<std::size_t> kept(blocks + 1, 0), degenerate(blocks, 0);
  for_blocks(nf, [&](std::size_t block, std::size_t begin, std::size_t end) {
    std::size_t n = 0;
    degenerate[block] =
        triangles_of(begin, end, [&](const auto&, const auto&, std::size_t) { ++n; });
    kept[block + 1] = n;
  });
  for (std::size_t b = 0; b < blocks; ++b) {
    kept[b + 1] += kept[b];
    issues.degenerate_triangles += degenerate[b];
  }
  mesh.triangles.resize(kept[blocks]);
  mesh.triangle_corners.resize(kept[blocks]);
  mesh.triangle_face.resize(kept[blocks]);
  for_blocks(nf, [&](std::size_t block, std::size_t begin, std::size_t end) {
    std::size_t at = kept[block];
    triangles_of(begin, end,
                 [&](const std::array<uint32_t, 3>& vertices,
                     const std::array<uint32_t, 3>& corners, std::size_t f) {
                   mesh.triangles[at] = vertices;
                   mesh.triangle_corners[at] = corners;
                   mesh.triangle_face[at++] = static_cast<uint32_t>(f);
                 });
  });
  // Unreferenced vertices: flags set by any number of faces (relaxed atomic
  // stores of the same value), then counted.
  std::vector<uint8_t> used(mesh.vertex_count(), 0);
  for_blocks(mesh.face_vertices.size(), [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
      std::atomic_ref<uint8_t>(used[mesh.face_vertices[c]]).store(1, std::memory_order_relaxed);
  });
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
  Expected<std::unique_ptr<FileBytes>> file = FileBytes::read(path);
  if (!file) return file.error();
  const std::string_view bytes = (*file)->view();
  if (bytes.empty()) return parse_error(path, "the file is empty");
  std::size_t other_materials = 0;
  Expected<MeshData> mesh =
      reader ? reader(path, bytes) : read_detail::read_gltf(path, bytes, &other_materials);
  file->reset();  // the mapping is not needed past the parse
  if (!mesh) return mesh.error();
  if (Status s = validate(path, *mesh); !s) return s.error();
  LoadedMesh out;
  out.mesh = std::move(*mesh);
  out.issues = triangulate_faces(out.mesh);
  out.issues.other_material_primitives = other_materials;
  return out;
}

}  // namespace texbake
