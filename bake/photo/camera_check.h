// `texbake cameras check` (SPEC section 9): how much of the mesh each camera
// sees, and the pose conventions that would explain a camera that sees
// little of it. Shares are of the vertices referenced by triangles.
//   in_front: Z > 0 in the camera's axes;
//   inside:   in front and inside the photo (and the distortion's valid radius);
//   masked:   inside, on pixels its mask file (Photo::mask, COLMAP's rule,
//             photo_bake.h "Masks") masks out: the mask's value bilinearly
//             interpolated at the vertex is 0 (0 for a photo without a mask
//             file; the check reads no photo, so the photos' own alpha is
//             not looked at);
//   visible:  inside, not masked and the segment to the camera's centre is free.
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
  double in_front = 0, inside = 0, masked = 0, visible = 0;  // shares in [0, 1]
  bool has_mask = false;                                     // Photo::mask was given (and read)
  std::vector<std::string> warnings;
};

// Mask files are read one at a time. Errors: kInternal (Embree); a mask
// file that cannot be read (read_mask's error) or whose size is neither the
// camera's nor of its aspect (kParse naming the file and both sizes).
// Results do not depend on the thread count.
Expected<std::vector<CameraCheck>> check_camera_poses(const MeshData& mesh,
                                                      const std::vector<Photo>& photos);

}  // namespace texbake
