// PLY and OBJ writers. Not OpenMesh's writers: they export from a halfedge
// mesh (ExporterT), which cannot hold the non-manifold faces MeshData keeps.
// Records are formatted straight into a fixed buffer that is written out as
// it fills (ChunkedFile), never the whole file in memory.
#include "mesh_io/write_mesh.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <future>
#include <initializer_list>
#include <memory>
#include <string>
#include <string_view>

#include "mesh_io/atomic_file.h"
#include "mesh_io/byte_order.h"
#include "mesh_io/file_name.h"

namespace texbake {
namespace fs = std::filesystem;

uint8_t colour_to_byte(float c) {
  if (!(c > 0.f)) return 0;  // also NaN
  if (c >= 1.f) return 255;
  return static_cast<uint8_t>(std::lround(c * 255.f));
}

namespace {

Status write_buffer(const fs::path& temp, const fs::path& target, const std::string& data) {
  std::FILE* f = std::fopen(temp.c_str(), "wb");
  if (!f) {
    return make_error(ErrorCode::kIo,
                      "cannot write " + target.string() + ": " + std::strerror(errno));
  }
  const std::size_t written = std::fwrite(data.data(), 1, data.size(), f);
  const bool ok = written == data.size() && std::fflush(f) == 0;
  const int err = errno;
  if (std::fclose(f) != 0 || !ok) {
    return make_error(ErrorCode::kIo,
                      "cannot write " + target.string() + ": " + std::strerror(err));
  }
  return ok_status();
}

// A file written through fixed buffers that are filled in place and written
// out whenever the next record might not fit: a mesh file is never whole in
// memory (a 13M-triangle OBJ is 1 GB of text, whose buffer cost as much to
// fault in as to format). A full buffer is written by a helper thread while
// the next one is formatted (two buffers in turn): copying 1 GB into the page
// cache takes this VM about as long as formatting it. I/O overlap only, not
// a parallel loop, so not under --threads; the bytes do not depend on it.
class ChunkedFile {
 public:
  static constexpr std::size_t kChunk = std::size_t{8} << 20;

  ChunkedFile(const fs::path& temp, const fs::path& target)
      : target_(target),
        f_(std::fopen(temp.c_str(), "wb")),
        err_(f_ ? 0 : (errno ? errno : EIO)),  // before the allocations can touch errno
        buf_(new char[kChunk]),
        spare_(new char[kChunk]) {}
  ~ChunkedFile() {
    wait();
    if (f_) std::fclose(f_);
  }
  ChunkedFile(const ChunkedFile&) = delete;
  ChunkedFile& operator=(const ChunkedFile&) = delete;

  // Where the next at most n (<= kChunk) bytes go; hand the end back to done().
  char* room(std::size_t n) {
    if (kChunk - used_ < n) flush();
    return buf_.get() + used_;
  }
  void done(char* end) { used_ = static_cast<std::size_t>(end - buf_.get()); }
  void append(std::string_view text) {
    for (std::size_t at = 0; at < text.size();) {
      const std::size_t n = std::min(text.size() - at, kChunk);
      char* p = room(n);
      std::memcpy(p, text.data() + at, n);
      done(p + n);
      at += n;
    }
  }

  Status close() {
    flush();
    wait();
    if (f_) {
      if (std::fflush(f_) != 0 && err_ == 0) err_ = errno ? errno : EIO;
      if (std::fclose(f_) != 0 && err_ == 0) err_ = errno ? errno : EIO;
      f_ = nullptr;
    }
    if (err_ != 0) {
      return make_error(ErrorCode::kIo,
                        "cannot write " + target_.string() + ": " + std::strerror(err_));
    }
    return ok_status();
  }

 private:
  // Waits for the buffer being written; keeps the first error.
  void wait() {
    if (!writing_.valid()) return;
    const int e = writing_.get();
    if (err_ == 0) err_ = e;
  }
  // Hands the filled buffer to the writer and takes the other one.
  void flush() {
    wait();
    if (used_ > 0 && f_ && err_ == 0) {
      std::swap(buf_, spare_);
      writing_ = std::async(std::launch::async, [f = f_, data = spare_.get(), n = used_] {
        return std::fwrite(data, 1, n, f) == n ? 0 : (errno ? errno : EIO);
      });
    }
    used_ = 0;
  }

