// COLMAP sparse models (SPEC section 9, --cameras FOLDER): the cameras and
// registered images of `cameras.txt` + `images.txt` or `cameras.bin` +
// `images.bin` (COLMAP's own formats, doc/format.rst). Each image becomes
// one camera projector (mapping/camera.h) with its photo's file name. The
// sparse points of `points3D` are read apart (read_colmap_points), for the
// check that the model is in the mesh's frame.
//
// When a folder holds both forms, the binary one is read, as COLMAP does.
// Text: '#' starts a comment line; cameras.txt has `CAMERA_ID MODEL WIDTH
// HEIGHT PARAMS...`; images.txt has two lines per image, `IMAGE_ID QW QX QY
// QZ TX TY TZ CAMERA_ID NAME` and its 2D points (skipped). Binary (little
// endian): cameras.bin = u64 count, then per camera u32 id, i32 model id,
// u64 width, u64 height, doubles (the model's count); images.bin = u64
// count, then per image u32 id, 4 + 3 doubles (q, t), u32 camera id, the
// name up to a NUL, u64 point count, 24 bytes per point (skipped).
#pragma once

#include <cstdint>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "mapping/camera.h"
#include "mapping/error.h"
#include "mapping/vec.h"

namespace texbake {

class AtomicFileSet;

struct ColmapImage {
  uint32_t image_id = 0;
  uint32_t camera_id = 0;
  std::string name;        // the photo's path relative to the images folder, as stored
  CameraProjector camera;  // intrinsics of camera_id with this image's pose
};

// The registered images of the model in `folder`, in file order. Errors name
// the file and the line (text) or record (binary):
//   kIo: the folder or a file is missing or unreadable ("FOLDER: no COLMAP
//        model (cameras.txt + images.txt or cameras.bin + images.bin)");
//   kParse: a malformed line, an unknown model ("cameras.txt line 4: unknown
//        camera model FOO"), a wrong parameter count, a duplicate id, an
//        image naming an unknown camera id, a non-unit quaternion, a
//        truncated binary file ("images.bin: truncated in record 3"), trailing
//        bytes after the last binary record.
Expected<std::vector<ColmapImage>> read_colmap_model(const std::filesystem::path& folder);

// Writes `images` as a COLMAP model into `folder` (created if missing):
// cameras.txt + images.txt + points3D.txt (numbers with 17 significant
// digits, so they read back exactly; no 2D points; the 3D `points`, grey
// with error 0 and no track, or none) or, with `binary`, the three .bin
// files. Images with equal intrinsics share one camera id. The model's files
// and the removal of the other form's (cameras, images, points3D of .bin for
// text and of .txt for binary: a stale binary model would otherwise win over
// the new text one) are one atomic set: staged in `set` when given (the
// caller commits it, with its other files: a workspace's photos), else
// committed here. Errors: kIo (nothing is changed).
Status write_colmap_model(const std::filesystem::path& folder,
                          const std::vector<ColmapImage>& images, bool binary,
                          AtomicFileSet* set = nullptr, std::span<const Vec3> points = {});

// The model's sparse 3D points (X Y Z of points3D.txt, or points3D.bin when
// the model is binary; colours, errors and tracks are skipped), in file
// order; none when the file is absent (a model written without points).
// Errors: kIo (unreadable), kParse naming the file and the line or record (a
// malformed line, a point that is not finite, a truncated binary file,
// trailing bytes).
Expected<std::vector<Vec3>> read_colmap_points(const std::filesystem::path& folder);

}  // namespace texbake
