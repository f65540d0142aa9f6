// Proxy fitting with CGAL (SPEC section 6). The contract, canonical choices
// and error cases are in fit_proxy.h; this file explains the how and why.
//
// Numerics: every computation runs in double on points moved to their
// bounding-box centre (so far-from-origin meshes keep their precision).
// CGAL is used where it is exact or where rounding cannot break the result:
//  - Min_sphere_of_spheres_d is documented to be robust with double; its
//    radius is then raised to the largest actual centre-point distance, so the
//    sphere encloses every point in double arithmetic whatever it rounded.
//  - convex_hull_2 and min_rectangle_2 run on the Epick kernel (exact
//    predicates: the hull is combinatorially right even for nearly collinear
//    input); only the rectangle's direction is taken from min_rectangle_2, the
//    extents are recomputed from all points, which again guarantees enclosure.
//  - the principal component fits use Eigen's closed-form 3x3 solver (CGAL's
//    Eigen_diagonalize_traits, passed explicitly: Default_diagonalize_traits
//    would fall back to a deprecated solver unless CGAL_EIGEN3_ENABLED is set).
#include "bake/fit/fit_proxy.h"

#include <CGAL/Eigen_diagonalize_traits.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Min_sphere_of_points_d_traits_2.h>
#include <CGAL/Min_sphere_of_points_d_traits_3.h>
#include <CGAL/Min_sphere_of_spheres_d.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/linear_least_squares_fitting_2.h>
#include <CGAL/linear_least_squares_fitting_3.h>
#include <CGAL/min_quadrilateral_2.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iterator>
#include <limits>
#include <string>
#include <type_traits>

