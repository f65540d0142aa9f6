// What projects an image onto a mesh: one of the six analytic proxies
// (mapping/proxy.h) or a calibrated camera (mapping/camera.h). A proxy file
// (`--proxy-file`) holds either; {"kind":"camera", ...} is a camera.
#pragma once

#include <variant>

#include "mapping/camera.h"
#include "mapping/proxy.h"

namespace texbake {

using Projector = std::variant<Proxy, CameraProjector>;

inline const CameraProjector* as_camera(const Projector& p) {
  return std::get_if<CameraProjector>(&p);
}
inline const Proxy* as_proxy(const Projector& p) {
  return std::get_if<Proxy>(&p);
}

}  // namespace texbake
