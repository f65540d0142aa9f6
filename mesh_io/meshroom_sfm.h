// Meshroom / AliceVision SfMData as JSON: `cameras.sfm` (StructureFromMotion's
// "Views and Poses"), any `.sfm` or `.json` SfMData (SPEC section 9,
// "Formats"). The conventions, as AliceVision's own source (repository
// alicevision/AliceVision, read at ca8300f, October 2024) applies them:
//
// - Values: boost::property_tree writes every value as a JSON string
//   ("width": "4000", "rotation": ["0.99", ...]); numbers and strings holding
//   a number are both read. `version` [major, minor, revision] is required
//   (sfmDataIO/jsonIO.cpp loadJSON); a version newer than 1.2.11 (the
//   library's ALICEVISION_SFMDATAIO_VERSION_*, sfmDataIO/sfmDataIO.hpp) is
//   refused, as AliceVision refuses it.
// - Intrinsics (jsonIO.cpp loadIntrinsic): `intrinsicId`, `width`,
//   `height`, `sensorWidth` (mm, default 36). The camera type: from version
//   1.2.8 `type` (pinhole, equidistant) with `distortionType` (none,
//   radialk1, radialk3, radialk3pt, brown, fisheye, fisheye1) and
//   `undistortionType` (none, radialk3, 3deanamorphic4, ...); before, `type`
//   alone (pinhole, radial1, radial3, brown, fisheye4, fisheye1,
//   3deanamorphic4, equidistant, equidistant_r3; camera/cameraCommon.hpp
//   compatibilityStringToEnums), case-insensitive.
// - Focal length in pixels (jsonIO.cpp, IntrinsicScaleOffset.cpp
//   setFocalLength), with fmm = `focalLength`, p = `pixelRatio` (default 1)
//   and mm -> px = width / sensorWidth:
//     version < 1.2.0:  fx = fy = `pxFocalLength` (one number)
//     1.2.0, 1.2.1:     `pxFocalLength` [fx, fy]
//     1.2.2 .. 1.2.4:   fx = fmm width / sensorWidth, fy = fx / p
//     1.2.5 .. 1.2.10:  fx = fmm width / sensorWidth, fy = fx p
//     1.2.11:           fx = fmm / p width / sensorWidth, fy = fmm width / sensorWidth
// - Principal point: `principalPoint` [x, y] is an offset from the image
//   centre (w/2, h/2) from version 1.2.1, absolute before
//   (IntrinsicScaleOffset.hpp getPrincipalPoint = offset + (w/2, h/2)).
// - Projection (camera/Pinhole.cpp project, IntrinsicScaleOffset.cpp
//   cam2ima): X_cam = R (X - C), (a, b) = (X/Z, Y/Z) distorted, then
//   (fx a' + ppx, fy b' + ppy); OpenCV axes (x right, y down, z forward).
// - Pixels: AliceVision puts the centre of the top-left pixel at (0, 0):
//   image/Sampler.hpp Sampler2d and image/Image.hpp getInterpolateColor
//   (used by camera/cameraUndistortImage.hpp and mesh/Texturing.cpp) read
//   pixel (i, j) at exactly (i, j), and mvsUtils/MultiViewParams.cpp rounds
//   a projection to floor(x + 0.5). So COLMAP's cx, cy = w/2 + offset + 0.5,
//   h/2 + offset + 0.5. (sfmDataIO/colmap.cpp, AliceVision's COLMAP export,
//   copies the principal point without the half pixel; the code that uses
//   the photos decides here.)
// - Distortion (`distortionParams`, on (a, b); camera/Distortion*.cpp
//   addDistortion): radialk1 [k1]: (a, b)(1 + k1 r^2) -> OPENCV (k2 p1 p2 =
//   0); radialk3 [k1 k2 k3]: (a, b)(1 + k1 r^2 + k2 r^4 + k3 r^6) -> OPENCV
//   when k3 = 0, else FULL_OPENCV (p, k4..k6 = 0); brown [k1 k2 k3 t1 t2]:
//   a' = a radial + t2 (r^2 + 2a^2) + 2 t1 a b, b' = b radial + t1 (r^2 +
//   2b^2) + 2 t2 a b, so t1 t2 are OpenCV's p1 p2 in that order -> OPENCV /
//   FULL_OPENCV; fisheye [k1..k4]: theta_d = theta + k1 theta^3 + ... + k4
//   theta^9, a' = a theta_d / r -> OPENCV_FISHEYE. No distortion -> PINHOLE.
//   radialk3pt, fisheye1, an undistortion other than none, and the
//   equidistant camera have no COLMAP model: refused, naming the intrinsic
//   and the key. distortionParams must hold the model's count.
// - Poses (jsonIO.hpp loadCameraPose, geometry/Pose3.hpp): `poses` [{poseId,
//   pose: {transform: {rotation, center}}}]; Pose3(c_R_w, w_c): rotation is
//   world-to-camera, center the camera centre in the world. saveMatrix
//   writes matrix(i) of an Eigen Mat3, column-major by default
//   (numeric/numeric.hpp): the 9 numbers are R column by column (read row
//   by row they are the camera-to-world rotation).
// - Views (jsonIO.cpp loadView): `viewId`, `poseId`, `intrinsicId`, `path`
//   (usually absolute; else relative to the file's folder). A view whose
//   poseId has no pose is not reconstructed and left out, with a note; a
//   view in a rig (`rigId`) is refused (its pose is the rig's composed with
//   a sub-pose). Other keys (featuresFolders, matchesFolders, structure,
//   metadata, locked, initialFocalLength, ...) are ignored.
#pragma once

#include <string>
#include <string_view>

#include "mapping/error.h"
#include "mesh_io/camera_formats.h"

namespace texbake {

// Errors (kParse) start with `source`, then the view or intrinsic and the
// key: "cameras.sfm: intrinsic 7: distortionType 'fisheye1': ...".
Expected<CameraFile> meshroom_from_json(std::string_view text, const std::string& source);

}  // namespace texbake
