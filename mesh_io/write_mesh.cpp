// PLY and OBJ writers. Not OpenMesh's writers: they export from a halfedge
// mesh (ExporterT), which cannot hold the non-manifold faces MeshData keeps,
// and the output is one memory buffer written at once (830k triangles in a
// few tens of milliseconds; issue #3's budget).
#include "mesh_io/write_mesh.h"

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <initializer_list>
#include <string>

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

// Appends a float in the shortest form that reads back to the same float.
void append_float(std::string& out, float v) {
  char buf[32];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
}
// Appends " a b c" (each value after a space), in append_float's form.
void append_floats(std::string& out, std::initializer_list<float> values) {
  for (float v : values) {
    out += ' ';
    append_float(out, v);
  }
}
void append_uint(std::string& out, uint64_t v) {
  char buf[24];
  auto r = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, r.ptr);
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
  std::string out = ply_header(mesh, ci, options.ascii, wide);
  const std::size_t nv = mesh.vertex_count(), nf = mesh.face_count();
  const std::size_t channels = ci.colours.empty() ? 0 : (ci.alpha ? 4 : 3);
  if (!options.ascii) {
    const std::size_t header = out.size();
    const std::size_t vrec = 12 + channels;
    out.resize(header + nv * vrec + nf * (wide ? 4 : 1) + mesh.face_vertices.size() * 4);
    char* p = out.data() + header;
    for (std::size_t v = 0; v < nv; ++v) {
      const Float3& q = mesh.positions[v];
      p = put_le(p, q.x);
      p = put_le(p, q.y);
      p = put_le(p, q.z);
      for (std::size_t k = 0; k < channels; ++k)
        *p++ = static_cast<char>(colour_to_byte(ci.colours[v][k]));
    }
    for (std::size_t f = 0; f < nf; ++f) {
      const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
      if (wide)
        p = put_le(p, static_cast<int32_t>(e - b));
      else
        *p++ = static_cast<char>(static_cast<uint8_t>(e - b));
      for (uint32_t c = b; c < e; ++c) p = put_le(p, static_cast<int32_t>(mesh.face_vertices[c]));
    }
  } else {
    out.reserve(out.size() + nv * 40 + mesh.face_vertices.size() * 8);
    for (std::size_t v = 0; v < nv; ++v) {
      const Float3& q = mesh.positions[v];
      append_float(out, q.x);
      out += ' ';
      append_float(out, q.y);
      out += ' ';
      append_float(out, q.z);
      for (std::size_t k = 0; k < channels; ++k) {
        out += ' ';
        append_uint(out, colour_to_byte(ci.colours[v][k]));
      }
      out += '\n';
    }
    for (std::size_t f = 0; f < nf; ++f) {
      const uint32_t b = mesh.face_offsets[f], e = mesh.face_offsets[f + 1];
      append_uint(out, e - b);
      for (uint32_t c = b; c < e; ++c) {
        out += ' ';
        append_uint(out, mesh.face_vertices[c]);
      }
      out += '\n';
    }
  }
  return write_atomically(path,
                          [&](const fs::path& temp) { return write_buffer(temp, path, out); });
}

Status write_obj(const fs::path& path, const MeshData& mesh, const MeshWriteOptions& options) {
  const ColourInfo ci = colour_info(mesh, options);
  const bool uvs = mesh.has_uvs() && mesh.corner_uv.size() == mesh.face_vertices.size();
  const bool normals =
      !mesh.corner_normal.empty() && mesh.corner_normal.size() == mesh.face_vertices.size();
  std::string out = "# written by texbake\n";
  const fs::path mtl_path = fs::path(path).replace_extension(".mtl");
  if (!options.obj_material_texture.empty()) {
    out += "mtllib " + mtl_path.filename().string() + "\nusemtl texbake\n";
  }
  out.reserve(mesh.vertex_count() * 48 + mesh.face_vertices.size() * 16);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const Float3& q = mesh.positions[v];
    out += 'v';
    append_floats(out, {q.x, q.y, q.z});
    if (!ci.colours.empty()) {
      const auto& c = ci.colours[v];
      append_floats(out, {colour_to_byte(c[0]) / 255.f, colour_to_byte(c[1]) / 255.f,
                          colour_to_byte(c[2]) / 255.f});
    }
    out += '\n';
  }
  if (uvs) {
    for (const Float2& t : mesh.uvs) {
      out += "vt";
      append_floats(out, {t.u, t.v});
      out += '\n';
    }
  }
  if (normals) {
    for (const Float3& n : mesh.normals) {
      out += "vn";
      append_floats(out, {n.x, n.y, n.z});
      out += '\n';
    }
  }
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    out += 'f';
    for (uint32_t c = mesh.face_offsets[f]; c < mesh.face_offsets[f + 1]; ++c) {
      out += ' ';
      append_uint(out, uint64_t{mesh.face_vertices[c]} + 1);  // OBJ is 1-based
      if (uvs || normals) {
        out += '/';
        if (uvs) append_uint(out, uint64_t{mesh.corner_uv[c]} + 1);
        if (normals) {
          out += '/';
          append_uint(out, uint64_t{mesh.corner_normal[c]} + 1);
        }
      }
    }
    out += '\n';
  }
  if (!options.obj_material_texture.empty()) {
    const std::string mtl =
        "# written by texbake\nnewmtl texbake\nKa 1 1 1\nKd 1 1 1\nKs 0 0 0\nmap_Kd " +
        options.obj_material_texture + "\n";
    Status s = stage_or_write(options.file_set, mtl_path, [&](const fs::path& temp) {
      return write_buffer(temp, mtl_path, mtl);
    });
    if (!s) return s;
  }
  return stage_or_write(options.file_set, path,
                        [&](const fs::path& temp) { return write_buffer(temp, path, out); });
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
