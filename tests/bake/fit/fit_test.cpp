// Tests of bake/fit/fit_proxy.h (SPEC section 6).
//
// Synthetic shapes: points sampled (seeded) on a known sphere, cylinder,
// cone, disk or rectangle, each displaced by noise uniform in a ball whose
// radius is 1% of the shape's radius (rectangle: of half its shorter side).
// The fitted parameters must come back within 1% of the shape's size (its
// largest dimension) and 1 degree of direction. The fits enclose the points,
// so noise biases sizes outwards by up to the noise radius; the shapes below
// keep that under 1%.
//
// Real meshes: the minimum enclosing sphere of every mesh in the shared data
// folder is checked against Welzl's algorithm, written here independently of
// CGAL.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bake/fit/fit_proxy.h"
#include "mapping/proxy.h"

namespace texbake {
namespace {

constexpr double kPi = std::numbers::pi;

double degrees_between(Vec3 a, Vec3 b) {
  const double c = dot(normalize(a), normalize(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180 / kPi;
}

Vec3 to_vec(Float3 f) {
  return {f.x, f.y, f.z};
}

// Two unit vectors perpendicular to unit `n` and to each other, e1 x e2 = n.
// (Deliberately not the fit's equator rule: any frame will do here.)
std::pair<Vec3, Vec3> any_frame(Vec3 n) {
  const Vec3 helper = std::abs(n.z) < 0.9 ? Vec3{0, 0, 1} : Vec3{1, 0, 0};
  const Vec3 e1 = normalize(cross(helper, n));
  return {e1, cross(n, e1)};
}

constexpr int kSamples = 141 * 141;

class Sampler {
 public:
  explicit Sampler(unsigned seed) : rng_(seed) {}
  double uniform(double lo = 0, double hi = 1) {
    return std::uniform_real_distribution<double>(lo, hi)(rng_);
  }
  Vec3 unit_vector() {
    std::normal_distribution<double> g;
    Vec3 v;
    do v = {g(rng_), g(rng_), g(rng_)};
    while (length(v) < 1e-9);
    return normalize(v);
  }
  // Uniform in the ball of radius r.
  Vec3 ball(double r) { return unit_vector() * (r * std::cbrt(uniform())); }
  // Sample i of kSamples in [0,1)^2, one per cell of a kGrid x kGrid grid
  // (jittered stratification). Meshes sample their surface evenly; i.i.d.
  // samples would add covariance noise that turns a cylinder's axis by about
  // 1 degree at 20,000 points, which is the sampler's fault, not the fit's.
  std::array<double, 2> stratified(int i) {
    return {(i % kGrid + uniform()) / kGrid, (i / kGrid + uniform()) / kGrid};
  }
  static constexpr int kGrid = 141;

 private:
  std::mt19937 rng_;
};

std::vector<Float3> to_floats(const std::vector<Vec3>& points) {
  std::vector<Float3> out;
  for (const Vec3& p : points) {
    out.push_back({static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)});
  }
  return out;
}

std::vector<Float3> sample_sphere(Vec3 center, double r, double noise, unsigned seed) {
  Sampler s(seed);
  std::vector<Vec3> p;
  for (int i = 0; i < kSamples; ++i) {
    const auto [a, b] = s.stratified(i);  // area-uniform: z uniform, azimuth uniform
    const double z = 2 * b - 1, ring = std::sqrt(1 - z * z), phi = 2 * kPi * a;
    p.push_back(center + Vec3{ring * std::cos(phi), ring * std::sin(phi), z} * r + s.ball(noise));
  }
  return to_floats(p);
}

// Lateral surface, area-uniform.
std::vector<Float3> sample_cylinder(Vec3 base, Vec3 axis, double r, double h, double noise,
                                    unsigned seed) {
  Sampler s(seed);
  const auto [e1, e2] = any_frame(axis);
  std::vector<Vec3> p;
  for (int i = 0; i < kSamples; ++i) {
    const auto [sa, sh] = s.stratified(i);
    const double a = 2 * kPi * sa;
    p.push_back(base + axis * (h * sh) + (e1 * std::cos(a) + e2 * std::sin(a)) * r + s.ball(noise));
  }
  return to_floats(p);
}

// Lateral surface, area-uniform: the distance t from the apex along the axis
// has density proportional to t, so t = H sqrt(U).
std::vector<Float3> sample_cone(Vec3 apex, Vec3 axis, double radius, double height, double noise,
                                unsigned seed) {
  Sampler s(seed);
  const auto [e1, e2] = any_frame(axis);
  std::vector<Vec3> p;
  for (int i = 0; i < kSamples; ++i) {
    const auto [sa, st] = s.stratified(i);
    const double t = height * std::sqrt(st);
    const double a = 2 * kPi * sa;
    p.push_back(apex - axis * t + (e1 * std::cos(a) + e2 * std::sin(a)) * (radius * t / height) +
                s.ball(noise));
  }
  return to_floats(p);
}

std::vector<Float3> sample_disk(Vec3 center, Vec3 normal, double r, double noise, unsigned seed) {
  Sampler s(seed);
  const auto [e1, e2] = any_frame(normal);
  std::vector<Vec3> p;
  for (int i = 0; i < kSamples; ++i) {
    const auto [sa, sr] = s.stratified(i);
    const double rho = r * std::sqrt(sr);
    const double a = 2 * kPi * sa;
    p.push_back(center + (e1 * std::cos(a) + e2 * std::sin(a)) * rho + s.ball(noise));
  }
  return to_floats(p);
}

// The rectangle p00 + s du + t dv, s, t in [0, 1].
std::vector<Float3> sample_rectangle(Vec3 p00, Vec3 du, Vec3 dv, double noise, unsigned seed) {
  Sampler s(seed);
  std::vector<Vec3> p;
  for (int i = 0; i < kSamples; ++i) {
    const auto [a, b] = s.stratified(i);
    p.push_back(p00 + du * a + dv * b + s.ball(noise));
  }
  return to_floats(p);
}

void expect_near_vec(Vec3 got, Vec3 want, double tol, const char* what) {
  EXPECT_LE(length(got - want), tol)
      << what << ": got (" << got.x << ", " << got.y << ", " << got.z << "), want (" << want.x
      << ", " << want.y << ", " << want.z << ")";
}

void expect_valid_proxy(const ProxyParams& params) {
  auto proxy = make_proxy(params);
  EXPECT_TRUE(proxy.has_value()) << (proxy ? "" : proxy.error().message);
}

// ---- Sphere. ----------------------------------------------------------------

TEST(FitSphere, NoisySphereComesBackWithinOnePercent) {
  const Vec3 center{3, -1, 2};
  const double r = 2, size = 2 * r;
  const auto points = sample_sphere(center, r, 0.01 * r, 1);
  auto fit = fit_sphere(points);
  ASSERT_TRUE(fit) << fit.error().message;
  expect_near_vec(fit->center, center, 0.01 * size, "center");
  EXPECT_NEAR(fit->radius, r, 0.01 * size);
  // Default up is +Z: pole +Z, equator +X (SPEC section 1's default).
  EXPECT_EQ(fit->pole, (Vec3{0, 0, 1}));
  ASSERT_TRUE(fit->equator);
  EXPECT_EQ(*fit->equator, (Vec3{1, 0, 0}));
  expect_valid_proxy(*fit);
}

TEST(FitSphere, PoleFollowsUpAndEquatorSkipsParallelAxes) {
  const auto points = sample_sphere({0, 0, 0}, 1, 0, 2);
  FitOptions options;
  options.up = {-2, 0, 0};  // -X: +X is parallel, so the equator is +Y
  auto fit = fit_sphere(points, options);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_EQ(fit->pole, (Vec3{-1, 0, 0}));
  EXPECT_EQ(*fit->equator, (Vec3{0, 1, 0}));
}

TEST(FitSphere, FourPointsOnARegularTetrahedron) {
  // The vertices of a regular tetrahedron inscribed in the unit sphere: the
  // minimum enclosing sphere is that sphere (by symmetry, worked by hand).
  const std::vector<Float3> points = {
      {1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};  // circumradius sqrt(3)
  auto fit = fit_sphere(points);
  ASSERT_TRUE(fit) << fit.error().message;
  expect_near_vec(fit->center, {0, 0, 0}, 1e-12, "center");
  EXPECT_NEAR(fit->radius, std::sqrt(3.0), 1e-12);
}

// ---- Welzl's minimum enclosing ball, the independent reference. -------------
// Randomised incremental form (Welzl 1991; the nested-loop "minidisk" version
// of de Berg et al., Computational Geometry, section 4.7, lifted to 3D).

struct Ball {
  Vec3 c;
  double r2 = 0;
};

bool outside(const Ball& b, Vec3 p) {
  const Vec3 d = p - b.c;
  return dot(d, d) > b.r2 * (1 + 1e-10) + 1e-300;
}

Ball ball2(Vec3 a, Vec3 b) {
  const Vec3 c = (a + b) * 0.5;
  return {c, dot(a - c, a - c)};
}

Ball ball3(Vec3 a, Vec3 b, Vec3 c) {
  // Circumcircle of the triangle, in its plane.
  const Vec3 ab = b - a, ac = c - a, n = cross(ab, ac);
  const double n2 = dot(n, n);
  if (n2 < 1e-24 * dot(ab, ab) * dot(ac, ac)) {  // collinear: the longest pair
    Ball best = ball2(a, b);
    for (const Ball& x : {ball2(a, c), ball2(b, c)}) best = x.r2 > best.r2 ? x : best;
    return best;
  }
  const Vec3 off = (cross(n, ab) * dot(ac, ac) + cross(ac, n) * dot(ab, ab)) / (2 * n2);
  return {a + off, dot(off, off)};
}

Ball ball4(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  // Circumsphere: 2 (q - a) . x = |q - a|^2 for q = b, c, d (x = centre - a),
  // solved by Cramer's rule.
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double det = 2 * dot(u, cross(v, w));
  if (std::abs(det) < 1e-18 * length(u) * length(v) * length(w)) {  // coplanar
    Ball best = ball3(a, b, c);
    for (const Ball& x : {ball3(a, b, d), ball3(a, c, d), ball3(b, c, d)}) {
      if (x.r2 > best.r2) best = x;
    }
    return best;
  }
  const Vec3 x =
      (cross(v, w) * dot(u, u) + cross(w, u) * dot(v, v) + cross(u, v) * dot(w, w)) / det;
  return {a + x, dot(x, x)};
}

Ball welzl(std::vector<Vec3> p) {
  std::shuffle(p.begin(), p.end(), std::mt19937(7));
  Ball b{p[0], 0};
  for (std::size_t i = 1; i < p.size(); ++i) {
    if (!outside(b, p[i])) continue;
    b = ball2(p[i], p[0]);
    for (std::size_t j = 1; j < i; ++j) {
      if (!outside(b, p[j])) continue;
      b = ball2(p[i], p[j]);
      for (std::size_t k = 0; k < j; ++k) {
        if (!outside(b, p[k])) continue;
        b = ball3(p[i], p[j], p[k]);
        for (std::size_t l = 0; l < k; ++l) {
          if (outside(b, p[l])) b = ball4(p[i], p[j], p[k], p[l]);
        }
      }
    }
  }
  return b;
}

// A minimal OFF reader for the test data (the project's mesh reader lives in
// mesh_io and is tested there; this keeps the fit test independent of it).
// Handles "OFF" on its own line, '#' comments and blank lines, polygon faces.
MeshData read_off(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string text, line;
  while (std::getline(in, line)) {
    text += line.substr(0, line.find('#'));
    text += '\n';
  }
  std::istringstream s(text);
  std::string magic;
  std::size_t nv = 0, nf = 0, ne = 0;
  s >> magic >> nv >> nf >> ne;
  MeshData mesh;
  if (magic != "OFF" || !s) return mesh;
  mesh.positions.resize(nv);
  for (Float3& p : mesh.positions) s >> p.x >> p.y >> p.z;
  mesh.face_offsets.push_back(0);
  for (std::size_t f = 0; f < nf && s; ++f) {
    std::size_t k = 0;
    s >> k;
    for (std::size_t c = 0; c < k; ++c) {
      uint32_t v = 0;
      s >> v;
      mesh.face_vertices.push_back(v);
    }
    mesh.face_offsets.push_back(static_cast<uint32_t>(mesh.face_vertices.size()));
  }
  if (!s) mesh.positions.clear();
  return mesh;
}

TEST(FitSphere, EnclosesEveryDataMeshAndIsMinimal) {
  int meshes = 0;
  for (const auto& entry : std::filesystem::directory_iterator(TEXBAKE_DATA_DIR)) {
    if (entry.path().extension() != ".off") continue;
    SCOPED_TRACE(entry.path().filename().string());
    const MeshData mesh = read_off(entry.path());
    ASSERT_FALSE(mesh.positions.empty()) << "could not read the test mesh";
    ++meshes;
    auto fit = fit_proxy(ProxyKind::kSphere, mesh);
    ASSERT_TRUE(fit) << fit.error().message;
    const auto& s = std::get<SphereParams>(*fit);

    std::vector<Vec3> used;
    std::vector<char> referenced(mesh.positions.size(), 0);
    for (uint32_t v : mesh.face_vertices) referenced[v] = 1;
    for (std::size_t i = 0; i < referenced.size(); ++i) {
      if (referenced[i]) used.push_back(to_vec(mesh.positions[i]));
    }
    double worst = 0;
    for (const Vec3& p : used) worst = std::max(worst, length(p - s.center));
    EXPECT_LE(worst, s.radius * (1 + 1e-12)) << "a vertex lies outside the fitted sphere";

    const Ball ref = welzl(used);
    const double ref_r = std::sqrt(ref.r2);
    for (const Vec3& p : used) ASSERT_FALSE(outside(ref, p)) << "Welzl's ball is wrong";
    EXPECT_LE(s.radius, 1.01 * ref_r);
    EXPECT_GE(s.radius, ref_r * (1 - 1e-9));  // nothing enclosing is smaller than the minimum
    expect_valid_proxy(*fit);
  }
  EXPECT_GE(meshes, 6);
}

// ---- Cylinder. --------------------------------------------------------------

struct CylinderCase {
  Vec3 base, axis;  // axis unit, into the up (+Z) hemisphere
  double r, h;
};

void check_cylinder(const CylinderCase& c, unsigned seed, const FitOptions& options = {}) {
  const double size = std::max(2 * c.r, c.h);
  const auto points = sample_cylinder(c.base, c.axis, c.r, c.h, 0.01 * c.r, seed);
  auto fit = fit_cylinder(points, options);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_LE(degrees_between(fit->axis, c.axis), 1.0);
  EXPECT_NEAR(fit->radius, c.r, 0.01 * size);
  EXPECT_NEAR(fit->height, c.h, 0.01 * size);
  expect_near_vec(fit->base, c.base, 0.01 * size, "base");
  ASSERT_TRUE(fit->equator);
  EXPECT_NEAR(dot(*fit->equator, fit->axis), 0, 1e-12);
  // Encloses: every point within the radius of the axis, between the caps.
  const Vec3 a = normalize(fit->axis);
  for (const Float3& f : points) {
    const Vec3 w = to_vec(f) - fit->base;
    const double h = dot(w, a);
    ASSERT_LE(length(w - a * h), fit->radius * (1 + 1e-9));
    ASSERT_GE(h, -1e-9 * size);
    ASSERT_LE(h, fit->height + 1e-9 * size);
  }
  expect_valid_proxy(*fit);
}

TEST(FitCylinder, TallNoisyCylinderAxisIsTheLargestPrincipalDirection) {
  check_cylinder({{1, 2, 3}, normalize(Vec3{0.3, -0.2, 1}), 1, 3}, 11);
}

TEST(FitCylinder, SquatNoisyCylinderAxisIsTheSmallestPrincipalDirection) {
  // A tin: height < diameter, so the axis has the smallest variance.
  check_cylinder({{-1, 0, 0.5}, normalize(Vec3{0.1, 0.4, 1}), 1.5, 1}, 12);
}

TEST(FitCylinder, AxisIntoTheUpHemisphere) {
  // A bottle lying along -X; with up = +X its axis must come back as +X, base
  // at the low-x end.
  FitOptions options;
  options.up = {1, 0, 0};
  check_cylinder({{-2, 0, 0}, {1, 0, 0}, 0.5, 3}, 13, options);
}

TEST(FitCylinder, GivenAxisIsKept) {
  // Points of a tilted cylinder, but the axis is forced to +Z: the fit keeps
  // it and encloses the points around it.
  const auto points = sample_cylinder({0, 0, 0}, normalize(Vec3{0, 0.2, 1}), 1, 3, 0, 14);
  FitOptions options;
  options.axis = Vec3{0, 0, -2};
  auto fit = fit_cylinder(points, options);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_EQ(fit->axis, (Vec3{0, 0, -1}));
  for (const Float3& f : points) {
    const Vec3 w = to_vec(f) - fit->base;
    const double h = -w.z;
    ASSERT_GE(h, -1e-9);
    ASSERT_LE(h, fit->height + 1e-9);
    ASSERT_LE(std::hypot(w.x, w.y), fit->radius * (1 + 1e-9));
  }
}

// ---- Cone. ------------------------------------------------------------------

struct ConeCase {
  Vec3 apex, axis;  // axis unit, from base towards apex
  double radius, height;
};

void check_cone(const ConeCase& c, double noise_fraction, unsigned seed,
                const FitOptions& options = {}) {
  const double size = std::max(2 * c.radius, c.height);
  const auto points =
      sample_cone(c.apex, c.axis, c.radius, c.height, noise_fraction * c.radius, seed);
  auto fit = fit_cone(points, options);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_LE(degrees_between(fit->axis, c.axis), 1.0);
  expect_near_vec(fit->apex, c.apex, 0.01 * size, "apex");
  EXPECT_NEAR(fit->height, c.height, 0.01 * size);
  EXPECT_NEAR(fit->radius, c.radius, 0.01 * size);
  // The cone follows the middle of the noise (fit_proxy.h): no point lies
  // beyond the base plane, none further than twice the noise outside the
  // lateral surface. In the (depth t below the apex, radius rho) half-plane
  // the generator runs from (0, 0) to (height, radius).
  const Vec3 a = normalize(fit->axis);
  const double slant = std::hypot(fit->height, fit->radius);
  for (const Float3& f : points) {
    const double t = dot(fit->apex - to_vec(f), a);
    const double rho = length((fit->apex - a * t) - to_vec(f));
    ASSERT_LE(t, fit->height + 1e-9 * size);
    ASSERT_LE((rho * fit->height - t * fit->radius) / slant,
              2 * noise_fraction * c.radius + 1e-6 * size);
  }
  expect_valid_proxy(*fit);
}

TEST(FitCone, WideNoisyConeApexUp) {
  // Radius 2, height 1.5 (half-angle 53 degrees): the axis is the smallest
  // principal direction.
  check_cone({{0.5, -1, 2}, normalize(Vec3{0.2, 0.1, 1}), 2, 1.5}, 0.01, 21);
}

TEST(FitCone, NoisyConeApexDownKeepsAxisTowardsTheApex) {
  // A lampshade hanging upside down: the axis points down, whatever up says.
  check_cone({{0, 0, -1}, normalize(Vec3{0.1, 0, -1}), 1.5, 2}, 0.01, 22);
}

TEST(FitCone, SlenderConeAxisIsTheLargestPrincipalDirection) {
  // Radius 1, height 4: the axis has the largest variance.
  check_cone({{1, 1, 5}, normalize(Vec3{-0.2, 0.3, 1}), 1, 4}, 0.01, 23);
}

TEST(FitCone, GivenAxisWithTheRightSignIsKept) {
  FitOptions options;
  options.axis = Vec3{0, 0, 3};
  check_cone({{0, 0, 2}, {0, 0, 1}, 1.5, 2}, 0.01, 24, options);
}

TEST(FitCone, GivenAxisPointingToTheBaseIsAnError) {
  const auto points = sample_cone({0, 0, 2}, {0, 0, 1}, 1.5, 2, 0, 25);
  FitOptions options;
  options.axis = Vec3{0, 0, -1};
  auto fit = fit_cone(points, options);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(fit.error().message.find("reverse"), std::string::npos) << fit.error().message;
  // Only the line fixed (the --up shorthand): the fit finds the apex side.
  options.keep_axis_sign = false;
  auto free_sign = fit_cone(points, options);
  ASSERT_TRUE(free_sign) << free_sign.error().message;
  EXPECT_NEAR(free_sign->axis.z, 1, 1e-12);
}

TEST(FitCone, CylinderIsNotACone) {
  const auto points = sample_cylinder({0, 0, 0}, {0, 0, 1}, 1, 3, 0, 26);
  FitOptions options;
  options.axis = Vec3{0, 0, 1};
  auto fit = fit_cone(points, options);
  ASSERT_FALSE(fit);
  EXPECT_EQ(fit.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(fit.error().message.find("cylinder"), std::string::npos) << fit.error().message;
}

// ---- Disk. ------------------------------------------------------------------

TEST(FitDisk, NoisyDiskComesBackWithinOnePercent) {
  const Vec3 center{1, 2, -3}, normal = normalize(Vec3{0.3, -0.5, 1});
  const double r = 2, size = 2 * r;
  const auto points = sample_disk(center, -normal, r, 0.01 * r, 31);  // sampled with -normal
  auto fit = fit_disk(points);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_LE(degrees_between(fit->normal, normal), 1.0);  // flipped into the up hemisphere
  expect_near_vec(fit->center, center, 0.01 * size, "center");
  EXPECT_NEAR(fit->radius, r, 0.01 * size);
  ASSERT_TRUE(fit->equator);
  EXPECT_NEAR(dot(*fit->equator, fit->normal), 0, 1e-12);
  for (const Float3& f : points) {
    const Vec3 w = to_vec(f) - fit->center;
    ASSERT_LE(length(w - fit->normal * dot(w, fit->normal)), fit->radius * (1 + 1e-9));
  }
  expect_valid_proxy(*fit);
}

TEST(FitDisk, HorizontalDiskHasTheDefaultFrame) {
  const auto points = sample_disk({0, 0, 0}, {0, 0, 1}, 1, 0, 32);
  auto fit = fit_disk(points);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_NEAR(fit->normal.z, 1, 1e-9);
  EXPECT_NEAR(fit->equator->x, 1, 1e-9);  // +X made perpendicular to a normal ~ +Z
}

// ---- Quad and plane. --------------------------------------------------------

struct RectangleCase {
  Vec3 p00, du, dv;  // the expected corner order: u right, v up, du x dv towards the viewer
};

// Checks corners p00, p10, p11, p01 against the case, and enclosure of the
// points projected on the quad's plane.
void check_rectangle(const RectangleCase& c, const std::vector<Float3>& points,
                     const FitOptions& options = {}) {
  const double size = length(c.du + c.dv);
  const std::array<Vec3, 4> want = {c.p00, c.p00 + c.du, c.p00 + c.du + c.dv, c.p00 + c.dv};
  auto quad = fit_quad(points, options);
  ASSERT_TRUE(quad) << quad.error().message;
  const char* names[] = {"p00", "p10", "p11", "p01"};
  for (int i = 0; i < 4; ++i) expect_near_vec(quad->corners[i], want[i], 0.01 * size, names[i]);
  expect_valid_proxy(*quad);

  auto plane = fit_plane(points, options);
  ASSERT_TRUE(plane) << plane.error().message;
  expect_near_vec(plane->origin, c.p00, 0.01 * size, "origin");
  expect_near_vec(plane->u_axis, c.du, 0.01 * size, "u_axis");
  expect_near_vec(plane->v_axis, c.dv, 0.01 * size, "v_axis");
  EXPECT_NEAR(dot(plane->u_axis, plane->v_axis), 0, 1e-9 * size * size);
  // Not mirrored: seen from the normal's tip, u to the right of v.
  EXPECT_GT(dot(cross(plane->u_axis, plane->v_axis), cross(c.du, c.dv)), 0);
  for (const Float3& f : points) {
    const Vec3 w = to_vec(f) - plane->origin;
    const double u = dot(w, plane->u_axis) / dot(plane->u_axis, plane->u_axis);
    const double v = dot(w, plane->v_axis) / dot(plane->v_axis, plane->v_axis);
    ASSERT_GE(u, -1e-9);
    ASSERT_LE(u, 1 + 1e-9);
    ASSERT_GE(v, -1e-9);
    ASSERT_LE(v, 1 + 1e-9);
  }
  expect_valid_proxy(*plane);
}

TEST(FitQuad, NoisyWallRectangleHasVAlongUp) {
  // A 4 x 2.5 rectangle on a wall facing (cos 30, sin 30, 0), its sides
  // rotated 20 degrees in the wall: v is the side closest to +Z, u = v x n.
  const Vec3 n{std::cos(kPi / 6), std::sin(kPi / 6), 0};
  const Vec3 horizontal = cross(Vec3{0, 0, 1}, n);  // to the right seen from n's tip
  const Vec3 vertical{0, 0, 1};
  const double t = 20 * kPi / 180;
  const Vec3 u = horizontal * std::cos(t) + vertical * std::sin(t);
  const Vec3 v = cross(n, u);
  const RectangleCase c{{2, 1, 0.5}, u * 4, v * 2.5};
  check_rectangle(c, sample_rectangle(c.p00, c.du, c.dv, 0.01 * 1.25, 41));
}

TEST(FitQuad, FloorRectangleHasUAlongX) {
  // Horizontal, sides at 30 degrees from X: u is the side closest to +X
  // (v the one closest to normal x equator = +Y).
  const double t = kPi / 6;
  const Vec3 u{std::cos(t), std::sin(t), 0}, v{-std::sin(t), std::cos(t), 0};
  const RectangleCase c{{-1, -1, 0.2}, u * 2, v * 3};
  check_rectangle(c, sample_rectangle(c.p00, c.du, c.dv, 0.01 * 1, 42));
}

TEST(FitQuad, GivenNormalIsKept) {
  // Seen from below (normal -Z): the image must not be mirrored from there.
  const Vec3 u{-1, 0, 0}, v{0, 1, 0};  // u x v = -Z
  const RectangleCase c{{1, -1, 0}, u * 2, v * 2};
  FitOptions options;
  options.axis = Vec3{0, 0, -1};
  auto quad = fit_quad(sample_rectangle(c.p00, c.du, c.dv, 0, 43), options);
  ASSERT_TRUE(quad) << quad.error().message;
  const Vec3 normal =
      cross(quad->corners[1] - quad->corners[0], quad->corners[3] - quad->corners[0]);
  EXPECT_LT(normal.z, 0);
}

TEST(FitPoints, OnlyReferencedVerticesCount) {
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {100, 100, 100}, {0, 0, 1}};
  mesh.face_offsets = {0, 3, 6};
  mesh.face_vertices = {0, 1, 2, 0, 2, 4};
  const auto points = fit_points(mesh);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(points[3].z, 1.0f);
  auto fit = fit_proxy(ProxyKind::kSphere, mesh);
  ASSERT_TRUE(fit) << fit.error().message;
  EXPECT_LT(std::get<SphereParams>(*fit).radius, 1);  // vertex 3 is ignored

  MeshData cloud;  // no faces: a point cloud uses every vertex
  cloud.positions = mesh.positions;
  EXPECT_EQ(fit_points(cloud).size(), 5u);
}

// ---- Degenerate inputs. -----------------------------------------------------

constexpr ProxyKind kAllKinds[] = {ProxyKind::kSphere, ProxyKind::kCylinder, ProxyKind::kCone,
                                   ProxyKind::kDisk,   ProxyKind::kQuad,     ProxyKind::kPlane};

void expect_error(const Expected<ProxyParams>& fit, ProxyKind kind, const std::string& words) {
  ASSERT_FALSE(fit) << to_string(kind) << ": expected an error mentioning '" << words << "'";
  EXPECT_EQ(fit.error().code, ErrorCode::kInvalidArgument);
  EXPECT_NE(fit.error().message.find(std::string("cannot fit a ") + to_string(kind)),
            std::string::npos)
      << fit.error().message;
  EXPECT_NE(fit.error().message.find(words), std::string::npos) << fit.error().message;
}

TEST(FitDegenerate, NoPoints) {
  for (ProxyKind kind : kAllKinds)
    expect_error(fit_proxy(kind, std::span<const Float3>{}), kind, "no points");
}

TEST(FitDegenerate, OnePoint) {
  const std::vector<Float3> one = {{1, 2, 3}};
  for (ProxyKind kind : kAllKinds) expect_error(fit_proxy(kind, one), kind, "only one point");
}

TEST(FitDegenerate, CoincidentPoints) {
  const std::vector<Float3> same(50, Float3{1, 2, 3});
  for (ProxyKind kind : kAllKinds) expect_error(fit_proxy(kind, same), kind, "50 points coincide");
}

TEST(FitDegenerate, NonFinitePoint) {
  std::vector<Float3> points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  points[1].y = std::nanf("");
  for (ProxyKind kind : kAllKinds)
    expect_error(fit_proxy(kind, points), kind, "point 1 is not finite");
}

TEST(FitDegenerate, CollinearPoints) {
  std::vector<Float3> line;
  for (int i = 0; i < 100; ++i) line.push_back({0.1f * i, 0.2f * i, 0.3f * i + 1});
  for (ProxyKind kind : {ProxyKind::kDisk, ProxyKind::kQuad, ProxyKind::kPlane}) {
    expect_error(fit_proxy(kind, line), kind, "collinear");
  }
  for (ProxyKind kind : {ProxyKind::kCylinder, ProxyKind::kCone}) {
    expect_error(fit_proxy(kind, line), kind, "lie on the axis");
  }
  // A sphere around a segment is fine: its diameter is the segment.
  auto sphere = fit_sphere(line);
  ASSERT_TRUE(sphere) << sphere.error().message;
  EXPECT_NEAR(sphere->radius, 0.5 * std::sqrt(9.9 * 9.9 + 19.8 * 19.8 + 29.7 * 29.7), 1e-5);
}

TEST(FitDegenerate, NoExtentAlongTheAxis) {
  // A flat disk fitted as a cylinder or cone: its symmetry axis is the
  // normal, along which it has no extent.
  const auto flat = sample_disk({0, 0, 0}, {0, 0, 1}, 1, 0, 51);
  for (ProxyKind kind : {ProxyKind::kCylinder, ProxyKind::kCone}) {
    expect_error(fit_proxy(kind, flat), kind, "no extent along the axis");
  }
}

TEST(FitDegenerate, ZeroDirections) {
  const auto points = sample_sphere({0, 0, 0}, 1, 0, 52);
  FitOptions zero_up;
  zero_up.up = {0, 0, 0};
  for (ProxyKind kind : kAllKinds)
    expect_error(fit_proxy(kind, points, zero_up), kind, "up is the zero vector");
  FitOptions zero_axis;
  zero_axis.axis = Vec3{0, 0, 0};
  expect_error(fit_proxy(ProxyKind::kCylinder, points, zero_axis), ProxyKind::kCylinder,
               "axis is the zero vector");
  expect_error(fit_proxy(ProxyKind::kDisk, points, zero_axis), ProxyKind::kDisk,
               "normal is the zero vector");
}

}  // namespace
}  // namespace texbake