namespace texbake {
namespace {

// Principal component fits and minimum spheres: plain double (see above).
using K = CGAL::Simple_cartesian<double>;
// Convex hull and minimum rectangle: exact predicates, double constructions.
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point2 = Epick::Point_2;

// Extents below this fraction of the bounding-box diagonal count as zero:
// float input carries about 6e-8 relative precision, so anything smaller is
// rounding noise, not shape.
constexpr double kZeroRelative = 1e-6;
// cos(10 degrees): the equator skips coordinate axes closer than this to the
// pole; quads use the projected up direction only when the plane is tilted
// more than 10 degrees from horizontal (|up projected| > sin 10 degrees).
constexpr double kCos10Degrees = 0.98480775301220806;
constexpr double kSin10Degrees = 0.17364817766693033;
// A direction counts as perpendicular to up when |dot| is below this
// (sin 1 degree): a fitted wall's normal is only that close to horizontal, and
// its side must not flip with the noise.
constexpr double kPerpendicularDot = 0.017452406437283512;
// Cone profile: at most this many height bins (more only adds noise).
constexpr int kMaxProfileBins = 64;
// Minimum points per profile bin on average, so each bin's maximum radius is
// a sample of the envelope rather than of a single noisy point.
constexpr std::size_t kPointsPerBin = 16;
// Cone profile: a bin's outer shell is its points within this fraction of the
// largest radius below the bin's maximum (wide enough for the noise of a
// scan, narrow enough to drop a cap's interior).
constexpr double kShellBand = 0.05;
// A cone whose apex lies further than this many axial extents from the points
// is a cylinder in disguise: report it instead of returning a huge cone.
constexpr double kMaxApexDistance = 100;

constexpr std::array<Vec3, 3> kCoordinateAxes = {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}};

Error invalid(const char* kind, const std::string& what) {
  return make_error(ErrorCode::kInvalidArgument, std::string("cannot fit a ") + kind + ": " + what);
}

// The input, validated and moved to its bounding-box centre.
struct LocalPoints {
  std::vector<K::Point_3> points;  // p - offset
  Vec3 offset;                     // bounding-box centre (world)
  double diagonal = 0;             // bounding-box diagonal
};

Expected<LocalPoints> prepare_points(std::span<const Float3> input, const char* kind) {
  if (input.empty()) return invalid(kind, "there are no points");
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi = -lo;
  for (std::size_t i = 0; i < input.size(); ++i) {
    const Vec3 p{input[i].x, input[i].y, input[i].z};
    if (!is_finite(p)) return invalid(kind, "point " + std::to_string(i) + " is not finite");
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  LocalPoints out;
  out.offset = (lo + hi) * 0.5;
  out.diagonal = length(hi - lo);
  if (!(out.diagonal > 0)) {
    return invalid(kind, input.size() == 1
                             ? "there is only one point"
                             : "all " + std::to_string(input.size()) + " points coincide");
  }
  out.points.reserve(input.size());
  for (const Float3& f : input) {
    out.points.emplace_back(f.x - out.offset.x, f.y - out.offset.y, f.z - out.offset.z);
  }
  return out;
}

Expected<Vec3> unit_direction(Vec3 v, const char* kind, const char* name) {
  if (!is_finite(v)) return invalid(kind, std::string(name) + " is not finite");
  const double len = length(v);
  if (!(len > 0)) return invalid(kind, std::string(name) + " is the zero vector");
  return v / len;
}

// -0.0 + 0.0 == +0.0: printed proxies say 0, not -0, for axes like -(-Y).
Vec3 tidy(Vec3 v) {
  return v + Vec3{0, 0, 0};
}

Vec3 to_vec(const K::Point_3& p) {
  return {p.x(), p.y(), p.z()};
}
Vec3 to_vec(const K::Vector_3& v) {
  return {v.x(), v.y(), v.z()};
}

// Flips `dir` into the up hemisphere; ties (dir perpendicular to up) are
// broken by the first coordinate axis dir is not perpendicular to.
Vec3 orient_up(Vec3 dir, Vec3 up) {
  double d = dot(dir, up);
  for (std::size_t i = 0; std::abs(d) < kPerpendicularDot && i < kCoordinateAxes.size(); ++i) {
    d = dot(dir, kCoordinateAxes[i]);
  }
  return d < 0 ? -dir : dir;
}

// The first of +X, +Y, +Z at least 10 degrees from `axis`, made perpendicular
// (Gram-Schmidt). One always qualifies: some coordinate axis makes at least
// acos(1/sqrt(3)) = 54.7 degrees with any unit vector.
Vec3 equator_for(Vec3 axis) {
  for (const Vec3& e : kCoordinateAxes) {
    const double d = dot(e, axis);
    if (std::abs(d) < kCos10Degrees) return normalize(e - axis * d);
  }
  return normalize(kCoordinateAxes[0] - axis * axis.x);  // unreachable for unit axes
}

// Principal component analysis with CGAL: the best-fit line gives the
// eigenvector of the largest eigenvalue, the best-fit plane's normal that of
// the smallest. Their fitting qualities are 1 - l2/l1 (line) and 1 - l3/l2
// (plane), CGAL PCA_util.h fitting_line_3/fitting_plane_3.
struct Principal {
  Vec3 centroid;
  Vec3 largest;   // unit
  Vec3 smallest;  // unit
  double line_quality = 0;
  double plane_quality = 0;
};

Principal principal_components(const std::vector<K::Point_3>& points) {
  const CGAL::Eigen_diagonalize_traits<double, 3> solver;
  K::Line_3 line;
  K::Plane_3 plane;
  K::Point_3 centroid;
  Principal out;
  out.line_quality = CGAL::linear_least_squares_fitting_3(
      points.begin(), points.end(), line, centroid, CGAL::Dimension_tag<0>(), K(), solver);
  out.plane_quality = CGAL::linear_least_squares_fitting_3(
      points.begin(), points.end(), plane, centroid, CGAL::Dimension_tag<0>(), K(), solver);
  out.centroid = to_vec(centroid);
  out.largest = normalize(to_vec(line.to_vector()));
  out.smallest = normalize(to_vec(plane.orthogonal_vector()));
  return out;
}

// The symmetry axis of a surface of revolution: the principal direction whose
// eigenvalue stands apart (l1/l2 > l2/l3 <=> line quality > plane quality).
Vec3 symmetry_axis(const Principal& pca) {
  return pca.line_quality > pca.plane_quality ? pca.largest : pca.smallest;
}

// Two unit vectors spanning the plane perpendicular to `n`, with e1 x e2 = n
// and e1 = equator_for(n).
struct PlaneBasis {
  Vec3 e1, e2;
};
PlaneBasis plane_basis(Vec3 n) {
  const Vec3 e1 = equator_for(n);
  return {e1, cross(n, e1)};
}

struct Circle {
  double x = 0, y = 0, radius = 0;
};

// The minimum enclosing circle of the convex hull's vertices (the same as the
// whole set's), radius then raised to the largest distance from any point so
// rounding cannot leave a point outside.
Circle min_enclosing_circle(const std::vector<Point2>& hull, const std::vector<Point2>& all) {
  using Traits = CGAL::Min_sphere_of_points_d_traits_2<Epick, double, CGAL::Tag_true>;
  CGAL::Min_sphere_of_spheres_d<Traits> min_circle(hull.begin(), hull.end());
  auto c = min_circle.center_cartesian_begin();
  Circle out;
  out.x = *c;
  out.y = *++c;
  double r2 = 0;
  for (const Point2& p : all) {
    r2 = std::max(r2, (p.x() - out.x) * (p.x() - out.x) + (p.y() - out.y) * (p.y() - out.y));
  }
  out.radius = std::max(min_circle.radius(), std::sqrt(r2));
  return out;
}

std::vector<Point2> convex_hull(const std::vector<Point2>& points) {
  std::vector<Point2> hull;
  CGAL::convex_hull_2(points.begin(), points.end(), std::back_inserter(hull));
  return hull;  // counter-clockwise, as min_rectangle_2 requires
}

// ---- Cylinder and cone: the axis line. ------------------------------------

// Points in the axis frame: h along the axis, (x, y) across it.
struct AxisFrame {
  Vec3 axis;  // unit
  PlaneBasis basis;
  std::vector<double> h;
  std::vector<Point2> across;
  double h_min = 0, h_max = 0;
  Circle circle;  // minimum enclosing circle of `across`: the axis passes its centre
};

Expected<AxisFrame> axis_frame(const LocalPoints& local, const FitOptions& options,
                               const char* kind) {
  AxisFrame f;
  if (options.axis) {
    auto axis = unit_direction(*options.axis, kind, "the axis");
    if (!axis) return axis.error();
    f.axis = *axis;
  } else {
    f.axis = symmetry_axis(principal_components(local.points));
  }
  f.basis = plane_basis(f.axis);
  const std::size_t n = local.points.size();
  f.h.resize(n);
  f.across.reserve(n);
  f.h_min = std::numeric_limits<double>::infinity();
  f.h_max = -f.h_min;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 p = to_vec(local.points[i]);
    f.h[i] = dot(p, f.axis);
    f.h_min = std::min(f.h_min, f.h[i]);
    f.h_max = std::max(f.h_max, f.h[i]);
    f.across.emplace_back(dot(p, f.basis.e1), dot(p, f.basis.e2));
  }
  const double zero = kZeroRelative * local.diagonal;
  if (f.h_max - f.h_min < zero) return invalid(kind, "the points have no extent along the axis");
  f.circle = min_enclosing_circle(convex_hull(f.across), f.across);
  if (f.circle.radius < zero) {
    return invalid(kind, "the points lie on the axis (no radius around it)");
  }
  return f;
}

// World position of the axis point at height h.
Vec3 axis_point(const AxisFrame& f, const LocalPoints& local, double h) {
  return local.offset + f.basis.e1 * f.circle.x + f.basis.e2 * f.circle.y + f.axis * h;
}

// ---- Disk, quad, plane: the best-fit plane. ---------------------------------

struct PlaneFrame {
  Vec3 origin;  // world position of the 2D origin (the centroid)
  Vec3 normal;  // unit
  PlaneBasis basis;
  std::vector<Point2> projected;
  std::vector<Point2> hull;
};

Expected<PlaneFrame> plane_frame(const LocalPoints& local, const FitOptions& options, Vec3 up,
                                 const char* kind) {
  PlaneFrame f;
  const Principal pca = principal_components(local.points);
  if (options.axis) {
    auto normal = unit_direction(*options.axis, kind, "the normal");
    if (!normal) return normal.error();
    f.normal = options.keep_axis_sign ? *normal : orient_up(*normal, up);
  } else {
    f.normal = orient_up(pca.smallest, up);
  }
  f.basis = plane_basis(f.normal);
  f.origin = local.offset + pca.centroid;
  f.projected.reserve(local.points.size());
  for (const K::Point_3& q : local.points) {
    const Vec3 p = to_vec(q) - pca.centroid;
    f.projected.emplace_back(dot(p, f.basis.e1), dot(p, f.basis.e2));
  }
  f.hull = convex_hull(f.projected);
  if (f.hull.size() < 3) return invalid(kind, "the points are collinear");
  return f;
}

// The minimum-area enclosing rectangle's side directions (unit, 2D), or an
// error when the points are collinear (rectangle of zero width).
struct RectangleSides {
  std::array<double, 2> d1, d2;  // d2 = d1 rotated by +90 degrees
};

Expected<RectangleSides> min_rectangle_sides(const PlaneFrame& f, double diagonal,
                                             const char* kind) {
  std::vector<Point2> corners;
  CGAL::min_rectangle_2(f.hull.begin(), f.hull.end(), std::back_inserter(corners));
  // The longest of the rectangle's edges from corner 0 gives the most
  // accurate direction (min_rectangle_2 constructs the corners in double).
  double best = 0;
  RectangleSides s{};
  for (int k : {1, 3}) {
    if (corners.size() < 4) break;
    const double dx = corners[k].x() - corners[0].x(), dy = corners[k].y() - corners[0].y();
    const double len = std::hypot(dx, dy);
    if (len > best) {
      best = len;
      s.d1 = {dx / len, dy / len};
    }
  }
  if (!(best > 0)) return invalid(kind, "the points are collinear");
  s.d2 = {-s.d1[1], s.d1[0]};
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const Point2& p : f.hull) {
    const double t = p.x() * s.d2[0] + p.y() * s.d2[1];
    lo = std::min(lo, t);
    hi = std::max(hi, t);
  }
  if (hi - lo < kZeroRelative * diagonal) return invalid(kind, "the points are collinear");
  return s;
}

