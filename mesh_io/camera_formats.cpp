#include "mesh_io/camera_formats.h"

#include "mesh_io/json_strict.h"
#include "mesh_io/meshroom_sfm.h"
#include "mesh_io/metashape_xml.h"
#include "mesh_io/nerfstudio_json.h"
#include "mesh_io/regular_file.h"

namespace texbake {

std::string_view camera_format_name(CameraFormat format) {
  switch (format) {
    case CameraFormat::kCameraList:
      return "texbake camera list";
    case CameraFormat::kNerfstudio:
      return "nerfstudio transforms.json";
    case CameraFormat::kMetashape:
      return "Metashape cameras.xml";
    case CameraFormat::kMeshroom:
      return "Meshroom .sfm";
  }
  return "camera file";
}

Expected<CameraFile> camera_file_from_text(std::string_view text, const std::string& source) {
  // XML (after blanks and a UTF-8 byte order mark): Metashape's.
  std::size_t first = text.rfind("\xEF\xBB\xBF", 0) == 0 ? 3 : 0;
  first = text.find_first_not_of(" \t\r\n", first);
  if (first != std::string_view::npos && text[first] == '<')
    return metashape_from_xml(text, source);
  // JSON: the format is told by the top-level keys; the reader of that
  // format then checks everything (and parses again: camera files are small).
  Expected<nlohmann::json> root = parse_json_object(text, source);
  if (!root) return root.error();
  if (root->contains("frames")) return nerfstudio_from_json(text, source);
  if (root->contains("cameras")) {
    Expected<std::vector<CameraListEntry>> list = camera_list_from_json(text, source);
    if (!list) return list.error();
    return CameraFile{CameraFormat::kCameraList, std::move(list).value(), {}};
  }
  if (root->contains("views") && (root->contains("intrinsics") || root->contains("poses"))) {
    return meshroom_from_json(text, source);
  }
  return make_error(
      ErrorCode::kParse,
      source +
          ": not a camera file texbake reads: a texbake camera list has the key "
          "'cameras', a nerfstudio / instant-ngp transforms.json 'frames', a Meshroom .sfm "
          "'views' with 'intrinsics' and 'poses'; a Metashape cameras.xml is XML (a COLMAP model "
          "is given as its folder)");
}

std::filesystem::path camera_photo_path(CameraFormat format, const std::string& image,
                                        const std::filesystem::path& folder) {
  namespace fs = std::filesystem;
  const fs::path path = fs::path(image).is_absolute() ? fs::path(image) : folder / image;
  std::error_code ec;
  if (format != CameraFormat::kMetashape || path.has_extension() || fs::exists(path, ec)) {
    return path;
  }
  for (const char* ext :
       {".jpg", ".JPG", ".jpeg", ".JPEG", ".png", ".PNG", ".tif", ".TIF", ".tiff", ".TIFF"}) {
    fs::path p = path;
    p += ext;
    if (fs::is_regular_file(p, ec)) return p;
  }
  return path;
}

Expected<CameraFile> read_camera_file(const std::filesystem::path& path) {
  const std::string name = path.filename().string();
  if (name == "cameras.txt" || name == "images.txt" || name == "cameras.bin" ||
      name == "images.bin") {
    return make_error(ErrorCode::kParse,
                      path.string() + ": a file of a COLMAP model: give the model's folder");
  }
  Expected<std::string> text = read_text_file(path, "a camera file");
  if (!text) return text.error();
  return camera_file_from_text(*text, path.string());
}

}  // namespace texbake
