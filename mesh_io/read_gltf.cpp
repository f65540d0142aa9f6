// glTF 2.0 (.glb binary and .gltf JSON with external or data: buffers and
// images), parsed by tinygltf (the Debian shared library, as the GLB writers
// use it), behind checks of texbake's own, because tinygltf 2.7 trusts its
// input in places:
//  - a .glb's container (header, chunk lengths) is checked here first:
//    tinygltf 2.7 does not count the BIN chunk's 8-byte header when it checks
//    the chunk against the file, so a lying length reads past the end;
//  - the JSON's nesting depth is limited (mesh_io/json_strict.h) before it is parsed:
//    the parsed document is freed recursively, so a file of a million '['
//    would overflow the stack;
//  - tinygltf reads external files through callbacks of texbake's (regular
//    files only, a FIFO would block; no '~' or environment expansion; only
//    inside the glTF file's folder, not in the current folder as tinygltf
//    also looks: a URI that is absolute, of another scheme than data:, or
//    leaves the folder once ".." and links are resolved is refused before
//    anything is opened);
//  - values tinygltf reports as malformed but drops silently (its `err`
//    after a successful load) are errors;
//  - images are not decoded by tinygltf (its stb_image copy): an embedded
//    image is kept as its encoded bytes (MeshData::texture_bytes), an
//    external one as its path (MeshData::texture_path);
//  - every accessor, buffer view and index texbake uses is checked against
//    its buffer here before a byte is read (tinygltf checks none of them).
//
// What is read: every primitive of every mesh of every node of the default
// scene (else scene 0; with no scene at all, every mesh once, untransformed),
// nodes in depth-first order, primitives in order. Each primitive's
// vertices follow the previous ones' (a mesh used by two nodes is read
// twice), its triangles become faces. Positions and normals are carried to
// the scene's frame by the node's world transform (matrix, or T * R * S,
// composed down the hierarchy); normals by the inverse transpose; where the
// transform mirrors (negative determinant) each triangle's corners 2 and 3
// swap, so the front faces stay front faces (glTF 2.0, section 3.7.4).
#include <tiny_gltf.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "mapping/sample.h"
#include "mesh_io/byte_order.h"
#include "mesh_io/file_name.h"
#include "mesh_io/json_strict.h"
#include "mesh_io/read_mesh_internal.h"
#include "mesh_io/regular_file.h"
#include "mesh_io/text_scan.h"