// The enclosing rectangle in world space: corners p00, p10, p11, p01 with u
// to the right and v up seen from the normal's tip (see fit_proxy.h).
Expected<std::array<Vec3, 4>> fit_rectangle(std::span<const Float3> input,
                                            const FitOptions& options, const char* kind) {
  auto local = prepare_points(input, kind);
  if (!local) return local.error();
  auto up = unit_direction(options.up, kind, "up");
  if (!up) return up.error();
  auto frame = plane_frame(*local, options, *up, kind);
  if (!frame) return frame.error();
  auto sides = min_rectangle_sides(*frame, local->diagonal, kind);
  if (!sides) return sides.error();
  const PlaneFrame& f = *frame;

  // Reference for v: up projected into the plane, or normal x equator (= e2)
  // when the plane is nearly perpendicular to up.
  const Vec3 up_in_plane = *up - f.normal * dot(*up, f.normal);
  const Vec3 ref3 = length(up_in_plane) > kSin10Degrees ? up_in_plane : f.basis.e2;
  const std::array<double, 2> ref{dot(ref3, f.basis.e1), dot(ref3, f.basis.e2)};
  // v = the rectangle side direction (+-d1, +-d2) closest to ref; u = v x n,
  // which in the (e1, e2) plane is v rotated by -90 degrees.
  std::array<double, 2> v2{};
  double best = -std::numeric_limits<double>::infinity();
  for (const auto& d : {sides->d1, sides->d2}) {
    for (double sign : {1.0, -1.0}) {
      const double score = sign * (d[0] * ref[0] + d[1] * ref[1]);
      if (score > best) {
        best = score;
        v2 = {sign * d[0], sign * d[1]};
      }
    }
  }
  const std::array<double, 2> u2{v2[1], -v2[0]};
  double u_lo = std::numeric_limits<double>::infinity(), u_hi = -u_lo, v_lo = u_lo, v_hi = -u_lo;
  for (const Point2& p : f.projected) {
    const double u = p.x() * u2[0] + p.y() * u2[1];
    const double v = p.x() * v2[0] + p.y() * v2[1];
    u_lo = std::min(u_lo, u);
    u_hi = std::max(u_hi, u);
    v_lo = std::min(v_lo, v);
    v_hi = std::max(v_hi, v);
  }
  const Vec3 u3 = f.basis.e1 * u2[0] + f.basis.e2 * u2[1];
  const Vec3 v3 = f.basis.e1 * v2[0] + f.basis.e2 * v2[1];
  const Vec3 p00 = f.origin + u3 * u_lo + v3 * v_lo;
  const Vec3 du = u3 * (u_hi - u_lo), dv = v3 * (v_hi - v_lo);
  return std::array<Vec3, 4>{p00, p00 + du, p00 + du + dv, p00 + dv};
}

