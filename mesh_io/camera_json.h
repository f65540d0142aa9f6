// Camera projectors as JSON (SPEC section 9), e.g.
//   {"kind":"camera","model":"OPENCV","width":4000,"height":3000,
//    "params":[fx,fy,cx,cy,k1,k2,p1,p2],
//    "pose":{"q_wxyz":[qw,qx,qy,qz],"t":[tx,ty,tz]}}
// "model" is one of COLMAP's seven names and "params" its parameters in
// COLMAP's order (mapping/camera.h). "pose" is exactly one of
//   {"q_wxyz":[4], "t":[3]}        world-to-camera (COLMAP's images.txt)
//   {"R":[[3]x3], "t":[3]}          world-to-camera, R row by row
//   {"center":[3], "R":[[3]x3]}     the camera centre and world-to-camera R
//   {"cam_to_world":[[4]x4]}        camera-to-world, row by row
//   {"eye":[3], "target":[3], "up":[3]}
// each with an optional "axes": "opencv" (default: x right, y down, z
// forward) or "opengl" (y up, looking down -z; Blender, nerfstudio).
//
// A camera list, the JSON form of `--cameras`:
//   {"cameras":[{camera..., "image":"IMG_1.jpg"}, ...]}
//
// Errors are kParse (kIo when the file cannot be read) and start with the
// file (or `source`), the camera's place in the list and the key: unknown or
// missing keys, wrong types, non-finite numbers, an unknown model, a wrong
// parameter count, a non-orthonormal rotation, two pose forms at once.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "mapping/camera.h"
#include "mapping/error.h"

namespace texbake {

Expected<CameraProjector> camera_from_json(std::string_view text,
                                           const std::string& source = "camera JSON");

struct CameraListEntry {
  CameraProjector camera;
  std::string image;  // as written (relative to the list's folder unless absolute)
};
Expected<std::vector<CameraListEntry>> read_camera_list(const std::filesystem::path& path);
// The same from text (errors start with `source`).
Expected<std::vector<CameraListEntry>> camera_list_from_json(std::string_view text,
                                                             const std::string& source);

}  // namespace texbake