namespace texbake::read_detail {
namespace fs = std::filesystem;

namespace {

// An external buffer or image file tinygltf may read whole: 4 GiB (the
// largest a GLB can hold).
constexpr std::uintmax_t kMaxExternalBytes = std::uintmax_t{1} << 32;

// Instancing multiplies a mesh by its nodes: a small file could describe
// billions of triangles. At most this many corners and vertices beyond the
// total size in bytes of the file's buffers (a primitive's own data cannot
// describe more corners than it has bytes).
constexpr std::uint64_t kInstancingAllowance = std::uint64_t{1} << 24;

// ---------------------------------------------------------------------------
// Checks before tinygltf parses.

uint32_t le32(const std::string_view bytes, std::size_t at) {
  return load_le32(bytes.data() + at);
}

// The GLB container (glTF 2.0, section 4.4): a 12-byte header ("glTF",
// version 2, total length = the file's size), then chunks of an 8-byte
// header (length, type) and their 4-byte aligned data: JSON first, BIN
// optionally second, other types ignored. Returns the JSON chunk.
Expected<std::string_view> check_glb(const fs::path& path, std::string_view b) {
  if (b.size() < 12 || b.substr(0, 4) != "glTF") {
    return parse_error(path, b.size() >= 4 && b.substr(0, 4) != "glTF"
                                 ? "not a binary glTF file (no 'glTF' magic)"
                                 : "truncated: " + std::to_string(b.size()) +
                                       " bytes, shorter than the 12-byte GLB header");
  }
  if (le32(b, 4) != 2) {
    return parse_error(
        path, "GLB version " + std::to_string(le32(b, 4)) + "; texbake reads glTF 2.0 (version 2)");
  }
  const uint64_t length = le32(b, 8);
  if (length != b.size()) {
    return parse_error(path, "the GLB header declares " + std::to_string(length) +
                                 " bytes but the file has " + std::to_string(b.size()) +
                                 (length > b.size() ? " (truncated)" : " (corrupt)"));
  }
  std::string_view json;
  uint64_t at = 12;
  for (int chunk = 0; at < length; ++chunk) {
    if (at + 8 > length) {
      return parse_error(
          path, "truncated: GLB chunk " + std::to_string(chunk) + " has no complete 8-byte header");
    }
    const uint64_t n = le32(b, at);
    const uint32_t type = le32(b, at + 4);
    if (at + 8 + n > length) {
      return parse_error(path, "GLB chunk " + std::to_string(chunk) + " declares " +
                                   std::to_string(n) + " bytes, past the end of the file (" +
                                   std::to_string(length - at - 8) + " left; truncated)");
    }
    if (chunk == 0) {
      if (type != 0x4E4F534Au) return parse_error(path, "the first GLB chunk is not JSON");
      if (n == 0) return parse_error(path, "the GLB's JSON chunk is empty");
      json = b.substr(at + 8, n);
    } else if (chunk == 1 && type != 0x004E4942u) {
      return parse_error(path, "the second GLB chunk is not BIN");
    }
    if (n % 4 != 0) {
      return parse_error(
          path, "GLB chunk " + std::to_string(chunk) + " is not padded to 4 bytes (corrupt)");
    }
    at += 8 + n;
  }
  if (json.empty()) return parse_error(path, "the GLB has no JSON chunk");
  return json;
}

// ---------------------------------------------------------------------------
// tinygltf's file access and image callback.

// External files (buffers, images) are read from the glTF file's own folder
// only (README: "beside the .gltf"): a URI must be a relative path that,
// with ".." and symbolic links resolved, names a file inside that folder.
// An absolute path, another scheme than data: (file:, http:) or a path
// leaving the folder is refused before anything is opened. data: URIs never
// reach these callbacks (tinygltf decodes them).

// The glTF file's folder, absolute, links resolved.
fs::path gltf_folder(const fs::path& gltf) {
  std::error_code ec;
  fs::path folder = fs::absolute(gltf, ec).parent_path();
  const fs::path resolved = fs::weakly_canonical(folder, ec);
  return ec ? folder.lexically_normal() : resolved;
}

// Why `uri` (percent-decoded) may not be read beside the glTF whose folder
// is `folder` (from gltf_folder), or "" if it may.
std::string uri_refusal(const fs::path& folder, const std::string& uri) {
  if (!uri.empty() && (uri[0] == '/' || uri[0] == '\\')) return "is an absolute path";
  // RFC 3986 scheme: ALPHA *(ALPHA / DIGIT / "+" / "-" / ".") ":" (also
  // catches a Windows drive, "C:").
  const std::size_t colon = uri.find(':');
  if (colon != std::string::npos && colon > 0 && std::isalpha(static_cast<unsigned char>(uri[0])) &&
      std::all_of(uri.begin(), uri.begin() + colon, [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '+' || c == '-' || c == '.';
      })) {
    return "is a URI of scheme '" + uri.substr(0, colon) + "' (texbake reads data: URIs and paths)";
  }
  std::error_code ec;
  const fs::path target = fs::weakly_canonical(folder / fs::u8path(uri), ec);
  if (ec) return "cannot be resolved (" + ec.message() + ")";
  const auto f = std::mismatch(folder.begin(), folder.end(), target.begin(), target.end()).first;
  if (f != folder.end()) return "leaves the glTF's folder";
  return "";
}

struct FsContext {
  std::string base_dir;  // the glTF file's folder, absolute (tinygltf's basedir)
  fs::path folder;       // the same, links resolved (gltf_folder)
  // The first URI refused, and why (uri_refusal); reported after tinygltf returns.
  std::string refused_uri, refusal;
};

// tinygltf looks for a file as JoinPath(basedir, uri), then as "./" + uri;
// only the first is allowed, and only when uri_refusal finds nothing.
bool fs_exists(const std::string& name, void* user) {
  auto* ctx = static_cast<FsContext*>(user);
  const std::string prefix = ctx->base_dir.back() == '/' ? ctx->base_dir : ctx->base_dir + "/";
  if (name.rfind(prefix, 0) != 0) return false;
  const std::string uri = name.substr(prefix.size());
  if (std::string why = uri_refusal(ctx->folder, uri); !why.empty()) {
    if (ctx->refused_uri.empty()) ctx->refused_uri = uri, ctx->refusal = why;
    return false;
  }
  return static_cast<bool>(check_regular_file(name, "a glTF buffer or image"));
}

Error refused_uri_error(const fs::path& path, const std::string& uri, const std::string& why) {
  return parse_error(path, "the URI '" + uri + "' " + why +
                               "; texbake reads external buffers and images only from the "
                               "glTF file's folder");
}

std::string fs_expand(const std::string& name, void*) {
  return name;
}

bool fs_read(std::vector<unsigned char>* out, std::string* err, const std::string& name, void*) {
  auto fail = [&](const std::string& why) {
    if (err) *err = why;
    return false;
  };
  if (Status s = check_regular_file(name, "a glTF buffer or image"); !s) {
    return fail(s.error().message);
  }
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(name, ec);
  if (ec) return fail(name + ": cannot read (" + ec.message() + ")");
  if (size > kMaxExternalBytes) return fail(name + ": larger than 4 GiB");
  std::FILE* f = std::fopen(name.c_str(), "rb");
  if (!f) return fail(name + ": cannot open (" + std::strerror(errno) + ")");
  out->resize(static_cast<std::size_t>(size));
  const std::size_t got = size ? std::fread(out->data(), 1, out->size(), f) : 0;
  std::fclose(f);
  if (got != size) return fail(name + ": cannot read");
  return true;
}

bool fs_write(std::string*, const std::string&, const std::vector<unsigned char>&, void*) {
  return false;
}

// Images stay encoded: a data: URI's bytes are kept in image->image; an
// external image (uri set) and one in a bufferView (read and checked later,
// from the model) keep nothing here.
bool keep_encoded(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                  const unsigned char* bytes, int size, void*) {
  if (image->bufferView >= 0 || !image->uri.empty()) return true;
  if (size > 0) image->image.assign(bytes, bytes + size);
  return true;
}

std::string first_line(const std::string& s) {
  std::string l = s.substr(0, s.find('\n'));
  while (!l.empty() && std::isspace(static_cast<unsigned char>(l.back()))) l.pop_back();
  return l.empty() ? "tinygltf gave no reason" : l;
}

// ---------------------------------------------------------------------------
// Transforms: 4x4 column-major doubles, as glTF stores them.

using Mat4 = std::array<double, 16>;
constexpr Mat4 kIdentity = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};

Mat4 multiply(const Mat4& a, const Mat4& b) {
  Mat4 m{};
  for (int c = 0; c < 4; ++c) {
    for (int r = 0; r < 4; ++r) {
      double s = 0;
      for (int k = 0; k < 4; ++k) s += a[k * 4 + r] * b[c * 4 + k];
      m[c * 4 + r] = s;
    }
  }
  return m;
}

bool all_finite(const std::vector<double>& v) {
  return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
}

// The node's local transform: `matrix`, else T * R * S (glTF 2.0, section
// 3.5.2); the rotation quaternion (x, y, z, w) is normalised.
Expected<Mat4> local_transform(const fs::path& path, const tinygltf::Node& node, int index) {
  const std::string where = "node " + std::to_string(index);
  auto bad = [&](const char* what, std::size_t n, std::size_t want) {
    return parse_error(path, where + " has a " + what + " of " + std::to_string(n) +
                                 " numbers (glTF: " + std::to_string(want) + ")");
  };
  if (!node.matrix.empty()) {
    if (node.matrix.size() != 16) return bad("matrix", node.matrix.size(), 16);
    if (!all_finite(node.matrix)) return parse_error(path, where + " has a non-finite matrix");
    Mat4 m;
    std::copy(node.matrix.begin(), node.matrix.end(), m.begin());
    return m;
  }
  if (!node.translation.empty() && node.translation.size() != 3)
    return bad("translation", node.translation.size(), 3);
  if (!node.rotation.empty() && node.rotation.size() != 4)
    return bad("rotation", node.rotation.size(), 4);
  if (!node.scale.empty() && node.scale.size() != 3) return bad("scale", node.scale.size(), 3);
  if (!all_finite(node.translation) || !all_finite(node.rotation) || !all_finite(node.scale))
    return parse_error(path, where + " has a non-finite translation, rotation or scale");
  double x = 0, y = 0, z = 0, w = 1;
  if (!node.rotation.empty()) {
    x = node.rotation[0], y = node.rotation[1], z = node.rotation[2], w = node.rotation[3];
    const double n = std::sqrt(x * x + y * y + z * z + w * w);
    if (!(n > 0)) return parse_error(path, where + " has a zero rotation quaternion");
    x /= n, y /= n, z /= n, w /= n;
  }
  const double r[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)},
                          {2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)},
                          {2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)}};
  const double s[3] = {node.scale.empty() ? 1 : node.scale[0],
                       node.scale.empty() ? 1 : node.scale[1],
                       node.scale.empty() ? 1 : node.scale[2]};
  Mat4 m{};
  for (int c = 0; c < 3; ++c) {
    for (int row = 0; row < 3; ++row) m[c * 4 + row] = r[row][c] * s[c];
  }
  for (int k = 0; k < 3; ++k) m[12 + k] = node.translation.empty() ? 0 : node.translation[k];
  m[15] = 1;
  return m;
}