// The cone's radius-versus-height profile: in each of up to kMaxProfileBins
// height bins, the points within kShellBand of the bin's largest radius form
// the outer shell (a cap, interior or an inner wall lie further in and drop
// out); the shell's mean (h, rho) lies on the cone's generator, unbiased by
// noise that is symmetric about the surface. (The bin maxima alone would be
// biased outwards by the noise, which moves the apex by noise /
// sin(half-angle).) Precondition: h_max > h_min.
std::vector<K::Point_2> shell_profile(const std::vector<double>& h, const std::vector<double>& rho,
                                      double h_min, double h_max) {
  const std::size_t n = h.size();
  double rho_max = 0;
  for (double r : rho) rho_max = std::max(rho_max, r);
  const int bins = static_cast<int>(std::clamp<std::size_t>(n / kPointsPerBin, 2, kMaxProfileBins));
  const double extent = h_max - h_min;
  auto bin_of = [&](std::size_t i) {
    return std::clamp(static_cast<int>((h[i] - h_min) / extent * bins), 0, bins - 1);
  };
  std::vector<double> bin_max(bins, -1);
  for (std::size_t i = 0; i < n; ++i) bin_max[bin_of(i)] = std::max(bin_max[bin_of(i)], rho[i]);
  const double band = kShellBand * rho_max;
  std::vector<double> sum_h(bins, 0), sum_rho(bins, 0);
  std::vector<std::size_t> count(bins, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const int b = bin_of(i);
    if (rho[i] < bin_max[b] - band) continue;
    sum_h[b] += h[i];
    sum_rho[b] += rho[i];
    ++count[b];
  }
  std::vector<K::Point_2> profile;
  for (int b = 0; b < bins; ++b) {
    if (count[b] > 0) profile.emplace_back(sum_h[b] / count[b], sum_rho[b] / count[b]);
  }
  return profile;
}

