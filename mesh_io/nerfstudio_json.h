// nerfstudio / instant-ngp `transforms.json` (SPEC section 9, "Formats";
// the conventions as their sources apply them: nerfstudio's
// data/dataparsers/nerfstudio_dataparser.py, process_data/colmap_utils.py,
// cameras/camera_utils.py; instant-ngp's src/nerf_loader.cu,
// scripts/colmap2nerf.py):
//   {"camera_model": "OPENCV", "w": 4000, "h": 3000, "fl_x": ..., "fl_y": ...,
//    "cx": ..., "cy": ..., "k1": ..., "k2": ..., "p1": ..., "p2": ...,
//    "applied_transform": [[3x4]], "applied_scale": s,
//    "frames": [{"file_path": "images/a.png", "transform_matrix": [[4x4]]}, ...]}
// - transform_matrix: camera-to-world, row by row, OpenGL camera axes (x
//   right, y up, looking down -z).
// - Intrinsics in pixels, at the top level (shared) or in a frame; a key in
//   both must hold the same value (nerfstudio takes the top level's,
//   instant-ngp the frame's). The principal point `cx, cy` is in COLMAP's
//   pixel convention (nerfstudio casts rays through pixel + 0.5; its COLMAP
//   import copies cx, cy unchanged); without it, the image centre (as
//   instant-ngp). `fl_y` defaults to `fl_x`; `camera_angle_x` (radians) or
//   `x_fov` (degrees) may stand for `fl_x` (and agree with it when both are
//   given). `w`, `h` are required.
// - Lens: camera_model SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL,
//   OPENCV (nerfstudio's one perspective model: radial 1 + k1 r^2 + k2 r^4
//   + k3 r^6 + k4 r^8, tangential p1 p2 as OpenCV) or OPENCV_FISHEYE (k1..k4,
//   as COLMAP's); none: OPENCV, or OPENCV_FISHEYE with instant-ngp's
//   "is_fisheye": true. Mapped exactly onto COLMAP's models: no distortion
//   PINHOLE, k3 = 0 OPENCV, else FULL_OPENCV with k4..k6 = 0; a non-zero
//   perspective k4 (r^8: no COLMAP model has it), fisheye p1 or p2, or
//   another camera_model is an error naming the key.
// - applied_transform (3x4 [A | a]) and applied_scale s record how the
//   poses were re-framed from the data they came from (ns-process-data:
//   X_file = s (A X_original + a)). They are undone, as nerfstudio's own
//   transform_poses_to_original_space does, so the cameras are in the frame
//   of the original reconstruction (and of a mesh made from it); the
//   CameraFile's notes say so.
// - file_path: the photo, relative to the file's folder unless absolute.
// Keys that do not describe a camera are ignored; lens keys texbake cannot
// map (k5, k6, ftheta_p0..4, latlong, equirectangular, orthographic, a
// non-zero rolling_shutter, transform_matrix_start/_end) are errors.
#pragma once

#include <string>
#include <string_view>

#include "mapping/error.h"
#include "mesh_io/camera_formats.h"

namespace texbake {

// Errors (kParse) start with `source`, the frame ("frames[3]") and the key.
Expected<CameraFile> nerfstudio_from_json(std::string_view text, const std::string& source);

}  // namespace texbake