// ---------------------------------------------------------------------------
// Accessors.

struct Reader {
  const fs::path& path;
  const tinygltf::Model& model;
};

int component_bytes(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return 2;
    case TINYGLTF_COMPONENT_TYPE_INT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return 4;
    default:
      return 0;
  }
}

// An accessor's elements as raw bytes: `data` (null when the accessor has
// no bufferView: all zeros, glTF 2.0 section 3.6.2.3), `stride` between
// elements, `count`; everything checked to lie inside its buffer.
struct Elements {
  const unsigned char* data = nullptr;
  std::size_t stride = 0, count = 0;
  int components = 0, component_type = 0;
  bool normalized = false;
};

// `what` names the accessor's use ("mesh 0 primitive 1 POSITION").
Expected<Elements> elements(const Reader& r, int index, const std::string& what,
                            std::initializer_list<int> types) {
  const tinygltf::Model& m = r.model;
  const std::string acc_name = what + " (accessor " + std::to_string(index) + ")";
  if (index < 0 || static_cast<std::size_t>(index) >= m.accessors.size()) {
    return parse_error(r.path, what + " refers to accessor " + std::to_string(index) +
                                   " but there are " + std::to_string(m.accessors.size()));
  }
  const tinygltf::Accessor& a = m.accessors[index];
  if (a.sparse.isSparse) {
    return parse_error(r.path, acc_name + " is sparse; texbake does not read sparse accessors");
  }
  if (std::find(types.begin(), types.end(), a.type) == types.end()) {
    return parse_error(r.path, acc_name + " has the wrong type for its use");
  }
  const int cb = component_bytes(a.componentType);
  if (cb == 0) {
    return parse_error(r.path, acc_name + " has component type " + std::to_string(a.componentType) +
                                   ", not one glTF defines");
  }
  Elements e;
  e.components = tinygltf::GetNumComponentsInType(a.type);
  e.component_type = a.componentType;
  e.normalized = a.normalized;
  e.count = a.count;
  const uint64_t elem = uint64_t(cb) * e.components;
  if (a.bufferView < 0) return e;  // zeros
  if (static_cast<std::size_t>(a.bufferView) >= m.bufferViews.size()) {
    return parse_error(r.path, acc_name + " refers to bufferView " + std::to_string(a.bufferView) +
                                   " but there are " + std::to_string(m.bufferViews.size()));
  }
  const tinygltf::BufferView& v = m.bufferViews[a.bufferView];
  const std::string view_name = "bufferView " + std::to_string(a.bufferView);
  if (v.buffer < 0 || static_cast<std::size_t>(v.buffer) >= m.buffers.size()) {
    return parse_error(r.path, view_name + " refers to buffer " + std::to_string(v.buffer) +
                                   " but there are " + std::to_string(m.buffers.size()));
  }
  const std::vector<unsigned char>& buf = m.buffers[v.buffer].data;
  if (uint64_t(v.byteOffset) > buf.size() || uint64_t(v.byteLength) > buf.size() - v.byteOffset) {
    return parse_error(r.path, view_name + " (bytes " + std::to_string(v.byteOffset) + " + " +
                                   std::to_string(v.byteLength) + ") lies outside buffer " +
                                   std::to_string(v.buffer) + " of " + std::to_string(buf.size()) +
                                   " bytes");
  }
  e.stride = v.byteStride ? v.byteStride : elem;
  if (e.stride < elem) {
    return parse_error(r.path, view_name + " has byteStride " + std::to_string(v.byteStride) +
                                   ", less than the " + std::to_string(elem) +
                                   "-byte elements of " + acc_name);
  }
  if (e.count > 0) {
    const uint64_t last = uint64_t(e.count - 1);
    // count and stride are below 2^64 / 2^8: compare without overflow.
    if (uint64_t(a.byteOffset) > v.byteLength || last > (v.byteLength - a.byteOffset) / e.stride ||
        last * e.stride + elem > v.byteLength - a.byteOffset) {
      return parse_error(r.path, acc_name + ": " + std::to_string(e.count) +
                                     " elements from byte " + std::to_string(a.byteOffset) +
                                     " do not fit in " + view_name + " of " +
                                     std::to_string(v.byteLength) + " bytes");
    }
  }
  e.data = buf.data() + v.byteOffset + a.byteOffset;
  return e;
}