  fs::path target_;
  std::FILE* f_;
  int err_;
  std::unique_ptr<char[]> buf_, spare_;
  std::future<int> writing_;
  std::size_t used_ = 0;
};

// Formatting into a ChunkedFile's room: each returns the end of what it wrote.
// A float in the shortest form that reads back to the same float (at most
// 15 characters; room for 24), an unsigned integer (at most 20).
constexpr std::size_t kMaxFloatChars = 24, kMaxUintChars = 20;
inline char* put_float(char* p, float v) {
  return std::to_chars(p, p + kMaxFloatChars, v).ptr;
}
inline char* put_uint(char* p, uint64_t v) {
  return std::to_chars(p, p + kMaxUintChars, v).ptr;
}

template <class T>
inline char* put_le(char* p, T v) {
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    if constexpr (sizeof(T) == 4) {
      uint32_t u;
      std::memcpy(&u, &v, 4);
      u = byte_swap(u);
      std::memcpy(p, &u, 4);
      return p + 4;
    }
  }
  std::memcpy(p, &v, sizeof(T));
  return p + sizeof(T);
}

struct ColourInfo {
  std::span<const std::array<float, 4>> colours;  // empty: none
  bool alpha = false;
};

ColourInfo colour_info(const MeshData& mesh, const MeshWriteOptions& options) {
  ColourInfo info;
  info.colours = options.vertex_colors.empty()
                     ? std::span<const std::array<float, 4>>(mesh.vertex_colors)
                     : options.vertex_colors;
  for (const auto& c : info.colours) {
    if (colour_to_byte(c[3]) != 255) {
      info.alpha = true;
      break;
    }
  }
  return info;
}

std::string ply_header(const MeshData& mesh, const ColourInfo& ci, bool ascii, bool wide_count) {
  std::string h = "ply\nformat ";
  h += ascii ? "ascii 1.0\n" : "binary_little_endian 1.0\n";
  h += "comment written by texbake\n";
  h += "element vertex " + std::to_string(mesh.vertex_count()) + "\n";
  h += "property float x\nproperty float y\nproperty float z\n";
  if (!ci.colours.empty()) {
    h += "property uchar red\nproperty uchar green\nproperty uchar blue\n";
    if (ci.alpha) h += "property uchar alpha\n";
  }
  h += "element face " + std::to_string(mesh.face_count()) + "\n";
  h += wide_count ? "property list int int vertex_indices\n"
                  : "property list uchar int vertex_indices\n";
  h += "end_header\n";
  return h;
}

Status write_ply(const fs::path& path, const MeshData& mesh, const MeshWriteOptions& options) {
  const ColourInfo ci = colour_info(mesh, options);
  std::size_t max_corners = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    max_corners =
        std::max<std::size_t>(max_corners, mesh.face_offsets[f + 1] - mesh.face_offsets[f]);
  }
  const bool wide = max_corners > 255;
  const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
  const std::size_t channels = ci.colours.empty() ? 0 : (ci.alpha ? 4 : 3);
  auto write = [&](const fs::path& temp) {
    ChunkedFile out(temp, path);
    out.append(ply_header(mesh, ci, options.ascii, wide));
    if (!options.ascii) {
      for (std::size_t v = 0; v < nv; ++v) {
        char* p = out.room(16);
        const Float3& q = mesh.positions[v];
        p = put_le(p, q.x);
        p = put_le(p, q.y);
        p = put_le(p, q.z);
        for (std::size_t k = 0; k < channels; ++k)
          *p++ = static_cast<char>(colour_to_byte(ci.colours[v][k]));
        out.done(p);
      }
      for (std::size_t f = 0; f < nf; ++f) {
        const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
        char* p = out.room(4);
        if (wide)
          p = put_le(p, static_cast<int32_t>(e - b));
        else
          *p++ = static_cast<char>(static_cast<uint8_t>(e - b));
        out.done(p);
        for (uint32_t c = b; c < e; ++c) {
          p = out.room(4);
          out.done(put_le(p, static_cast<int32_t>(mesh.face_vertices[c])));
        }
      }
    } else {
      for (std::size_t v = 0; v < nv; ++v) {
        char* p = out.room(3 * (kMaxFloatChars + 1) + 4 * 4 + 1);
        const Float3& q = mesh.positions[v];
        p = put_float(p, q.x);
        *p++ = ' ';
        p = put_float(p, q.y);
        *p++ = ' ';
        p = put_float(p, q.z);
        for (std::size_t k = 0; k < channels; ++k) {
          *p++ = ' ';
          p = put_uint(p, colour_to_byte(ci.colours[v][k]));
        }
        *p++ = '\n';
        out.done(p);
      }
      for (std::size_t f = 0; f < nf; ++f) {
        const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
        char* p = out.room(kMaxUintChars);
        out.done(put_uint(p, e - b));
        for (uint32_t c = b; c < e; ++c) {
          p = out.room(kMaxUintChars + 1);
          *p++ = ' ';
          out.done(put_uint(p, mesh.face_vertices[c]));
        }
        p = out.room(1);
        *p++ = '\n';
        out.done(p);
      }
    }
    return out.close();
  };
  return write_atomically(path, write);
}

