// `texbake cameras check` (SPEC section 9): how much of the mesh each camera
// sees, and the pose conventions that would explain a camera that sees
// little of it. Shares are of the vertices referenced by triangles.
//   in_front: Z > 0 in the camera's axes;
//   inside:   in front and inside the photo (and the distortion's valid radius);
//   visible:  inside and the segment to the camera's centre is free.
// Warnings, when less than half of the mesh is inside the photo:
//   "camera-to-world given as world-to-camera?" when the inverse pose puts
//     more than half of the mesh (and twice as much) inside the photo;
//   "OpenGL axes? (y and z flipped)" when the pose with its camera y and z
//     negated does;
//   else "most of the mesh is behind the camera" when at most half is in
//     front, or "the mesh is outside the photo" when none of it is inside.
#pragma once

#include <string>
#include <vector>

#include "bake/photo/photo_bake.h"

namespace texbake {

struct CameraCheck {
  std::string name;
  double in_front = 0, inside = 0, visible = 0;  // shares in [0, 1]
  std::vector<std::string> warnings;
};

// Errors: kInternal (Embree). Results do not depend on the thread count.
Expected<std::vector<CameraCheck>> check_camera_poses(const MeshData& mesh,
                                                      const std::vector<Photo>& photos);

}  // namespace texbake