template <class T>
T load(const unsigned char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::endian::native == std::endian::big && sizeof(T) > 1) {
    using U = std::conditional_t<sizeof(T) == 2, uint16_t, uint32_t>;
    U u;
    std::memcpy(&u, &v, sizeof u);
    u = byte_swap(u);
    std::memcpy(&v, &u, sizeof v);
  }
  return v;
}

// Component k of element i as a float: float as stored; integers as their
// value, or normalised when the accessor says so (glTF 2.0, section 3.11:
// unsigned c / max, signed max(c / max, -1)).
float component(const Elements& e, std::size_t i, int k) {
  if (!e.data) return 0.f;
  const unsigned char* p = e.data + i * e.stride + k * component_bytes(e.component_type);
  switch (e.component_type) {
    case TINYGLTF_COMPONENT_TYPE_FLOAT:
      return load<float>(p);
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return e.normalized ? p[0] / 255.f : p[0];
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      const auto c = static_cast<int8_t>(p[0]);
      return e.normalized ? std::max(c / 127.f, -1.f) : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      const auto c = load<uint16_t>(p);
      return e.normalized ? c / 65535.f : c;
    }
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      const auto c = load<int16_t>(p);
      return e.normalized ? std::max(c / 32767.f, -1.f) : c;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      const auto c = load<uint32_t>(p);
      return e.normalized ? static_cast<float>(c / 4294967295.0) : static_cast<float>(c);
    }
    case TINYGLTF_COMPONENT_TYPE_INT: {
      const auto c = load<int32_t>(p);
      return e.normalized ? static_cast<float>(std::max(c / 2147483647.0, -1.0))
                          : static_cast<float>(c);
    }
  }
  return 0.f;
}

uint32_t index_value(const Elements& e, std::size_t i) {
  if (!e.data) return 0;
  const unsigned char* p = e.data + i * e.stride;
  switch (e.component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
      return p[0];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
      return load<uint16_t>(p);
    default:
      return load<uint32_t>(p);
  }
}

// ---------------------------------------------------------------------------
// The scene.

struct Instance {
  int mesh;
  Mat4 world;
};

