// The camera files `--cameras` takes besides a COLMAP model folder (SPEC
// section 9, "Formats"), told apart by their content, not their name:
//   texbake's JSON camera list   {"cameras": [...]}   (mesh_io/camera_json.h)
//   nerfstudio / instant-ngp     {"frames": [...]}     (mesh_io/nerfstudio_json.h)
//   Agisoft Metashape XML        <document><chunk>...  (mesh_io/metashape_xml.h)
//   Meshroom / AliceVision .sfm  {"views": [...], "intrinsics" or "poses"}
//                                                      (mesh_io/meshroom_sfm.h)
// Each is read into texbake's one camera form (mapping/camera.h: COLMAP's
// models, OpenCV axes, world-to-camera) with the photo's name as the file
// gives it.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "mapping/error.h"
#include "mesh_io/camera_json.h"

namespace texbake {

enum class CameraFormat { kCameraList, kNerfstudio, kMetashape, kMeshroom };

// "texbake camera list", "nerfstudio transforms.json", "Metashape cameras.xml",
// "Meshroom .sfm".
std::string_view camera_format_name(CameraFormat format);

struct CameraFile {
  CameraFormat format = CameraFormat::kCameraList;
  // In file order; each image as written (relative to the file's folder
  // unless absolute).
  std::vector<CameraListEntry> cameras;
  // What the reader did that the user must know, one sentence each, e.g.
  // that a nerfstudio file's applied_transform was undone.
  std::vector<std::string> notes;
};

// Reads `path`, a camera file of any format above. Errors (kParse; kIo when
// the file cannot be read) start with the path: a JSON object that is none
// of the formats ("not a camera file texbake reads: ..."), and each
// format's own.
Expected<CameraFile> read_camera_file(const std::filesystem::path& path);

// The same from text; errors start with `source`.
Expected<CameraFile> camera_file_from_text(std::string_view text, const std::string& source);

// The photo a camera file names `image`, with `folder` the photos' folder:
// `image` when absolute, else folder / image; for a Metashape label without
// an extension (Metashape's usual labels) that is not a file, the first of
// that path plus .jpg, .JPG, .jpeg, .JPEG, .png, .PNG, .tif, .TIF, .tiff,
// .TIFF that is a file (else the path unchanged).
std::filesystem::path camera_photo_path(CameraFormat format, const std::string& image,
                                        const std::filesystem::path& folder);

}  // namespace texbake
