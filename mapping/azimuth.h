// The one azimuth/seam rule of texbake (SPEC section 2), shared by the sphere,
// cylinder, cone and disk, and the construction of their orthonormal frames.
//
// u = atan2(v . east, v . equator) / (2 pi), wrapped into [0, 1), with
// east = axis x equator: seen from the tip of the axis, u grows counter-
// clockwise from the equator (u = 0) through east (u = 0.25). The seam is the
// half-plane through the axis containing the equator: u = 0 lies on it and u
// stays below 1, so no point has two texture coordinates.
#pragma once

#include <optional>
#include <string>

#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mapping/vec.h"

namespace texbake {

// Below this sine of the angle between two directions they count as parallel
// (an equator along the pole, two plane axes along each other). A relative
// measure: scale-free.
inline constexpr double kParallelTolerance = 1e-9;

// A component of length below kAxisTolerance times the point's distance scale
// is rounding noise: the point lies on the axis (pole, apex, disk centre),
// where the azimuth is undefined and u is 0 by convention.
inline constexpr double kAxisTolerance = 1e-12;

struct Azimuth {
  double u = 0;          // in [0, 1)
  bool on_axis = false;  // the component across the axis is rounding noise: u = 0
};

// Azimuth of vector w (any length) around frame.axis. `scale` is the length
// that w's component across the axis is compared with (e.g. the radius, or
// |w|); at or below kAxisTolerance * scale the point is on the axis.
Azimuth azimuth(const Frame& frame, Vec3 w, double scale);

// The unit direction across the axis at azimuth u: cos(2 pi u) equator +
// sin(2 pi u) east. azimuth(frame, azimuth_direction(frame, u), 1).u == u
// (up to rounding, modulo 1).
Vec3 azimuth_direction(const Frame& frame, double u);

// u wrapped into [0, 1): u - floor(u), with the rounding case u -> 1.0 mapped
// to 0.
double wrap_unit(double u);

// Normalises `v`, which must be finite and non-zero: the error names `name`.
// Robust to huge and tiny components (scales by the largest first).
Expected<Vec3> unit_vector(Vec3 v, const std::string& name);

// Builds the frame of a proxy from the user's axis and optional equator
// (SPEC section 1): axis normalised; equator made exactly perpendicular by
// Gram-Schmidt (twice, so the frame is orthonormal to rounding even for a
// nearly parallel equator); an absent equator is the first of +X, +Y, +Z not
// parallel to the axis. Errors (kInvalidArgument) name axis_name/equator_name:
// non-finite, zero, or an equator parallel to the axis.
Expected<Frame> make_frame(Vec3 axis, const std::optional<Vec3>& equator,
                           const std::string& axis_name, const std::string& equator_name);

}  // namespace texbake