Status write_obj(const fs::path& path, const MeshData& mesh, const MeshWriteOptions& options) {
  const ColourInfo ci = colour_info(mesh, options);
  const bool uvs = mesh.has_uvs() && mesh.corner_uv.size() == mesh.face_vertices.size();
  const bool normals =
      !mesh.corner_normal.empty() && mesh.corner_normal.size() == mesh.face_vertices.size();
  const fs::path mtl_path = fs::path(path).replace_extension(".mtl");
  if (!options.obj_material_texture.empty()) {
    const std::string mtl =
        "# written by texbake\nnewmtl texbake\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd " +
        options.obj_material_texture + "\n" +
        (options.obj_material_alpha ? "map_d " + options.obj_material_texture + "\n" : "");
    Status s = stage_or_write(options.file_set, mtl_path, [&](const fs::path& temp) {
      return write_buffer(temp, mtl_path, mtl);
    });
    if (!s) return s;
  }
  auto write = [&](const fs::path& temp) {
    ChunkedFile out(temp, path);
    out.append("# written by texbake\n");
    if (!options.obj_material_texture.empty()) {
      out.append("mtllib " + mtl_path.filename().string() + "\nusemtl texbake\n");
    }
    // "<tag> a b c\n": the values after spaces, in put_float's form.
    auto put_floats = [&](std::string_view tag, std::initializer_list<float> values) {
      char* p = out.room(tag.size() + values.size() * (kMaxFloatChars + 1) + 1);
      p = std::copy(tag.begin(), tag.end(), p);
      for (float v : values) {
        *p++ = ' ';
        p = put_float(p, v);
      }
      *p++ = '\n';
      out.done(p);
    };
    for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
      const Float3& q = mesh.positions[v];
      if (ci.colours.empty()) {
        put_floats("v", {q.x, q.y, q.z});
      } else {
        const auto& c = ci.colours[v];
        put_floats("v", {q.x, q.y, q.z, colour_to_byte(c[0]) / 255.f, colour_to_byte(c[1]) / 255.f,
                         colour_to_byte(c[2]) / 255.f});
      }
    }
    if (uvs) {
      for (const Float2& t : mesh.uvs) put_floats("vt", {t.u, t.v});
    }
    if (normals) {
      for (const Float3& n : mesh.normals) put_floats("vn", {n.x, n.y, n.z});
    }
    for (std::size_t f = 0; f < mesh.face_count(); ++f) {
      char* p = out.room(1);
      *p++ = 'f';
      out.done(p);
      for (uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
        p = out.room(3 * (kMaxUintChars + 1));
        *p++ = ' ';
        p = put_uint(p, uint64_t{mesh.face_vertices[c]} + 1);  // OBJ is 1-based
        if (uvs || normals) {
          *p++ = '/';
          if (uvs) p = put_uint(p, uint64_t{mesh.corner_uv[c]} + 1);
          if (normals) {
            *p++ = '/';
            p = put_uint(p, uint64_t{mesh.corner_normal[c]} + 1);
          }
        }
        out.done(p);
      }
      p = out.room(1);
      *p++ = '\n';
      out.done(p);
    }
    return out.close();
  };
  return stage_or_write(options.file_set, path, write);
}

}  // namespace

Status write_mesh(const fs::path& path, const MeshData& mesh, const MeshWriteOptions& options) {
  if (!options.vertex_colors.empty() && options.vertex_colors.size() != mesh.vertex_count()) {
    return make_error(ErrorCode::kInternal, "cannot write " + path.string() + ": " +
                                                std::to_string(options.vertex_colors.size()) +
                                                " colours for " +
                                                std::to_string(mesh.vertex_count()) + " vertices");
  }
  const std::string ext = lower_extension(path);
  if (ext == ".ply") return write_ply(path, mesh, options);
  if (ext == ".obj") return write_obj(path, mesh, options);
  if (ext == ".glb") {  // a caller bug: GLB has writers of its own
    return make_error(
        ErrorCode::kUnsupported,
        "cannot write " + path.string() +
            ": write_mesh writes .ply and .obj; GLB goes through "
            "write_vertex_color_glb or write_textured_mesh (mesh_io/write_textured.h)");
  }
  return make_error(ErrorCode::kUnsupported, "cannot write " + path.string() +
                                                 ": unknown mesh format '" + ext +
                                                 "' (texbake writes .ply and .obj)");
}

}  // namespace texbake