// The axis direction of a cylinder or cone: the fixed one, else the symmetry
// axis of the principal components.
Expected<Vec3> axis_direction(const LocalPoints& local, const FitOptions& options,
                              const char* kind) {
  if (options.axis) return unit_direction(*options.axis, kind, "the axis");
  return symmetry_axis(principal_components(local.points));
}

// The points relative to a given axis line through `anchor` (local
// coordinates): h along the axis, rho the distance from the line.
struct AnchoredFrame {
  std::vector<double> h, rho;
  double h_min = 0, h_max = 0, rho_max = 0;
};

AnchoredFrame anchored_frame(const LocalPoints& local, Vec3 anchor, Vec3 axis) {
  AnchoredFrame f;
  const std::size_t n = local.points.size();
  f.h.resize(n);
  f.rho.resize(n);
  f.h_min = std::numeric_limits<double>::infinity();
  f.h_max = -f.h_min;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 d = to_vec(local.points[i]) - anchor;
    f.h[i] = dot(d, axis);
    f.rho[i] = length(d - axis * f.h[i]);
    f.h_min = std::min(f.h_min, f.h[i]);
    f.h_max = std::max(f.h_max, f.h[i]);
    f.rho_max = std::max(f.rho_max, f.rho[i]);
  }
  return f;
}

// Negates h and swaps the extents: the same frame seen along -axis.
void flip(AnchoredFrame& f) {
  for (double& h : f.h) h = -h;
  f.h_min = -f.h_min;
  f.h_max = -f.h_max;
  std::swap(f.h_min, f.h_max);
}

}  // namespace

std::vector<Float3> fit_points(const MeshData& mesh) {
  if (mesh.face_vertices.empty()) return mesh.positions;
  std::vector<char> used(mesh.positions.size(), 0);
  for (uint32_t v : mesh.face_vertices) {
    if (v < used.size()) used[v] = 1;
  }
  std::vector<Float3> out;
  out.reserve(mesh.positions.size());
  for (std::size_t i = 0; i < used.size(); ++i) {
    if (used[i]) out.push_back(mesh.positions[i]);
  }
  return out;
}

