// STL (ASCII "solid ... endsolid" and binary: an 80-byte header, a
// little-endian triangle count, 50 bytes per triangle). OpenMesh 9.0's STL
// reader parses it (read_openmesh.cpp); it merges corners at equal positions
// into one vertex and drops triangles that then repeat a vertex. check_stl
// first makes sure a binary file holds the triangles its header declares,
// because OpenMesh reads past the end of a short one.
#include <bit>
#include <cstring>

#include "mesh_io/byte_order.h"
#include "mesh_io/read_mesh_internal.h"

namespace texbake::read_detail {
namespace fs = std::filesystem;

namespace {

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

}  // namespace

Expected<MeshData> read_stl(const fs::path& path, std::string_view bytes) {
  if (Status s = check_stl(path, bytes); !s) return s.error();
  Expected<OpenMeshRead> read = read_with_openmesh(path, NormalsAt::kVertex);
  if (!read) return read.error();
  return mesh_without_negative_index(path, std::move(*read));
}

}  // namespace texbake::read_detail
