// libFuzzer target for the mesh readers (SPEC section 8): the input is
// written to a temporary file with the extension TEXBAKE_FUZZ_EXT (".obj",
// ".ply", ".off", ".stl", ".glb" or ".gltf"; one executable per format, see
// CMakeLists.txt; a .gltf's external buffers and images are looked for
// beside the temporary file, so the seeds use data: URIs)
// and read with read_mesh, the same entry point the CLI uses. read_mesh works
// on paths (OpenMesh's readers open files themselves), hence the file.
//
// Besides the sanitizers, it checks read_mesh's contract on success: face
// indices in range, finite positions, triangles referring to real corners.
#include <unistd.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "mesh_io/read_mesh.h"

#ifndef TEXBAKE_FUZZ_EXT
#error "define TEXBAKE_FUZZ_EXT"
#endif

namespace {

std::filesystem::path temp_path() {
  // /dev/shm keeps the per-input write in memory where it exists.
  const std::filesystem::path dir =
      std::filesystem::exists("/dev/shm") ? "/dev/shm" : std::filesystem::temp_directory_path();
  return dir / ("texbake_fuzz_" + std::to_string(::getpid()) + TEXBAKE_FUZZ_EXT);
}

void check(bool ok, const char* what) {
  if (!ok) {
    std::fprintf(stderr, "read_mesh contract violated: %s\n", what);
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path path = temp_path();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);

  texbake::Expected<texbake::LoadedMesh> m = texbake::read_mesh(path);
  if (m) {
    const texbake::MeshData& mesh = m->mesh;
    const std::size_t nv = mesh.vertex_count();
    check(mesh.face_count() > 0, "no faces");
    for (uint32_t v : mesh.face_vertices) check(v < nv, "face index out of range");
    for (const auto& p : mesh.positions)
      check(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z), "non-finite position");
    for (const auto& t : mesh.triangles)
      check(t[0] < nv && t[1] < nv && t[2] < nv, "triangle index out of range");
    check(mesh.triangle_corners.size() == mesh.triangles.size(), "corner table size");
    for (const auto& t : mesh.triangle_corners)
      check(t[0] < mesh.face_vertices.size() && t[1] < mesh.face_vertices.size() &&
                t[2] < mesh.face_vertices.size(),
            "triangle corner out of range");
    check(mesh.corner_uv.empty() || mesh.corner_uv.size() == mesh.face_vertices.size(),
          "corner_uv size");
    for (uint32_t i : mesh.corner_uv) check(i < mesh.uvs.size(), "uv index out of range");
    check(mesh.corner_normal.empty() || mesh.corner_normal.size() == mesh.face_vertices.size(),
          "corner_normal size");
    for (uint32_t i : mesh.corner_normal)
      check(i < mesh.normals.size(), "normal index out of range");
    check(mesh.vertex_colors.empty() || mesh.vertex_colors.size() == nv, "vertex_colors size");
    check(mesh.texture_path.empty() || mesh.texture_bytes.empty(), "two textures");
  } else {
    check(!m.error().message.empty(), "empty error message");
  }
  return 0;
}
