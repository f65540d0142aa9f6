// Agisoft Metashape (and PhotoScan) `cameras.xml`, File > Export Cameras
// (SPEC section 9, "Formats"). The camera model is Agisoft's (Metashape
// manual, appendix C "Camera models"), with X = (X, Y, Z) in the camera's
// axes (OpenCV's: x right, y down, z forward):
//   frame:   x = X/Z, y = Y/Z, r^2 = x^2 + y^2
//   fisheye: x0 = X/Z, y0 = Y/Z, r0 = |(x0, y0)|, (x, y) = (x0, y0) atan(r0) / r0
//   x' = x (1 + k1 r^2 + k2 r^4 + k3 r^6 + k4 r^8) + p1 (r^2 + 2x^2) + 2 p2 x y
//   y' = y (1 + k1 r^2 + k2 r^4 + k3 r^6 + k4 r^8) + p2 (r^2 + 2y^2) + 2 p1 x y
//   u = w/2 + cx + x' (f + b1) + y' b2,  v = h/2 + cy + y' f
// with (u, v) in pixels, the centre of the top-left pixel at (0.5, 0.5) (as
// COLMAP). So, exactly, in COLMAP's terms: fx = f + b1, fy = f, principal
// point (w/2 + cx, h/2 + cy), OpenCV's p1 = Metashape's p2 and OpenCV's p2
// = Metashape's p1 (their roles are swapped); a frame camera becomes
// PINHOLE, OPENCV (k3 = 0) or FULL_OPENCV (k4..k6 = 0), a fisheye camera
// OPENCV_FISHEYE (its k1..k4 are OpenCV's on theta). A term no COLMAP model
// holds is an error naming it: b2 (skew), a frame camera's k4 (r^8), a
// fisheye's p1 p2, p3 p4, other sensor types (spherical, cylindrical, rpc).
//
// Poses: a camera's `<transform>` (16 numbers, row by row) is camera-to-
// chunk. The chunk's coordinates are brought to its world (the frame the
// model is exported in: local coordinates, or geocentric ones for a
// georeferenced chunk) by the `<transform>` of the camera's component
// (Metashape 2) or, when it has none, of the chunk (PhotoScan, Metashape 1):
// `X_world = s R X_chunk + t` (`<rotation>` 9 numbers row by row,
// `<translation>`, `<scale>`). Cameras without a transform (not aligned) are
// left out, with a note. The photo's name is the camera's `label`.
#pragma once

#include <string>
#include <string_view>

#include "mapping/error.h"
#include "mesh_io/camera_formats.h"

namespace texbake {

// Errors (kParse) start with `source`, the line, the camera or sensor and
// the element: "cameras.xml line 12: sensor 0: b2 is 0.5: ...".
Expected<CameraFile> metashape_from_xml(std::string_view text, const std::string& source);

}  // namespace texbake
