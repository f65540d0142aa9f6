// The camera projector's mathematics (mapping/camera.h) against values
// worked out by hand (PINHOLE, the turning points, the look-at frame) and
// against OpenCV's projectPoints / fisheye.projectPoints (expected values
// made by tests/mapping/camera_opencv_expected.py, kept in
// camera_opencv_expected.inc), and every pose form against every other.
#include "mapping/camera.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace texbake {
namespace {

struct OpenCvCase {
  std::string model;
  std::vector<double> params;
  std::vector<std::array<double, 5>> points;  // X, Y, Z, x, y
};
#include "tests/mapping/camera_opencv_expected.inc"

CameraProjector make_camera(CameraModel model, std::vector<double> params, int w, int h,
                            CameraPose pose = {}) {
  Expected<CameraProjector> c = CameraProjector::make({model, w, h, std::move(params), pose});
  EXPECT_TRUE(c) << c.error().message;
  return std::move(c).value();
}

TEST(CameraProjector, PinholeByHand) {
  // Identity pose; (0.2, -0.1, 2) -> a = 0.1, b = -0.05 -> x = 1000 * 0.1 +
  // 640 = 740, y = 900 * -0.05 + 360 = 315; (u, v) = (740 / 1280, 1 - 315 / 720).
  const CameraProjector c = make_camera(CameraModel::kPinhole, {1000, 900, 640, 360}, 1280, 720);
  const CameraProjection p = c.project({0.2, -0.1, 2});
  EXPECT_TRUE(p.inside);
  EXPECT_DOUBLE_EQ(p.pixel.x, 740);
  EXPECT_DOUBLE_EQ(p.pixel.y, 315);
  EXPECT_DOUBLE_EQ(p.uv.u, 740.0 / 1280);
  EXPECT_DOUBLE_EQ(p.uv.v, 1 - 315.0 / 720);
  EXPECT_DOUBLE_EQ(p.depth, 2);
  // The principal point's pixel centre convention: the top-left pixel's
  // centre (0.5, 0.5) is (u, v) = (0.5 / W, 1 - 0.5 / H), SPEC section 1's
  // texel centre of column 0, row 0.
  const CameraProjection corner = c.project({(0.5 - 640) / 1000 * 3, (0.5 - 360) / 900 * 3, 3});
  EXPECT_NEAR(corner.pixel.x, 0.5, 1e-12);
  EXPECT_NEAR(corner.pixel.y, 0.5, 1e-12);
  EXPECT_NEAR(corner.uv.u * 1280 - 0.5, 0, 1e-9);       // x = u W - 0.5 = 0
  EXPECT_NEAR((1 - corner.uv.v) * 720 - 0.5, 0, 1e-9);  // y = (1 - v) H - 0.5 = 0
  const CameraProjector s = make_camera(CameraModel::kSimplePinhole, {1000, 640, 360}, 1280, 720);
  EXPECT_DOUBLE_EQ(s.project({0.2, -0.1, 2}).pixel.y, 310);  // f = 1000 on both axes
}

TEST(CameraProjector, OutsideBehindBeyondTheImageAndPastTheTurningPoint) {
  const CameraProjector c = make_camera(CameraModel::kPinhole, {1000, 1000, 640, 360}, 1280, 720);
  EXPECT_FALSE(c.project({0, 0, -1}).inside);
  EXPECT_FALSE(c.project({0, 0, 0}).inside);
  EXPECT_FALSE(c.project({0.7, 0, 1}).inside);    // x = 1340 > 1280
  EXPECT_FALSE(c.project({0, -0.37, 1}).inside);  // y = -10 < 0
  EXPECT_TRUE(c.project({0.639, 0.359, 1}).inside);
  EXPECT_EQ(c.max_radius2(), INFINITY);

  // SIMPLE_RADIAL k = -0.5: r_d = r (1 - 0.5 r^2) turns where 1 - 1.5 r^2 = 0.
  const CameraProjector sr =
      make_camera(CameraModel::kSimpleRadial, {100, 5000, 5000, -0.5}, 10000, 10000);
  EXPECT_NEAR(sr.max_radius2(), 1 / 1.5, 1e-9);
  EXPECT_TRUE(sr.project({0.8, 0, 1}).inside);    // r^2 = 0.64
  EXPECT_FALSE(sr.project({0.83, 0, 1}).inside);  // r^2 = 0.6889: folded back, though in the image
  // RADIAL k1 = -0.2, k2 = 0.01: 1 - 0.6 s + 0.05 s^2 = 0 at s = 2.
  const CameraProjector ra =
      make_camera(CameraModel::kRadial, {100, 5000, 5000, -0.2, 0.01}, 10000, 10000);
  EXPECT_NEAR(ra.max_radius2(), 2, 1e-9);
  // OPENCV_FISHEYE k1 = -0.3: 1 - 0.9 theta^2 = 0 at theta = sqrt(1 / 0.9).
  const CameraProjector fe =
      make_camera(CameraModel::kOpenCVFisheye, {100, 100, 5000, 5000, -0.3, 0, 0, 0}, 10000, 10000);
  const double r_turn = std::tan(std::sqrt(1 / 0.9));
  EXPECT_NEAR(fe.max_radius2(), r_turn * r_turn, 1e-7);
  // FULL_OPENCV whose denominator never vanishes and numerator keeps growing: no turning point.
  const CameraProjector full = make_camera(
      CameraModel::kFullOpenCV, {100, 100, 50, 50, 0.1, 0.01, 0, 0, 0.001, 0, 0, 0}, 100, 100);
  EXPECT_EQ(full.max_radius2(), INFINITY);
}

TEST(CameraProjector, AgreesWithOpenCvToAMicroPixel) {
  Expected<CameraPose> pose = pose_from_quaternion(
      {kOpenCvQuaternion[0], kOpenCvQuaternion[1], kOpenCvQuaternion[2], kOpenCvQuaternion[3]},
      {kOpenCvTranslation[0], kOpenCvTranslation[1], kOpenCvTranslation[2]}, CameraAxes::kOpenCV,
      "test");
  ASSERT_TRUE(pose) << pose.error().message;
  ASSERT_EQ(kOpenCvCases.size(), 5u);
  for (const OpenCvCase& k : kOpenCvCases) {
    const std::optional<CameraModel> model = camera_model_from_name(k.model);
    ASSERT_TRUE(model) << k.model;
    const CameraProjector c = make_camera(*model, k.params, kOpenCvWidth, kOpenCvHeight, *pose);
    ASSERT_GT(k.points.size(), 40u);
    for (const auto& p : k.points) {
      const CameraProjection got = c.project({p[0], p[1], p[2]});
      EXPECT_NEAR(got.pixel.x, p[3], 1e-6) << k.model;
      EXPECT_NEAR(got.pixel.y, p[4], 1e-6) << k.model;
    }
  }
}

// One camera placed by every pose form: the same pixels, to 1e-9.
TEST(CameraProjector, EveryPoseFormGivesTheSamePixels) {
  // By hand: eye (0, -5, 0) looking at the origin with +z up: forward +y,
  // right = forward x up = +x, down = forward x right = -z. (1, 0, 0.5) is
  // then X = 1, Y = -0.5, Z = 5: a = 0.2, b = -0.1 -> (840, 260).
  Expected<CameraPose> look = pose_from_look_at({0, -5, 0}, {0, 0, 0}, {0, 0, 1}, "look");
  ASSERT_TRUE(look) << look.error().message;
  const std::vector<double> k = {1000, 1000, 640, 360};
  const CameraProjector by_look = make_camera(CameraModel::kPinhole, k, 1280, 720, *look);
  EXPECT_NEAR(by_look.project({1, 0, 0.5}).pixel.x, 840, 1e-9);
  EXPECT_NEAR(by_look.project({1, 0, 0.5}).pixel.y, 260, 1e-9);
  EXPECT_NEAR(length(by_look.centre() - Vec3{0, -5, 0}), 0, 1e-12);

  // A general rotation: a unit quaternion, and the matrix, centre and
  // cam_to_world worked out from it here.
  const double n = std::sqrt(0.7 * 0.7 + 0.1 * 0.1 + 0.5 * 0.5 + 0.3 * 0.3);
  const std::array<double, 4> q = {0.7 / n, 0.1 / n, 0.5 / n, -0.3 / n};
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const std::array<double, 9> r = {
      1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
      2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
      2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
  const Vec3 t{0.4, -0.3, 6};
  const Vec3 centre =
      -Vec3{r[0] * t.x + r[3] * t.y + r[6] * t.z, r[1] * t.x + r[4] * t.y + r[7] * t.z,
            r[2] * t.x + r[5] * t.y + r[8] * t.z};
  // OpenGL axes: the same camera's rotation with its y and z rows negated.
  std::array<double, 9> r_gl = r;
  for (int i = 3; i < 9; ++i) r_gl[i] = -r_gl[i];
  auto c2w = [&](const std::array<double, 9>& rot) {  // columns = rows of rot; last column = centre
    return std::array<double, 16>{rot[0], rot[3],   rot[6], centre.x, rot[1], rot[4],
                                  rot[7], centre.y, rot[2], rot[5],   rot[8], centre.z,
                                  0,      0,        0,      1};
  };
  const Vec3 forward{r[6], r[7], r[8]}, down{r[3], r[4], r[5]};
  std::vector<Expected<CameraPose>> poses;
  poses.push_back(pose_from_quaternion(q, t, CameraAxes::kOpenCV, "q"));
  poses.push_back(pose_from_rotation(r, t, CameraAxes::kOpenCV, "R"));
  poses.push_back(pose_from_centre(centre, r, CameraAxes::kOpenCV, "centre"));
  poses.push_back(pose_from_cam_to_world(c2w(r), CameraAxes::kOpenCV, "c2w"));
  poses.push_back(pose_from_rotation(r_gl, {t.x, -t.y, -t.z}, CameraAxes::kOpenGL, "R gl"));
  poses.push_back(pose_from_centre(centre, r_gl, CameraAxes::kOpenGL, "centre gl"));
  poses.push_back(pose_from_cam_to_world(c2w(r_gl), CameraAxes::kOpenGL, "c2w gl"));
  poses.push_back(pose_from_look_at(centre, centre + forward * 3, -down, "look"));
  // A quaternion of the OpenGL rotation: q times the 180 degree turn about x.
  poses.push_back(
      pose_from_quaternion({-x, w, -z, y}, {t.x, -t.y, -t.z}, CameraAxes::kOpenGL, "q gl"));
  const CameraProjector reference = make_camera(CameraModel::kPinhole, k, 1280, 720, *poses[0]);
  const std::vector<Vec3> points = {{0, 0, 0}, {0.5, -0.2, 0.3}, {-1, 0.7, -0.4}, {0.2, 0.9, 1.1}};
  for (std::size_t i = 0; i < poses.size(); ++i) {
    ASSERT_TRUE(poses[i]) << i << ": " << poses[i].error().message;
    const CameraProjector c = make_camera(CameraModel::kPinhole, k, 1280, 720, *poses[i]);
    EXPECT_NEAR(length(c.centre() - centre), 0, 1e-9) << "pose form " << i;
    for (const Vec3& p : points) {
      const CameraProjection want = reference.project(p), got = c.project(p);
      EXPECT_GT(want.depth, 0);
      EXPECT_NEAR(got.pixel.x, want.pixel.x, 1e-9) << "pose form " << i;
      EXPECT_NEAR(got.pixel.y, want.pixel.y, 1e-9) << "pose form " << i;
      EXPECT_NEAR(got.depth, want.depth, 1e-12) << "pose form " << i;
    }
  }
}

TEST(CameraProjector, BadPosesAndParametersAreErrors) {
  const std::array<double, 9> skew = {1, 0.01, 0, 0, 1, 0, 0, 0, 1};
  const std::array<double, 9> mirror = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
  Expected<CameraPose> a =
      pose_from_rotation(skew, {0, 0, 0}, CameraAxes::kOpenCV, "images.txt line 5");
  ASSERT_FALSE(a);
  EXPECT_NE(a.error().message.find("images.txt line 5"), std::string::npos) << a.error().message;
  EXPECT_NE(a.error().message.find("not orthonormal"), std::string::npos);
  EXPECT_FALSE(pose_from_rotation(mirror, {0, 0, 0}, CameraAxes::kOpenCV, "m"));
  // A quaternion is normalised (COLMAP's rule); only zero or non-finite fails.
  EXPECT_TRUE(pose_from_quaternion({1, 0.01, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "q"));
  EXPECT_TRUE(pose_from_quaternion({1, 1e-7, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "q"));
  EXPECT_FALSE(pose_from_quaternion({NAN, 0, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "q"));
  Expected<CameraPose> zero =
      pose_from_quaternion({0, 0, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "images.txt line 3");
  ASSERT_FALSE(zero);
  EXPECT_EQ(zero.error().message, "images.txt line 3: the quaternion is zero (no rotation)");
  Expected<CameraPose> inf =
      pose_from_quaternion({1, INFINITY, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "q");
  ASSERT_FALSE(inf);
  EXPECT_EQ(inf.error().message, "q: a value is not finite");
  EXPECT_FALSE(pose_from_cam_to_world({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1},
                                      CameraAxes::kOpenCV, "c2w"));
  EXPECT_FALSE(pose_from_look_at({0, 0, 0}, {0, 0, 1}, {0, 0, 2}, "look"));
  EXPECT_FALSE(pose_from_look_at({0, 0, 0}, {0, 0, 0}, {0, 0, 1}, "look"));
  EXPECT_FALSE(pose_from_rotation(skew, {0, INFINITY, 0}, CameraAxes::kOpenCV, "t"));

  Expected<CameraProjector> wrong_count =
      CameraProjector::make({CameraModel::kOpenCV, 100, 100, {1, 1, 50, 50}, {}});
  ASSERT_FALSE(wrong_count);
  EXPECT_EQ(wrong_count.error().message, "OPENCV takes 8 parameters, got 4");
  EXPECT_FALSE(CameraProjector::make({CameraModel::kPinhole, 100, 100, {0, 1, 50, 50}, {}}));
  EXPECT_FALSE(CameraProjector::make({CameraModel::kPinhole, 100, 100, {1, NAN, 50, 50}, {}}));
  EXPECT_FALSE(CameraProjector::make({CameraModel::kPinhole, 0, 100, {1, 1, 50, 50}, {}}));
}

TEST(CameraProjector, BadIntrinsicsAreErrorsWithTheirValue) {
  // Zero, negative and denormal focal lengths (1e-310 < DBL_MIN: 1 / f
  // overflows), non-finite values, principal points off the image.
  const std::vector<std::pair<std::vector<double>, std::string>> cases = {
      {{0, 100, 50, 40}, "PINHOLE: the focal length must be positive (got 0)"},
      {{100, -5, 50, 40}, "PINHOLE: the focal length must be positive (got -5)"},
      {{1e-310, 100, 50, 40}, "PINHOLE: the focal length must be positive (got 1e-310)"},
      {{100, 100, NAN, 40}, "PINHOLE: a camera parameter is not finite"},
      {{INFINITY, 100, 50, 40}, "PINHOLE: a camera parameter is not finite"},
      {{100, 100, -1, 40}, "PINHOLE: the principal point (-1, 40) is outside the 100 x 80 image"},
      {{100, 100, 50, 80.5},
       "PINHOLE: the principal point (50, 80.5) is outside the 100 x 80 image"},
  };
  for (const auto& [params, want] : cases) {
    Expected<CameraProjector> c =
        CameraProjector::make({CameraModel::kPinhole, 100, 80, params, {}});
    ASSERT_FALSE(c) << want;
    EXPECT_EQ(c.error().message, want);
  }
  // The image's corners and DBL_MIN itself are allowed.
  EXPECT_TRUE(CameraProjector::make({CameraModel::kPinhole, 100, 80, {100, 100, 0, 80}, {}}));
  EXPECT_TRUE(CameraProjector::make(
      {CameraModel::kPinhole, 100, 80, {std::numeric_limits<double>::min(), 1, 100, 0}, {}}));
}

TEST(CameraProjector, QuaternionsAreNormalisedAndSixDigitsGiveTheSamePixels) {
  // A general rotation, its quaternion printed with %.6g as some tools
  // write images.txt: |q|^2 differs from 1 by 1.8e-6, so the rotation
  // matrix of q as printed is off orthonormal by about that much (refused
  // as "not orthonormal" before; COLMAP normalises).
  const std::array<double, 4> exact = [] {
    std::array<double, 4> q{0.6293444660151111, 0.33363749783895236, 0.6179714580981894,
                            -0.33275041714161013};
    const double n = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    for (double& v : q) v /= n;
    return q;
  }();
  std::array<double, 4> rounded{};
  double dq2 = 0;
  for (int i = 0; i < 4; ++i) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", exact[i]);
    rounded[i] = std::strtod(buf, nullptr);
    dq2 += (rounded[i] - exact[i]) * (rounded[i] - exact[i]);
  }
  const double norm = std::sqrt(rounded[0] * rounded[0] + rounded[1] * rounded[1] +
                                rounded[2] * rounded[2] + rounded[3] * rounded[3]);
  ASSERT_GT(std::abs(norm * norm - 1), 1.7e-6);  // not a unit quaternion as printed
  const Vec3 t{0.3, -0.2, 4};
  Expected<CameraPose> a = pose_from_quaternion(exact, t, CameraAxes::kOpenCV, "exact");
  Expected<CameraPose> b = pose_from_quaternion(rounded, t, CameraAxes::kOpenCV, "rounded");
  ASSERT_TRUE(a) << a.error().message;
  ASSERT_TRUE(b) << b.error().message;
  // The bound: each component is rounded by at most half a unit in the 6th
  // digit (|dq_i| <= 5e-7 for |q_i| < 1, so |dq| <= 1e-6; measured here as
  // sqrt(dq2)). Normalising moves q by at most 2 |dq| on the unit sphere, and
  // unit quaternions e apart differ by a rotation of 4 asin(e / 2) ~ 2e
  // radians: 4 |dq|. With t kept, X_cam = R X + t moves by (dR - I) R X, at
  // most angle |X| (X the world point), and the pixel f (X/Z, Y/Z) by at
  // most |J| angle |X| with |J| = f / z (1 + a^2 + b^2)^(1/2) <= f / z (1 +
  // r^2) (the projection's Jacobian; to first order, which the bound's
  // rounding up covers).
  const double angle = 4 * std::sqrt(dq2);
  const double f = 1000;
  const CameraProjector ca = make_camera(CameraModel::kPinhole, {f, f, 640, 360}, 1280, 720, *a);
  const CameraProjector cb = make_camera(CameraModel::kPinhole, {f, f, 640, 360}, 1280, 720, *b);
  double worst = 0, worst_bound_ratio = 0;
  int inside = 0;
  for (int i = -4; i <= 4; ++i) {
    for (int j = -3; j <= 3; ++j) {
      // Points in front of camera a, spread over its photo, at depths 2..6.
      const double z = 2 + (i + j + 7) % 5;
      const Vec3 cam{0.6 * i / 4 * z, 0.3 * j / 3 * z, z};
      // World point: X = R^T (cam - t).
      const auto& r = a->r;
      const Vec3 d{cam.x - t.x, cam.y - t.y, cam.z - t.z};
      const Vec3 world{r[0] * d.x + r[3] * d.y + r[6] * d.z, r[1] * d.x + r[4] * d.y + r[7] * d.z,
                       r[2] * d.x + r[5] * d.y + r[8] * d.z};
      const CameraProjection pa = ca.project(world), pb = cb.project(world);
      ASSERT_TRUE(pa.inside);
      ++inside;
      const double moved = std::hypot(pa.pixel.x - pb.pixel.x, pa.pixel.y - pb.pixel.y);
      const double r2 = (cam.x * cam.x + cam.y * cam.y) / (z * z);
      const double dist = length(world);
      const double bound = f * angle * dist / z * (1 + r2);
      worst = std::max(worst, moved);
      worst_bound_ratio = std::max(worst_bound_ratio, moved / bound);
    }
  }
  EXPECT_EQ(inside, 63);
  EXPECT_LE(worst_bound_ratio, 1.0) << "worst " << worst << " px";
  // Measured: 0.00054 px, 0.14 of the bound.
  EXPECT_LT(worst, 0.05);  // at f = 1000: a twentieth of a pixel
}

TEST(CameraProjector, ModelNamesAndColmapIds) {
  // COLMAP src/colmap/sensor/models.h: the ids of cameras.bin.
  const std::vector<std::pair<std::string, int>> colmap = {
      {"SIMPLE_PINHOLE", 0}, {"PINHOLE", 1},        {"SIMPLE_RADIAL", 2}, {"RADIAL", 3},
      {"OPENCV", 4},         {"OPENCV_FISHEYE", 5}, {"FULL_OPENCV", 6}};
  const std::vector<int> counts = {3, 4, 4, 5, 8, 8, 12};
  for (std::size_t i = 0; i < colmap.size(); ++i) {
    const std::optional<CameraModel> m = camera_model_from_name(colmap[i].first);
    ASSERT_TRUE(m) << colmap[i].first;
    EXPECT_EQ(camera_model_name(*m), colmap[i].first);
    EXPECT_EQ(camera_model_id(*m), colmap[i].second);
    EXPECT_EQ(camera_model_from_id(colmap[i].second), m);
    EXPECT_EQ(camera_param_count(*m), counts[i]) << colmap[i].first;
  }
  EXPECT_FALSE(camera_model_from_name("opencv"));
  EXPECT_FALSE(camera_model_from_name("THIN_PRISM_FISHEYE"));
  EXPECT_FALSE(camera_model_from_id(7));
}

}  // namespace
}  // namespace texbake
