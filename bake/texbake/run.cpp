// Errors, the version, and what every call shares (bake/texbake/run.h).
#include "bake/texbake/run.h"

#include <cmath>
#include <cstdio>
#include <vector>

namespace texbake {

ErrorCategory category(const Error& error) {
  switch (error.code) {
    case ErrorCode::kInvalidArgument:
    case ErrorCode::kUnsupported:
      return ErrorCategory::kUsage;
    case ErrorCode::kParse:
    case ErrorCode::kIo:
      return ErrorCategory::kInput;
    case ErrorCode::kCancelled:
      return ErrorCategory::kCancelled;
    case ErrorCode::kInternal:
      break;
  }
  return ErrorCategory::kInternal;
}

const char* version() {
  return TEXBAKE_VERSION;
}

Expected<LoadedMesh> read_mesh(const std::filesystem::path& path, const RunOptions& run) {
  return detail::run_call<LoadedMesh>(run, [&] { return read_mesh(path); });
}

namespace {

// Triangles of the faces' triangulation before degenerate ones are removed
// (mesh_io/read_mesh.cpp triangulate_faces: n - 2 per polygon of n >= 3
// corners, fan or ear clipping alike; one per face of fewer corners).
std::size_t triangulated_count(const MeshData& mesh) {
  std::size_t count = 0;
  for (std::size_t f = 0; f < mesh.face_count(); ++f) {
    const std::size_t n = mesh.face_offsets[f + 1] - mesh.face_offsets[f];
    count += n < 3 ? 1 : n - 2;
  }
  return count;
}

}  // namespace

Status check_triangles(const MeshData& mesh) {
  if (!mesh.triangles.empty()) return ok_status();
  if (mesh.face_count() == 0) return make_error(ErrorCode::kParse, "the mesh has no faces");
  return make_error(ErrorCode::kParse, "all " + std::to_string(triangulated_count(mesh)) +
                                           " triangles are degenerate");
}

namespace detail {

Error as_input(Error error) {
  if (category(error) == ErrorCategory::kUsage) error.code = ErrorCode::kParse;
  return error;
}

Status check_mapped(std::size_t undefined, std::size_t total, const std::string& what,
                    std::vector<std::string>& warnings) {
  if (total > 0 && undefined == total) {
    return make_error(ErrorCode::kParse,
                      "the proxy maps none of the mesh's " + std::to_string(total) + " " + what +
                          " (no (u, v) for any of them: is the proxy's geometry far off the "
                          "mesh's scale?)");
  }
  if (total > 0 && static_cast<double>(undefined) > kUndefinedWarnShare * total) {
    char share[32];
    std::snprintf(share, sizeof share, "%.1f", 100.0 * undefined / total);
    warnings.push_back(std::to_string(undefined) + " of " + std::to_string(total) + " " + what +
                       " (" + share +
                       " %) have no mapping through the proxy; they are "
                       "treated as occluded");
  }
  return ok_status();
}

Counts mesh_counts(const MeshData& mesh) {
  Counts c;
  c.vertices = mesh.vertex_count();
  c.triangles = mesh.triangles.size();
  const std::size_t all = triangulated_count(mesh);
  c.degenerate_triangles = all > c.triangles ? all - c.triangles : 0;
  // Referenced: by a face (read_mesh's rule); a mesh built in memory with
  // triangles only counts those.
  std::vector<char> used(c.vertices, 0);
  auto use = [&](uint32_t v) {
    if (v < used.size()) used[v] = 1;
  };
  if (mesh.face_count() > 0) {
    for (uint32_t v : mesh.face_vertices) use(v);
  } else {
    for (const auto& t : mesh.triangles) {
      for (uint32_t v : t) use(v);
    }
  }
  for (char u : used) c.unreferenced_vertices += u == 0;
  return c;
}

Status check_image(const ImageView& image) {
  if (image.width < 1 || image.height < 1 || !image.has_texels()) {
    return make_error(ErrorCode::kInvalidArgument, "the image has no pixels");
  }
  return ok_status();
}

Status check_shading_colors(const VertexBakeOptions& options) {
  auto check = [](const Rgba& c, std::string_view flag) -> Status {
    const double d[4] = {c[0], c[1], c[2], c[3]};
    Expected<Rgba> checked = color_from_components(d, flag);
    if (!checked) return checked.error();
    return ok_status();
  };
  if (options.occluded == OccludedMode::kColor) {
    if (Status s = check(options.occluded_color, "--occluded"); !s) return s;
  }
  if (options.outside == OutsideMode::kColor) return check(options.outside_color, "--outside");
  return ok_status();
}

}  // namespace detail
}  // namespace texbake