namespace {

// The cone with a given apex: the axis line passes through it, and the
// generator is the line through the apex that best fits the shell profile
// (orthogonal regression through the origin: the principal direction of the
// profile's second moments about the apex, closed form for 2 x 2).
Expected<ConeParams> fit_cone_through_apex(const LocalPoints& local, const FitOptions& options) {
  constexpr const char* kKind = "cone";
  const double zero = kZeroRelative * local.diagonal;
  auto axis = axis_direction(local, options, kKind);
  if (!axis) return axis.error();
  const bool keep_sign = options.axis && options.keep_axis_sign;
  // t = distance below the apex along the axis (the axis points from the
  // base towards the apex, so the points should have t > 0).
  Vec3 dir = *axis;
  AnchoredFrame a = anchored_frame(local, *options.anchor - local.offset, -dir);
  if (!keep_sign && -a.h_min > a.h_max) {  // the points lie on the axis' tip side
    dir = -dir;
    flip(a);
  }
  if (!(a.h_max > zero)) {
    return invalid(kKind, keep_sign ? "every point lies beyond the given apex along the given "
                                      "axis (the axis points from the base towards the apex: "
                                      "reverse it)"
                                    : "the points have no extent along the axis");
  }
  if (!(a.rho_max > zero))
    return invalid(kKind, "the points lie on the axis (no radius around it)");
  const std::vector<K::Point_2> profile = shell_profile(a.h, a.rho, a.h_min, a.h_max);
  double stt = 0, str = 0, srr = 0;
  for (const K::Point_2& p : profile) {
    stt += p.x() * p.x();
    str += p.x() * p.y();
    srr += p.y() * p.y();
  }
  // Principal direction (cos th, sin th) of [[stt, str], [str, srr]].
  const double th = 0.5 * std::atan2(2 * str, stt - srr);
  const double slope = std::tan(th);  // radius per unit of distance below the apex
  if (!(slope > 0) || !std::isfinite(slope)) {
    return invalid(kKind, "the points do not widen away from the given apex");
  }
  ConeParams c;
  c.apex = *options.anchor;
  c.axis = tidy(dir);
  c.equator = tidy(equator_for(c.axis));
  c.height = options.height ? *options.height : a.h_max;
  c.radius = slope * c.height;
  return c;
}

}  // namespace

Expected<SphereParams> fit_sphere(std::span<const Float3> input, const FitOptions& options) {
  constexpr const char* kKind = "sphere";
  auto local = prepare_points(input, kKind);
  if (!local) return local.error();
  auto pole =
      unit_direction(options.axis.value_or(options.up), kKind, options.axis ? "the pole" : "up");
  if (!pole) return pole.error();
  const Vec3 up_pole =
      options.axis && !options.keep_axis_sign ? orient_up(*pole, options.up) : *pole;

  if (options.anchor) {
    // A given centre: the smallest sphere around it that encloses every point.
    const Vec3 center = *options.anchor - local->offset;
    double r2 = 0;
    for (const K::Point_3& p : local->points) {
      const Vec3 d = to_vec(p) - center;
      r2 = std::max(r2, dot(d, d));
    }
    if (!(std::sqrt(r2) > kZeroRelative * local->diagonal)) {
      return invalid(kKind, "every point lies at the given centre");
    }
    SphereParams s;
    s.center = *options.anchor;
    s.radius = std::sqrt(r2);
    s.pole = tidy(up_pole);
    s.equator = tidy(equator_for(up_pole));
    return s;
  }

  // Min_sphere_of_spheres_d on points (radius 0): expected linear time, robust
  // in double (CGAL manual, "Bounding Volumes", Min_sphere_of_spheres_d).
  using Traits = CGAL::Min_sphere_of_points_d_traits_3<K, double, CGAL::Tag_true>;
  CGAL::Min_sphere_of_spheres_d<Traits> min_sphere(local->points.begin(), local->points.end());
  auto c = min_sphere.center_cartesian_begin();
  Vec3 center;
  center.x = *c;
  center.y = *++c;
  center.z = *++c;
  double r2 = 0;
  for (const K::Point_3& p : local->points) {
    const Vec3 d = to_vec(p) - center;
    r2 = std::max(r2, dot(d, d));
  }
  SphereParams s;
  s.center = local->offset + center;
  s.radius = std::max(min_sphere.radius(), std::sqrt(r2));
  s.pole = tidy(up_pole);
  s.equator = tidy(equator_for(up_pole));
  return s;
}