// The meshes of the scene's nodes with their world transforms, depth first
// (an explicit stack: a long chain of nodes must not overflow the call
// stack). A node met twice (a cycle, or two parents) is an error: glTF
// nodes form a tree (section 3.5.1).
Expected<std::vector<Instance>> scene_instances(const fs::path& path, const tinygltf::Model& m) {
  std::vector<Instance> out;
  if (m.scenes.empty()) {
    for (std::size_t i = 0; i < m.meshes.size(); ++i)
      out.push_back({static_cast<int>(i), kIdentity});
    return out;
  }
  int scene = m.defaultScene < 0 ? 0 : m.defaultScene;
  if (static_cast<std::size_t>(scene) >= m.scenes.size()) {
    return parse_error(path, "the default scene " + std::to_string(scene) + " does not exist (" +
                                 std::to_string(m.scenes.size()) + " scenes)");
  }
  std::vector<char> seen(m.nodes.size(), 0);
  std::vector<std::pair<int, Mat4>> stack;
  const std::vector<int>& roots = m.scenes[scene].nodes;
  for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, kIdentity});
  while (!stack.empty()) {
    auto [n, parent] = stack.back();
    stack.pop_back();
    if (n < 0 || static_cast<std::size_t>(n) >= m.nodes.size()) {
      return parse_error(path, "scene " + std::to_string(scene) + " refers to node " +
                                   std::to_string(n) + " but there are " +
                                   std::to_string(m.nodes.size()));
    }
    if (seen[n]) {
      return parse_error(path, "node " + std::to_string(n) +
                                   " appears twice in the scene (a cycle, or two parents; glTF "
                                   "nodes form a tree)");
    }
    seen[n] = 1;
    const tinygltf::Node& node = m.nodes[n];
    Expected<Mat4> local = local_transform(path, node, n);
    if (!local) return local.error();
    const Mat4 world = multiply(parent, *local);
    if (node.mesh >= 0) {
      if (static_cast<std::size_t>(node.mesh) >= m.meshes.size()) {
        return parse_error(path, "node " + std::to_string(n) + " refers to mesh " +
                                     std::to_string(node.mesh) + " but there are " +
                                     std::to_string(m.meshes.size()));
      }
      out.push_back({node.mesh, world});
    }
    for (auto it = node.children.rbegin(); it != node.children.rend(); ++it) {
      stack.push_back({*it, world});
    }
  }
  return out;
}

// Required extensions texbake reads or may ignore (they change shading or
// lighting, not geometry or the base colour): KHR_mesh_quantization
// (integer attributes, read by `component`), KHR_materials_* but the
// archived pbrSpecularGlossiness (which replaces the base colour), lights.
// Everything else (KHR_texture_transform, which moves the UVs, texture
// formats, compression) is refused.
bool extension_ok(const std::string& ext) {
  return ext == "KHR_mesh_quantization" || ext == "KHR_lights_punctual" ||
         (ext.rfind("KHR_materials_", 0) == 0 && ext != "KHR_materials_pbrSpecularGlossiness");
}

// The texture of material `mi`, the TEXCOORD set it uses, into `mesh`.
Status read_material(const fs::path& path, const tinygltf::Model& m, int mi, MeshData& mesh,
                     int* texcoord) {
  *texcoord = 0;
  if (mi < 0) return ok_status();
  if (static_cast<std::size_t>(mi) >= m.materials.size()) {
    return parse_error(path, "a primitive refers to material " + std::to_string(mi) +
                                 " but there are " + std::to_string(m.materials.size()));
  }
  const tinygltf::PbrMetallicRoughness& pbr = m.materials[mi].pbrMetallicRoughness;
  if (pbr.baseColorFactor.size() == 4 && all_finite(pbr.baseColorFactor)) {
    mesh.base_color_factor = std::array<float, 4>{
        static_cast<float>(pbr.baseColorFactor[0]), static_cast<float>(pbr.baseColorFactor[1]),
        static_cast<float>(pbr.baseColorFactor[2]), static_cast<float>(pbr.baseColorFactor[3])};
  } else {
    return parse_error(path, "material " + std::to_string(mi) +
                                 " has a baseColorFactor that is not four finite numbers");
  }
  const int ti = pbr.baseColorTexture.index;
  if (ti < 0) return ok_status();
  const std::string where = "material " + std::to_string(mi) + "'s baseColorTexture";
  if (static_cast<std::size_t>(ti) >= m.textures.size()) {
    return parse_error(path, where + " refers to texture " + std::to_string(ti) +
                                 " but there are " + std::to_string(m.textures.size()));
  }
  *texcoord = std::max(0, pbr.baseColorTexture.texCoord);
  const int ii = m.textures[ti].source;
  if (ii < 0) {
    return parse_error(path, "texture " + std::to_string(ti) +
                                 " (the base colour) has no source image texbake can read "
                                 "(an extension's image format?)");
  }
  if (static_cast<std::size_t>(ii) >= m.images.size()) {
    return parse_error(path, "texture " + std::to_string(ti) + " refers to image " +
                                 std::to_string(ii) + " but there are " +
                                 std::to_string(m.images.size()));
  }
  const tinygltf::Image& image = m.images[ii];
  mesh.texture_is_srgb = true;
  if (image.bufferView >= 0) {
    const tinygltf::BufferView& v = m.bufferViews.at(image.bufferView);  // checked by tinygltf
    const std::vector<unsigned char>& buf = m.buffers.at(v.buffer).data;
    if (uint64_t(v.byteOffset) > buf.size() || uint64_t(v.byteLength) > buf.size() - v.byteOffset) {
      return parse_error(path, "image " + std::to_string(ii) + "'s bufferView " +
                                   std::to_string(image.bufferView) + " lies outside its buffer");
    }
    const unsigned char* p = buf.data() + v.byteOffset;
    mesh.texture_bytes.assign(p, p + v.byteLength);
  } else if (!image.uri.empty()) {
    const std::string decoded = percent_decode(image.uri);
    if (std::string why = uri_refusal(gltf_folder(path), decoded); !why.empty()) {
      return refused_uri_error(path, image.uri, why);
    }
    const fs::path full = (path.parent_path() / fs::u8path(decoded)).lexically_normal();
    if (Status s = check_regular_file(full, "an image"); !s) {
      return make_error(ErrorCode::kIo, path.string() + ": the base colour image '" + image.uri +
                                            "': " + s.error().message);
    }
    mesh.texture_path = full.string();
    return ok_status();
  } else {
    mesh.texture_bytes = image.image;  // a data: URI, decoded by tinygltf
  }
  if (mesh.texture_bytes.empty()) {
    return parse_error(path, "image " + std::to_string(ii) + " (the base colour) is empty");
  }
  mesh.texture_mime_type = image.mimeType;
  mesh.texture_name = path.string() + ": image " + std::to_string(ii);
  return ok_status();
}

