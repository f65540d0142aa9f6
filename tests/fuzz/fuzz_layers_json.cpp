// libFuzzer target for the layers file and the projector (proxy or camera)
// readers (mesh_io/layers_json.h, mesh_io/proxy_json.h): any text is either
// parsed or an error naming its source; nothing else (the sanitizers watch).
// Relative paths resolve under a folder that does not exist, so no file is
// read but what an absolute path names (refused unless a regular file).
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "mesh_io/layers_json.h"
#include "mesh_io/proxy_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const texbake::Expected<texbake::LayersSpec> layers =
      texbake::layers_from_json(text, "/nonexistent-texbake-fuzz", "fuzz.json");
  if (!layers && layers.error().message.rfind("fuzz.json", 0) != 0 &&
      layers.error().message.find("/nonexistent-texbake-fuzz") == std::string::npos &&
      layers.error().message.find('/') == std::string::npos) {
    std::abort();  // an error that names no source
  }
  if (layers) {
    for (const texbake::LayerSpec& l : layers->layers) {
      if (!l.projector && l.cameras.empty()) std::abort();  // a layer without a projector
      if (!(l.opacity >= 0 && l.opacity <= 1)) std::abort();
    }
  }
  (void)texbake::projector_from_json(text, "fuzz.json");
  return 0;
}