Expected<CylinderParams> fit_cylinder(std::span<const Float3> input, const FitOptions& options) {
  constexpr const char* kKind = "cylinder";
  auto local = prepare_points(input, kKind);
  if (!local) return local.error();
  auto up = unit_direction(options.up, kKind, "up");
  if (!up) return up.error();
  const bool keep_sign = options.axis && options.keep_axis_sign;
  const double zero = kZeroRelative * local->diagonal;
  if (options.anchor) {
    // A given base centre: the axis line passes through it.
    auto axis = axis_direction(*local, options, kKind);
    if (!axis) return axis.error();
    Vec3 dir = *axis;
    AnchoredFrame a = anchored_frame(*local, *options.anchor - local->offset, dir);
    if (!keep_sign && -a.h_min > a.h_max) {  // the points lie on the -axis side
      dir = -dir;
      flip(a);
    }
    if (!(a.h_max > zero)) {
      return invalid(kKind, keep_sign ? "every point lies behind the given base along the given "
                                        "axis (reverse the axis or move the base)"
                                      : "the points have no extent along the axis");
    }
    if (!(a.rho_max > zero))
      return invalid(kKind, "the points lie on the axis (no radius around it)");
    CylinderParams c;
    c.base = *options.anchor;
    c.axis = tidy(dir);
    c.equator = tidy(equator_for(c.axis));
    c.radius = a.rho_max;
    c.height = a.h_max;
    return c;
  }
  auto frame = axis_frame(*local, options, kKind);
  if (!frame) return frame.error();
  AxisFrame& f = *frame;
  const bool flip = !keep_sign && dot(orient_up(f.axis, *up), f.axis) < 0;
  CylinderParams c;
  c.radius = f.circle.radius;
  c.height = f.h_max - f.h_min;
  if (flip) {
    c.axis = -f.axis;
    c.base = axis_point(f, *local, f.h_max);
  } else {
    c.axis = f.axis;
    c.base = axis_point(f, *local, f.h_min);
  }
  c.axis = tidy(c.axis);
  c.equator = tidy(equator_for(c.axis));
  return c;
}

Expected<ConeParams> fit_cone(std::span<const Float3> input, const FitOptions& options) {
  constexpr const char* kKind = "cone";
  auto local = prepare_points(input, kKind);
  if (!local) return local.error();
  auto up = unit_direction(options.up, kKind, "up");
  if (!up) return up.error();
  if (options.height && !(*options.height > 0)) return invalid(kKind, "the height is not positive");
  if (options.anchor) return fit_cone_through_apex(*local, options);
  auto frame = axis_frame(*local, options, kKind);
  if (!frame) return frame.error();
  const AxisFrame& f = *frame;
  const std::size_t n = f.h.size();
  const double extent = f.h_max - f.h_min;

  std::vector<double> rho(n);
  for (std::size_t i = 0; i < n; ++i) {
    rho[i] = std::hypot(f.across[i].x() - f.circle.x, f.across[i].y() - f.circle.y);
  }
  const std::vector<K::Point_2> profile = shell_profile(f.h, rho, f.h_min, f.h_max);
  if (profile.size() < 2) return invalid(kKind, "the points have no extent along the axis");

  // Orthogonal regression (CGAL) rather than ordinary least squares, so a
  // flat, wide cone (radius changing fast with height) is fitted as well as
  // a slender one.
  K::Line_2 line;
  K::Point_2 centroid;
  CGAL::linear_least_squares_fitting_2(profile.begin(), profile.end(), line, centroid,
                                       CGAL::Dimension_tag<0>(), K(),
                                       CGAL::Eigen_diagonalize_traits<double, 2>());
  // line: a h + b rho + c = 0  =>  rho = intercept + slope h.
  if (line.b() == 0) return invalid(kKind, "the points have no extent along the axis");
  const double slope = -line.a() / line.b();
  const double intercept = -line.c() / line.b();

  // Apex where the line meets the axis; the base plane at the far end of the
  // points, so every point lies between base and apex planes (up to noise
  // at the tip).
  const double h_apex = slope == 0 ? std::numeric_limits<double>::infinity() : -intercept / slope;
  const bool apex_up = slope < 0;  // radius shrinks with h: apex on the +axis side
  const double h_base = apex_up ? f.h_min : f.h_max;
  if (!(std::abs(h_apex - h_base) <= (1 + kMaxApexDistance) * extent)) {
    return invalid(kKind,
                   "the radius barely changes along the axis (the apex would lie more than " +
                       std::to_string(static_cast<int>(kMaxApexDistance)) +
                       " times the height away); fit a cylinder instead");
  }
  // A given height moves the base plane along the fitted generator.
  const double radius =
      options.height ? std::abs(slope) * *options.height : intercept + slope * h_base;
  if (!(radius > kZeroRelative * local->diagonal)) {
    return invalid(kKind, "the points do not narrow towards an apex");
  }
  if (options.axis && options.keep_axis_sign && !apex_up) {
    return invalid(kKind,
                   "the points widen towards the given axis' tip, but the axis must point from the "
                   "base towards the apex (reverse it)");
  }
  ConeParams c;
  c.axis = apex_up ? f.axis : -f.axis;
  c.apex = axis_point(f, *local, h_apex);
  c.height = options.height ? *options.height : std::abs(h_apex - h_base);
  c.radius = radius;
  c.axis = tidy(c.axis);
  c.equator = tidy(equator_for(c.axis));
  return c;
}