Expected<MeshData> read_model(const fs::path& path, const tinygltf::Model& m,
                              std::size_t* other_material_primitives) {
  for (const std::string& ext : m.extensionsRequired) {
    if (ext == "KHR_draco_mesh_compression" || ext == "EXT_meshopt_compression") {
      return parse_error(path, "requires " + ext +
                                   ", compressed geometry texbake cannot decode (decompress it "
                                   "first, e.g. gltf-transform copy)");
    }
    if (!extension_ok(ext)) {
      return parse_error(path, "requires the extension " + ext + ", which texbake does not read");
    }
  }
  Expected<std::vector<Instance>> instances = scene_instances(path, m);
  if (!instances) return instances.error();

  uint64_t budget = kInstancingAllowance;
  for (const tinygltf::Buffer& b : m.buffers) budget += b.data.size();

  // The material of the first triangle primitive decides the texture.
  int first_material = -2;
  for (const Instance& in : *instances) {
    for (const tinygltf::Primitive& p : m.meshes[in.mesh].primitives) {
      if (first_material == -2) first_material = p.material;
    }
  }
  MeshData mesh;
  int texcoord = 0;
  if (first_material >= -1) {
    if (Status s = read_material(path, m, first_material, mesh, &texcoord); !s) return s.error();
  }
  const std::string uv_name = "TEXCOORD_" + std::to_string(texcoord);

  std::vector<Float2> uv;
  std::vector<Float3> nrm;
  std::vector<std::array<float, 4>> rgba;
  bool any_uv = false, any_normal = false, any_color = false;
  mesh.face_offsets.push_back(0);
  Reader r{path, m};
  for (const Instance& in : *instances) {
    const tinygltf::Mesh& gm = m.meshes[in.mesh];
    const Mat4& w = in.world;
    // Normal matrix: the cofactors of the upper 3x3 (its inverse transpose
    // times the determinant), sign-corrected by the determinant.
    const double a[3][3] = {{w[0], w[4], w[8]}, {w[1], w[5], w[9]}, {w[2], w[6], w[10]}};
    double cof[3][3];
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        cof[i][j] = a[(i + 1) % 3][(j + 1) % 3] * a[(i + 2) % 3][(j + 2) % 3] -
                    a[(i + 1) % 3][(j + 2) % 3] * a[(i + 2) % 3][(j + 1) % 3];
      }
    }
    const double det = a[0][0] * cof[0][0] + a[0][1] * cof[0][1] + a[0][2] * cof[0][2];
    const bool mirrored = det < 0;
    for (std::size_t pi = 0; pi < gm.primitives.size(); ++pi) {
      const tinygltf::Primitive& p = gm.primitives[pi];
      const std::string where =
          "mesh " + std::to_string(in.mesh) + " primitive " + std::to_string(pi);
      if (p.mode != TINYGLTF_MODE_TRIANGLES && p.mode != -1) {
        static const char* kModes[] = {"POINTS",    "LINES",          "LINE_LOOP",   "LINE_STRIP",
                                       "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
        const std::string mode =
            p.mode >= 0 && p.mode <= 6 ? kModes[p.mode] : "mode " + std::to_string(p.mode);
        return parse_error(path, where + " is " + mode + "; texbake reads TRIANGLES primitives");
      }
      if (p.extensions.count("KHR_draco_mesh_compression")) {
        auto pos_it = p.attributes.find("POSITION");
        if (pos_it == p.attributes.end() || pos_it->second < 0 ||
            static_cast<std::size_t>(pos_it->second) >= m.accessors.size() ||
            m.accessors[pos_it->second].bufferView < 0) {
          return parse_error(path, where +
                                       " is compressed with KHR_draco_mesh_compression, "
                                       "which texbake cannot decode");
        }
      }
      if (p.material != first_material) ++*other_material_primitives;
      auto attr = [&](const std::string& name) {
        auto it = p.attributes.find(name);
        return it == p.attributes.end() ? -2 : it->second;
      };
      const int pos_index = attr("POSITION");
      if (pos_index == -2) return parse_error(path, where + " has no POSITION");
      Expected<Elements> pos = elements(r, pos_index, where + " POSITION", {TINYGLTF_TYPE_VEC3});
      if (!pos) return pos.error();
      const std::size_t nv = pos->count;
      const std::size_t base = mesh.positions.size();
      if (nv > budget || base + nv > budget || base + nv > std::numeric_limits<uint32_t>::max()) {
        return parse_error(path, where +
                                     ": more vertices than texbake reads from a file of this "
                                     "size (instanced too often?)");
      }
      for (std::size_t i = 0; i < nv; ++i) {
        const double x = component(*pos, i, 0), y = component(*pos, i, 1),
                     z = component(*pos, i, 2);
        mesh.positions.push_back({static_cast<float>(w[0] * x + w[4] * y + w[8] * z + w[12]),
                                  static_cast<float>(w[1] * x + w[5] * y + w[9] * z + w[13]),
                                  static_cast<float>(w[2] * x + w[6] * y + w[10] * z + w[14])});
      }
      // Optional attributes: the same count as POSITION, finite values.
      auto optional = [&](const std::string& name,
                          std::initializer_list<int> types) -> Expected<Elements> {
        const int index = attr(name);
        if (index == -2) return Elements{};
        Expected<Elements> e = elements(r, index, where + " " + name, types);
        if (!e) return e.error();
        if (e->count != nv) {
          return parse_error(path, where + " " + name + " has " + std::to_string(e->count) +
                                       " elements but POSITION has " + std::to_string(nv));
        }
        for (std::size_t i = 0; i < nv; ++i) {
          for (int k = 0; k < e->components; ++k) {
            if (!std::isfinite(component(*e, i, k))) {
              return parse_error(
                  path, where + " " + name + " element " + std::to_string(i) + " is not finite");
            }
          }
        }
        return e;
      };
      Expected<Elements> tex = optional(uv_name, {TINYGLTF_TYPE_VEC2});
      if (!tex) return tex.error();
      Expected<Elements> nor = optional("NORMAL", {TINYGLTF_TYPE_VEC3});
      if (!nor) return nor.error();
      Expected<Elements> col = optional("COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4});
      if (!col) return col.error();
      any_uv = any_uv || tex->components;
      any_normal = any_normal || nor->components;
      any_color = any_color || col->components;
      for (std::size_t i = 0; i < nv; ++i) {
        // glTF's t runs down from the image's top-left corner; texbake's
        // (and OBJ's) v runs up from the bottom-left (SPEC section 1): v = 1 - t.
        uv.push_back(tex->components ? Float2{component(*tex, i, 0), 1.f - component(*tex, i, 1)}
                                     : Float2{0, 0});
        Float3 n{};  // missing: zero, which the users of normals replace (smooth normals)
        if (nor->components) {
          const double x = component(*nor, i, 0), y = component(*nor, i, 1),
                       z = component(*nor, i, 2);
          const double s = mirrored ? -1 : 1;
          double t[3];
          for (int k = 0; k < 3; ++k) t[k] = s * (cof[k][0] * x + cof[k][1] * y + cof[k][2] * z);
          const double len = std::sqrt(t[0] * t[0] + t[1] * t[1] + t[2] * t[2]);
          if (len > 0 && std::isfinite(len)) {
            n = {static_cast<float>(t[0] / len), static_cast<float>(t[1] / len),
                 static_cast<float>(t[2] / len)};
          }
        }
        nrm.push_back(n);
        // COLOR_0 is linear light; MeshData's colours are sRGB-encoded. A
        // primitive without COLOR_0 is white (glTF: no vertex colour factor).
        std::array<float, 4> c{1, 1, 1, 1};
        if (col->components) {
          for (int k = 0; k < 3; ++k) c[k] = linear_to_srgb(component(*col, i, k));
          if (col->components == 4) c[3] = component(*col, i, 3);
        }
        rgba.push_back(c);
      }
      // Triangles: the indices, or 0 .. nv-1 without them.
      Elements idx;
      std::size_t corners = nv;
      if (p.indices >= 0) {
        Expected<Elements> e = elements(r, p.indices, where + " indices", {TINYGLTF_TYPE_SCALAR});
        if (!e) return e.error();
        if (e->component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
            e->component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
            e->component_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) {
          return parse_error(path, where + " indices are not unsigned integers");
        }
        idx = *e;
        corners = idx.count;
      } else if (p.indices != -1) {
        return parse_error(path, where + " refers to accessor " + std::to_string(p.indices));
      }
      if (corners % 3 != 0) {
        return parse_error(path, where + " has " + std::to_string(corners) +
                                     " corners, not a multiple of 3 (TRIANGLES)");
      }
      if (corners > budget || mesh.face_vertices.size() + corners > budget) {
        return parse_error(path, where +
                                     ": more triangles than texbake reads from a file of "
                                     "this size (instanced too often?)");
      }
      for (std::size_t c = 0; c < corners; c += 3) {
        uint32_t t[3];
        for (int k = 0; k < 3; ++k) {
          const std::size_t at = c + k;
          const uint32_t v = p.indices >= 0 ? index_value(idx, at) : static_cast<uint32_t>(at);
          if (v >= nv) {
            return parse_error(path, where + " index " + std::to_string(at) + " is " +
                                         std::to_string(v) + " but the primitive has " +
                                         std::to_string(nv) + " vertices");
          }
          t[k] = static_cast<uint32_t>(base + v);
        }
        if (mirrored) std::swap(t[1], t[2]);
        mesh.face_vertices.insert(mesh.face_vertices.end(), t, t + 3);
        mesh.face_offsets.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
      }
    }
  }
  // Per-corner tables: one entry per glTF vertex (vertices are split where
  // their attributes differ), indexed like the positions.
  if (any_uv) {
    mesh.uvs = std::move(uv);
    mesh.corner_uv = mesh.face_vertices;
  }
  if (any_normal) {
    mesh.normals = std::move(nrm);
    mesh.corner_normal = mesh.face_vertices;
  }
  if (any_color) mesh.vertex_colors = std::move(rgba);
  if (!mesh.has_texture()) mesh.texture_is_srgb = false;
  return mesh;
}

}  // namespace

