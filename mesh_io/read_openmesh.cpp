// The OpenMesh adapter: OBJ, binary OFF and binary STL are parsed by
// OpenMesh 9.0's readers (after read_obj.cpp, read_off.cpp and read_stl.cpp
// have checked the file, see there), through a custom importer
// (ArrayImporter) that fills MeshData's plain arrays directly. OpenMesh's
// halfedge TriMesh/PolyMesh would refuse non-manifold faces ("complex edge")
// and so lose faces, which SPEC section 8 forbids; the importer builds no
// halfedges and keeps every face as the file has it.
#include <OpenMesh/Core/IO/IOManager.hh>
#include <OpenMesh/Core/IO/importer/BaseImporter.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <algorithm>
#include <limits>
#include <mutex>

#include "mesh_io/file_name.h"
#include "mesh_io/read_mesh_internal.h"

namespace texbake::read_detail {
namespace fs = std::filesystem;

namespace {

// Fills MeshData, never builds halfedges.
class ArrayImporter final : public OpenMesh::IO::BaseImporter {
 public:
  explicit ArrayImporter(NormalsAt normals) : normals_mode_(normals) { mesh_.face_offsets = {0}; }

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
    if (normals_mode_ == NormalsAt::kCorner) {
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
    if (normals_mode_ == NormalsAt::kCorner) {
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
    // zero_uv() adds a (0, 0) entry: only when some corner really lacks a UV.
    if (!mesh_.corner_uv.empty() && mesh_.corner_uv.size() < mesh_.face_vertices.size()) {
      mesh_.corner_uv.resize(mesh_.face_vertices.size(), zero_uv());
    }
    if (normals_mode_ == NormalsAt::kCorner) {
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
  NormalsAt normals_mode_;
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

bool read_into(const fs::path& path, ArrayImporter& importer) {
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

}  // namespace

Expected<OpenMeshRead> read_with_openmesh(const fs::path& path, NormalsAt normals) {
  ArrayImporter importer(normals);
  if (!read_into(path, importer)) {
    return parse_error(path, "OpenMesh cannot parse it as " + lower_extension(path).substr(1) +
                                 " (malformed file)");
  }
  importer.complete();
  OpenMeshRead out;
  out.mesh = std::move(importer.mesh());
  if (importer.bad_index()) out.negative_index_face = importer.bad_index()->first;
  out.textures = importer.textures();
  out.first_face_texindex = importer.first_face_texindex();
  return out;
}

Expected<MeshData> mesh_without_negative_index(const fs::path& path, OpenMeshRead&& read) {
  if (read.negative_index_face) {
    return parse_error(
        path, "face " + std::to_string(*read.negative_index_face) + " has a negative vertex index");
  }
  return std::move(read.mesh);
}

}  // namespace texbake::read_detail
