// Proxy fitting (SPEC section 6): the parameters of a sphere, cylinder, cone,
// disk, quad or plane that wrap a point set, computed with CGAL (only
// bake/fit/fit_proxy.cpp includes CGAL; it builds into the texbake_fit library).
//
// What each fit returns (all vectors unit, every optional field filled):
//  - sphere: the minimum enclosing sphere (CGAL Min_sphere_of_spheres_d).
//    pole = the fixed axis if given (flipped into the up hemisphere unless
//    keep_axis_sign), else `up`.
//  - cylinder: axis from a principal component analysis (CGAL
//    linear_least_squares_fitting_3) or the fixed axis; the axis line passes
//    through the centre of the minimum enclosing circle of the points
//    projected on the plane perpendicular to it; radius = that circle's radius
//    (every point lies within `radius` of the axis); base and height span the
//    points' extent along the axis. The axis points into the up hemisphere.
//  - cone: axis line as the cylinder's. The radius-versus-height profile
//    (in each of up to 64 height bins, the mean height and radius of the
//    outer shell: the points within 5% of the largest radius below the bin's
//    maximum) is fitted by a line (CGAL linear_least_squares_fitting_2,
//    orthogonal regression). apex = where the line meets the axis (the narrow
//    end); base plane at the points' far end; radius = the line's radius
//    there; the axis points from the base to the apex (whatever `up` says).
//    The cone follows the middle of the surface's noise rather than
//    enclosing it (an enclosing cone's apex would move by noise divided by
//    sin(half-angle)): points may lie outside the lateral surface by about
//    the noise, never beyond the base plane.
//  - disk: best-fit plane (linear_least_squares_fitting_3), then the minimum
//    enclosing circle of the points projected on it. The normal points into
//    the up hemisphere.
//  - quad / plane: best-fit plane, then the minimum-area enclosing rectangle
//    of the projected points (CGAL convex_hull_2 + min_rectangle_2). Seen from
//    the normal's tip (normal in the up hemisphere), u runs to the right and v
//    up, u x v = normal (SPEC section 1): v is the rectangle side closest to
//    `up` projected into the plane; when the normal is within 10 degrees of
//    `up` (a floor seen from above), v is the side closest to
//    normal x equator (the equator rule below), so u follows +X for a
//    horizontal plane with up = +Z. plane: origin = p00, u_axis = p10 - p00,
//    v_axis = p01 - p00 (the axis lengths are the rectangle's sides).
//
// Canonical choices (documented, deterministic):
//  - "into the up hemisphere": dot(direction, up) > 0; when the direction is
//    within 1 degree of perpendicular to up (a wall's normal), the first of
//    +X, +Y, +Z it is not within 1 degree of perpendicular to decides
//    instead (so a fitted wall does not flip sides with the noise).
//  - equator: the first of +X, +Y, +Z that makes at least 10 degrees with the
//    pole/axis/normal, made perpendicular to it (Gram-Schmidt). For axes
//    along a coordinate axis this is SPEC section 1's default; near-parallel
//    candidates are skipped so the equator never comes from a rounding-noise
//    residual.
//  - a principal axis for cylinder and cone: of the three principal
//    directions (covariance eigenvectors, eigenvalues l1 >= l2 >= l3), the
//    one whose eigenvalue stands apart from the other two (a surface of
//    revolution has two equal eigenvalues): the largest (from the line fit)
//    if l1/l2 > l2/l3, else the smallest (the plane fit's normal). So both a
//    tall bottle and a flat tin get their symmetry axis.
//
// Errors (ErrorCode::kInvalidArgument, the message says what is wrong): no
// points, a non-finite coordinate, all points coincident, points with no
// extent along the cylinder/cone axis or no radius around it, collinear
// points for disk/quad/plane, a cone whose radius does not change along the
// axis (apex more than 100 times the points' axial extent away), a zero up or
// fixed axis. "Zero" means below 1e-6 of the points' bounding-box diagonal
// (float input has about 6e-8 relative precision).
#pragma once

#include <optional>
#include <span>
#include <vector>

#include "mapping/error.h"
#include "mapping/proxy.h"
#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct FitOptions {
  // The up direction (need not be unit, must not be zero): the sphere's pole
  // when no axis is fixed, the hemisphere for axes and normals, and the
  // direction v follows on quads and planes. Default +Z.
  Vec3 up{0, 0, 1};
  // Fixed direction instead of a fitted one (need not be unit): the sphere's
  // pole, the cylinder's or cone's axis, the normal of disk, quad and plane.
  std::optional<Vec3> axis;
  // true: `axis` is used with the sign given (a user's --axis/--normal/
  // --pole; a cone must then narrow towards the axis' tip, else an error).
  // false: only its line is fixed; the sign follows the rules above (up
  // hemisphere, cone towards its apex), as for the --up shorthand.
  bool keep_axis_sign = true;
  // Values the user fixed (given flags). The fit keeps them and fits the
  // remaining parameters *around them* (not around values it would have
  // fitted itself):
  //  - anchor: the sphere's centre (radius = the largest distance of a point
  //    from it), the disk's centre (radius = the largest in-plane distance),
  //    the cylinder's base centre (the axis line passes through it; radius =
  //    the largest distance from that line; height = the points' extent
  //    beyond the base), the cone's apex (the generator is fitted through
  //    it: a line through the origin of the distance-below-apex versus
  //    radius profile; height = the points' extent below the apex unless
  //    `height` is given; radius = slope * height), the plane's origin (the
  //    axes keep the fitted rectangle's directions, their lengths reach the
  //    farthest point). Without a fixed axis direction, a cylinder's or cone's
  //    axis sign is chosen so the points lie on the side of the base (towards
  //    the apex's base) where they extend further.
  //  - height: the cone's base plane lies `height` below the apex (fitted or
  //    given); its radius is the fitted generator's radius there. (A
  //    cylinder's given height needs nothing re-fitted: the base stays at the
  //    points' low end.)
  // Radius and the equator need no re-fit: nothing else depends on them.
  std::optional<Vec3> anchor;
  std::optional<double> height;
};

// The points a mesh's fit uses: the vertices referenced by at least one face,
// in index order (SPEC section 8: unreferenced vertices take no part). A mesh
// without faces (a point cloud) uses all its vertices.
std::vector<Float3> fit_points(const MeshData& mesh);

Expected<SphereParams> fit_sphere(std::span<const Float3> points, const FitOptions& options = {});
Expected<CylinderParams> fit_cylinder(std::span<const Float3> points,
                                      const FitOptions& options = {});
Expected<ConeParams> fit_cone(std::span<const Float3> points, const FitOptions& options = {});
Expected<DiskParams> fit_disk(std::span<const Float3> points, const FitOptions& options = {});
Expected<QuadParams> fit_quad(std::span<const Float3> points, const FitOptions& options = {});
Expected<PlaneParams> fit_plane(std::span<const Float3> points, const FitOptions& options = {});

// Dispatches on kind.
Expected<ProxyParams> fit_proxy(ProxyKind kind, std::span<const Float3> points,
                                const FitOptions& options = {});
// fit_proxy on fit_points(mesh).
Expected<ProxyParams> fit_proxy(ProxyKind kind, const MeshData& mesh,
                                const FitOptions& options = {});

}  // namespace texbake
