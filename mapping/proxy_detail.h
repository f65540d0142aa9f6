// Small helpers shared by the proxies' .cpp files (not part of the public API).
#pragma once

#include "mapping/proxy.h"

namespace texbake::detail {

// (u, v) within this distance of [0, 1] count as inside: points forward-mapped
// onto an edge come back off it by rounding (1e-17), and must stay "ok".
// Classification only: uv itself is never clamped here.
inline constexpr double kEdgeTolerance = 1e-12;

inline bool in_unit_interval(double t) {
  return t >= -kEdgeTolerance && t <= 1 + kEdgeTolerance;
}

// The result for a point without a mapping (NaN/inf input, sphere centre, a
// cylinder's axis): finite numbers only, so nothing downstream sees a NaN.
// `fallback_direction` is a unit vector (the proxy's axis or normal).
inline MapResult undefined_result(Vec3 fallback_direction, UV uv = {}) {
  return {uv, fallback_direction, MapStatus::kUndefined};
}

}  // namespace texbake::detail