Expected<DiskParams> fit_disk(std::span<const Float3> input, const FitOptions& options) {
  constexpr const char* kKind = "disk";
  auto local = prepare_points(input, kKind);
  if (!local) return local.error();
  auto up = unit_direction(options.up, kKind, "up");
  if (!up) return up.error();
  auto frame = plane_frame(*local, options, *up, kKind);
  if (!frame) return frame.error();
  // Collinear points have a "minimum enclosing circle" too, but no plane:
  // the rectangle's width tells.
  auto sides = min_rectangle_sides(*frame, local->diagonal, kKind);
  if (!sides) return sides.error();
  const PlaneFrame& f = *frame;
  if (options.anchor) {
    // A given centre: the radius reaches the farthest point in the plane.
    const Vec3 center = *options.anchor - local->offset;
    double r2 = 0;
    for (const K::Point_3& q : local->points) {
      const Vec3 w = to_vec(q) - center;
      const Vec3 in_plane = w - f.normal * dot(w, f.normal);
      r2 = std::max(r2, dot(in_plane, in_plane));
    }
    if (!(std::sqrt(r2) > kZeroRelative * local->diagonal)) {
      return invalid(kKind, "every point lies on the normal through the given centre");
    }
    DiskParams d;
    d.center = *options.anchor;
    d.normal = tidy(f.normal);
    d.equator = tidy(f.basis.e1);
    d.radius = std::sqrt(r2);
    return d;
  }
  const Circle circle = min_enclosing_circle(f.hull, f.projected);
  DiskParams d;
  d.center = f.origin + f.basis.e1 * circle.x + f.basis.e2 * circle.y;
  d.normal = tidy(f.normal);
  d.equator = tidy(f.basis.e1);  // = equator_for(normal)
  d.radius = circle.radius;
  return d;
}

Expected<QuadParams> fit_quad(std::span<const Float3> input, const FitOptions& options) {
  auto corners = fit_rectangle(input, options, "quad");
  if (!corners) return corners.error();
  return QuadParams{*corners};
}

Expected<PlaneParams> fit_plane(std::span<const Float3> input, const FitOptions& options) {
  auto corners = fit_rectangle(input, options, "plane");
  if (!corners) return corners.error();
  const auto& p = *corners;
  if (!options.anchor) return PlaneParams{p[0], p[1] - p[0], p[3] - p[0]};
  // A given origin: the fitted rectangle's directions, lengths reaching the
  // farthest point (points on the origin's negative side clamp).
  const Vec3 origin = *options.anchor;
  const Vec3 u = normalize(p[1] - p[0]), v = normalize(p[3] - p[0]);
  double u_len = 0, v_len = 0;
  for (const Float3& q : input) {
    const Vec3 w = Vec3{q.x, q.y, q.z} - origin;
    u_len = std::max(u_len, dot(w, u));
    v_len = std::max(v_len, dot(w, v));
  }
  const double zero = kZeroRelative * length(p[2] - p[0]);
  if (!(u_len > zero) || !(v_len > zero)) {
    return invalid("plane", std::string("no point lies on the positive ") +
                                (u_len > zero ? "v" : "u") +
                                " side of the given origin (the fitted axes would have no length)");
  }
  return PlaneParams{origin, u * u_len, v * v_len};
}

Expected<ProxyParams> fit_proxy(ProxyKind kind, std::span<const Float3> points,
                                const FitOptions& options) {
  auto widen = [](auto result) -> Expected<ProxyParams> {
    if (!result) return result.error();
    return ProxyParams{std::move(*result)};
  };
  switch (kind) {
    case ProxyKind::kSphere:
      return widen(fit_sphere(points, options));
    case ProxyKind::kCylinder:
      return widen(fit_cylinder(points, options));
    case ProxyKind::kCone:
      return widen(fit_cone(points, options));
    case ProxyKind::kDisk:
      return widen(fit_disk(points, options));
    case ProxyKind::kQuad:
      return widen(fit_quad(points, options));
    case ProxyKind::kPlane:
      return widen(fit_plane(points, options));
  }
  return make_error(ErrorCode::kInternal, "fit_proxy: unknown proxy kind");
}

Expected<ProxyParams> fit_proxy(ProxyKind kind, const MeshData& mesh, const FitOptions& options) {
  const std::vector<Float3> points = fit_points(mesh);
  return fit_proxy(kind, points, options);
}

}  // namespace texbake
