// libFuzzer target for the camera list reader (mesh_io/camera_json.h, the
// JSON form of --cameras): any text is either a list of cameras, each with
// its image, or an error starting with the source; nothing else (the
// sanitizers watch).
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "mesh_io/camera_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const auto list = texbake::camera_list_from_json(text, "fuzz.json");
  if (!list && list.error().message.rfind("fuzz.json", 0) != 0) std::abort();
  if (list) {
    if (list->empty()) std::abort();
    for (const texbake::CameraListEntry& e : *list) {
      if (e.image.empty()) std::abort();
    }
  }
  return 0;
}