Expected<MeshData> read_gltf(const fs::path& path, std::string_view bytes,
                             std::size_t* other_material_primitives) {
  const bool binary = lower_extension(path) == ".glb";
  std::string_view json = bytes;
  if (binary) {
    Expected<std::string_view> j = check_glb(path, bytes);
    if (!j) return j.error();
    json = *j;
  }
  if (json.size() > std::numeric_limits<unsigned int>::max()) {
    return parse_error(path, "larger than the 4 GiB tinygltf reads");
  }
  if (Status s = check_json_depth(json, path.string()); !s) return s.error();

  FsContext fsc;
  fsc.folder = gltf_folder(path);
  {
    std::error_code ec;
    fsc.base_dir = fs::absolute(path, ec).parent_path().string();
    if (fsc.base_dir.empty()) fsc.base_dir = ".";
  }
  tinygltf::TinyGLTF loader;
  tinygltf::FsCallbacks callbacks{&fs_exists, &fs_expand, &fs_read, &fs_write, &fsc};
  loader.SetFsCallbacks(callbacks);
  loader.SetImageLoader(&keep_encoded, nullptr);
  tinygltf::Model model;
  std::string err, warn;
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn,
                                              reinterpret_cast<const unsigned char*>(bytes.data()),
                                              static_cast<unsigned int>(bytes.size()), fsc.base_dir)
                : loader.LoadASCIIFromString(&model, &err, &warn, json.data(),
                                             static_cast<unsigned int>(json.size()), fsc.base_dir);
  } catch (const std::bad_alloc&) {
    return make_error(ErrorCode::kIo, path.string() + ": not enough memory to read it");
  } catch (const std::exception& e) {
    err = e.what();
    ok = false;
  }
  if (!fsc.refused_uri.empty()) return refused_uri_error(path, fsc.refused_uri, fsc.refusal);
  if (!ok) {
    // tinygltf's messages for external buffers: "File not found : NAME",
    // "File read error : PATH : WHY" (from texbake's fs_read), "File size
    // mismatch : ..." (a .bin of another length than its byteLength).
    if (err.find("File not found") != std::string::npos ||
        err.find("File read error") != std::string::npos) {
      return make_error(ErrorCode::kIo, path.string() + ": a buffer it refers to cannot be read (" +
                                            first_line(err) + ")");
    }
    return parse_error(path, "not a valid glTF file: " + first_line(err));
  }
  if (model.asset.version.rfind("2.", 0) != 0) {
    return parse_error(path, "glTF version '" + model.asset.version + "'; texbake reads glTF 2.0");
  }
  // tinygltf 2.7 reports some malformed values in `err` and loads on
  // without them (a baseColorFactor of 3 numbers: the material keeps its
  // default white and loses its baseColorTexture; a texture reference
  // without "index"): the data was dropped, so the file is refused. (Its
  // warnings are about images that could not be read; the base colour
  // image is checked by read_material.)
  if (!err.empty()) return parse_error(path, "malformed value: " + first_line(err));
  return read_model(path, model, other_material_primitives);
}

}  // namespace texbake::read_detail
