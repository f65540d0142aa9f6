#include "bake/photo/camera_check.h"

#include <algorithm>
#include <optional>

#include "bake/photo/photo_view.h"
#include "bake/photo/segments.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"

namespace texbake {

namespace {

constexpr std::size_t kGrain = 4096;

std::vector<uint32_t> referenced_vertices(const MeshData& mesh) {
  std::vector<uint8_t> used(mesh.positions.size(), 0);
  for (const auto& t : mesh.triangles) used[t[0]] = used[t[1]] = used[t[2]] = 1;
  std::vector<uint32_t> out;
  for (std::size_t v = 0; v < used.size(); ++v) {
    if (used[v]) out.push_back(static_cast<uint32_t>(v));
  }
  return out;
}

// The share of `vertices` inside the photo of `camera`.
double inside_share(const CameraProjector& camera, const MeshData& mesh,
                    const std::vector<uint32_t>& vertices) {
  std::size_t inside = 0;
  for (uint32_t v : vertices) {
    const Float3 p = mesh.positions[v];
    inside += camera.project({p.x, p.y, p.z}).inside;
  }
  return static_cast<double>(inside) / static_cast<double>(vertices.size());
}

// The camera with another pose, or nullopt if it cannot be built.
std::optional<CameraProjector> with_pose(const CameraProjector& camera, const CameraPose& pose) {
  CameraSpec spec = camera.spec();
  spec.pose = pose;
  Expected<CameraProjector> c = CameraProjector::make(std::move(spec));
  if (!c) return std::nullopt;
  return std::move(c).value();
}

}  // namespace

Expected<std::vector<CameraCheck>> check_camera_poses(const MeshData& mesh,
                                                      const std::vector<Photo>& photos) {
  const std::vector<uint32_t> vertices = referenced_vertices(mesh);
  std::vector<CameraCheck> out;
  if (vertices.empty()) return out;
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kLow);
  if (!scene) return scene.error();
  const double offset = visibility_offset(*scene);
  const double n = static_cast<double>(vertices.size());
  for (const Photo& photo : photos) {
    const CameraProjector& camera = photo.camera;
    CameraCheck check;
    check.name = photo.name;
    std::optional<Image> mask;
    if (!photo.mask.empty()) {
      Expected<Image> read = photo_detail::read_mask(photo);
      if (!read) return read.error();
      PhotoImage size{read->width, read->height, {}};
      bool scaled = false;
      if (Status s = photo_detail::check_mask_size(photo, size, scaled); !s) return s.error();
      mask = std::move(read).value();
      check.has_mask = true;
    }
    const ImageView mask_view = mask ? mask->view() : ImageView{};
    // in front, inside, masked, visible
    std::vector<std::array<std::size_t, 4>> counts(block_count(vertices.size(), kGrain),
                                                   {0, 0, 0, 0});
    parallel_for_blocks(
        vertices.size(), kGrain, [&](std::size_t block, std::size_t begin, std::size_t end) {
          std::array<std::size_t, 4>& c = counts[block];
          std::vector<uint32_t> inside;
          for (std::size_t i = begin; i < end; ++i) {
            const Float3 p = mesh.positions[vertices[i]];
            const CameraProjection proj = camera.project({p.x, p.y, p.z});
            c[0] += proj.depth > 0;
            if (!proj.inside) continue;
            ++c[1];
            if (mask && !(photo_detail::mask_at(mask_view, true, proj.uv) > 0)) {
              ++c[2];
              continue;
            }
            inside.push_back(vertices[i]);
          }
          SegmentScratch scratch;
          std::vector<uint8_t> occluded(inside.size(), 0);
          occluded_segments(*scene, offset, mesh, inside, camera.centre(), scratch,
                            occluded.data());
          c[3] = static_cast<std::size_t>(std::count(occluded.begin(), occluded.end(), 0));
        });
    std::array<std::size_t, 4> total{0, 0, 0, 0};
    for (const auto& c : counts) {
      for (int k = 0; k < 4; ++k) total[k] += c[k];
    }
    mask.reset();
    check.in_front = total[0] / n;
    check.inside = total[1] / n;
    check.masked = total[2] / n;
    check.visible = total[3] / n;
    if (check.inside < 0.5) {
      const CameraPose& pose = camera.spec().pose;
      // The inverse transform: X = R^T X_cam - R^T t read as world-to-camera.
      CameraPose inverse;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) inverse.r[3 * i + j] = pose.r[3 * j + i];
      }
      inverse.t = camera.centre();
      CameraPose flipped = pose;
      for (int k = 3; k < 9; ++k) flipped.r[k] = -flipped.r[k];
      flipped.t = {pose.t.x, -pose.t.y, -pose.t.z};
      const std::optional<CameraProjector> inv = with_pose(camera, inverse);
      const std::optional<CameraProjector> flip = with_pose(camera, flipped);
      const double inv_inside = inv ? inside_share(*inv, mesh, vertices) : 0;
      const double flip_inside = flip ? inside_share(*flip, mesh, vertices) : 0;
      if (inv_inside > 0.5 && inv_inside > 2 * check.inside) {
        check.warnings.push_back("camera-to-world given as world-to-camera?");
      } else if (flip_inside > 0.5 && flip_inside > 2 * check.inside) {
        check.warnings.push_back("OpenGL axes? (y and z flipped)");
      } else if (check.in_front <= 0.5) {
        check.warnings.push_back("most of the mesh is behind the camera");
      } else if (check.inside == 0) {
        check.warnings.push_back("the mesh is outside the photo");
      }
    }
    out.push_back(std::move(check));
  }
  return out;
}

}  // namespace texbake
