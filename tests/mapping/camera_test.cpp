// The camera projector's mathematics (mapping/camera.h) against values
// worked out by hand (PINHOLE, the turning points, the look-at frame) and
// against OpenCV's projectPoints / fisheye.projectPoints (expected values
// made by tests/mapping/camera_opencv_expected.py, kept in
// camera_opencv_expected.inc), and every pose form against every other.
#include "mapping/camera.h"

#include <gtest/gtest.h>

#include <cmath>
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

Camera make_camera(CameraModel model, std::vector<double> params, int w, int h,
                   CameraPose pose = {}) {
  Expected<Camera> c = Camera::make({model, w, h, std::move(params), pose});
  EXPECT_TRUE(c) << c.error().message;
  return std::move(c).value();
}

TEST(Camera, PinholeByHand) {
  // Identity pose; (0.2, -0.1, 2) -> a = 0.1, b = -0.05 -> x = 1000 * 0.1 +
  // 640 = 740, y = 900 * -0.05 + 360 = 315; (u, v) = (740 / 1280, 1 - 315 / 720).
  const Camera c = make_camera(CameraModel::kPinhole, {1000, 900, 640, 360}, 1280, 720);
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
  const Camera s = make_camera(CameraModel::kSimplePinhole, {1000, 640, 360}, 1280, 720);
  EXPECT_DOUBLE_EQ(s.project({0.2, -0.1, 2}).pixel.y, 310);  // f = 1000 on both axes
}

TEST(Camera, OutsideBehindBeyondTheImageAndPastTheTurningPoint) {
  const Camera c = make_camera(CameraModel::kPinhole, {1000, 1000, 640, 360}, 1280, 720);
  EXPECT_FALSE(c.project({0, 0, -1}).inside);
  EXPECT_FALSE(c.project({0, 0, 0}).inside);
  EXPECT_FALSE(c.project({0.7, 0, 1}).inside);    // x = 1340 > 1280
  EXPECT_FALSE(c.project({0, -0.37, 1}).inside);  // y = -10 < 0
  EXPECT_TRUE(c.project({0.639, 0.359, 1}).inside);
  EXPECT_EQ(c.max_radius2(), INFINITY);

  // SIMPLE_RADIAL k = -0.5: r_d = r (1 - 0.5 r^2) turns where 1 - 1.5 r^2 = 0.
  const Camera sr = make_camera(CameraModel::kSimpleRadial, {100, 5000, 5000, -0.5}, 10000, 10000);
  EXPECT_NEAR(sr.max_radius2(), 1 / 1.5, 1e-9);
  EXPECT_TRUE(sr.project({0.8, 0, 1}).inside);    // r^2 = 0.64
  EXPECT_FALSE(sr.project({0.83, 0, 1}).inside);  // r^2 = 0.6889: folded back, though in the image
  // RADIAL k1 = -0.2, k2 = 0.01: 1 - 0.6 s + 0.05 s^2 = 0 at s = 2.
  const Camera ra = make_camera(CameraModel::kRadial, {100, 5000, 5000, -0.2, 0.01}, 10000, 10000);
  EXPECT_NEAR(ra.max_radius2(), 2, 1e-9);
  // OPENCV_FISHEYE k1 = -0.3: 1 - 0.9 theta^2 = 0 at theta = sqrt(1 / 0.9).
  const Camera fe =
      make_camera(CameraModel::kOpenCVFisheye, {100, 100, 5000, 5000, -0.3, 0, 0, 0}, 10000, 10000);
  const double r_turn = std::tan(std::sqrt(1 / 0.9));
  EXPECT_NEAR(fe.max_radius2(), r_turn * r_turn, 1e-7);
  // FULL_OPENCV whose denominator never vanishes and numerator keeps growing: no turning point.
  const Camera full = make_camera(CameraModel::kFullOpenCV,
                                  {100, 100, 50, 50, 0.1, 0.01, 0, 0, 0.001, 0, 0, 0}, 100, 100);
  EXPECT_EQ(full.max_radius2(), INFINITY);
}

TEST(Camera, AgreesWithOpenCvToAMicroPixel) {
  Expected<CameraPose> pose = pose_from_quaternion(
      {kOpenCvQuaternion[0], kOpenCvQuaternion[1], kOpenCvQuaternion[2], kOpenCvQuaternion[3]},
      {kOpenCvTranslation[0], kOpenCvTranslation[1], kOpenCvTranslation[2]}, CameraAxes::kOpenCV,
      "test");
  ASSERT_TRUE(pose) << pose.error().message;
  ASSERT_EQ(kOpenCvCases.size(), 5u);
  for (const OpenCvCase& k : kOpenCvCases) {
    const std::optional<CameraModel> model = camera_model_from_name(k.model);
    ASSERT_TRUE(model) << k.model;
    const Camera c = make_camera(*model, k.params, kOpenCvWidth, kOpenCvHeight, *pose);
    ASSERT_GT(k.points.size(), 40u);
    for (const auto& p : k.points) {
      const CameraProjection got = c.project({p[0], p[1], p[2]});
      EXPECT_NEAR(got.pixel.x, p[3], 1e-6) << k.model;
      EXPECT_NEAR(got.pixel.y, p[4], 1e-6) << k.model;
    }
  }
}

// One camera placed by every pose form: the same pixels, to 1e-9.
TEST(Camera, EveryPoseFormGivesTheSamePixels) {
  // By hand: eye (0, -5, 0) looking at the origin with +z up: forward +y,
  // right = forward x up = +x, down = forward x right = -z. (1, 0, 0.5) is
  // then X = 1, Y = -0.5, Z = 5: a = 0.2, b = -0.1 -> (840, 260).
  Expected<CameraPose> look = pose_from_look_at({0, -5, 0}, {0, 0, 0}, {0, 0, 1}, "look");
  ASSERT_TRUE(look) << look.error().message;
  const std::vector<double> k = {1000, 1000, 640, 360};
  const Camera by_look = make_camera(CameraModel::kPinhole, k, 1280, 720, *look);
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
  const Camera reference = make_camera(CameraModel::kPinhole, k, 1280, 720, *poses[0]);
  const std::vector<Vec3> points = {{0, 0, 0}, {0.5, -0.2, 0.3}, {-1, 0.7, -0.4}, {0.2, 0.9, 1.1}};
  for (std::size_t i = 0; i < poses.size(); ++i) {
    ASSERT_TRUE(poses[i]) << i << ": " << poses[i].error().message;
    const Camera c = make_camera(CameraModel::kPinhole, k, 1280, 720, *poses[i]);
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

TEST(Camera, BadPosesAndParametersAreErrors) {
  const std::array<double, 9> skew = {1, 0.01, 0, 0, 1, 0, 0, 0, 1};
  const std::array<double, 9> mirror = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
  Expected<CameraPose> a =
      pose_from_rotation(skew, {0, 0, 0}, CameraAxes::kOpenCV, "images.txt line 5");
  ASSERT_FALSE(a);
  EXPECT_NE(a.error().message.find("images.txt line 5"), std::string::npos) << a.error().message;
  EXPECT_NE(a.error().message.find("not orthonormal"), std::string::npos);
  EXPECT_FALSE(pose_from_rotation(mirror, {0, 0, 0}, CameraAxes::kOpenCV, "m"));
  EXPECT_FALSE(pose_from_quaternion({1, 0.01, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "q"));
  EXPECT_TRUE(pose_from_quaternion({1, 1e-7, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "q"));
  EXPECT_FALSE(pose_from_quaternion({NAN, 0, 0, 0}, {0, 0, 0}, CameraAxes::kOpenCV, "q"));
  EXPECT_FALSE(pose_from_cam_to_world({1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1},
                                      CameraAxes::kOpenCV, "c2w"));
  EXPECT_FALSE(pose_from_look_at({0, 0, 0}, {0, 0, 1}, {0, 0, 2}, "look"));
  EXPECT_FALSE(pose_from_look_at({0, 0, 0}, {0, 0, 0}, {0, 0, 1}, "look"));
  EXPECT_FALSE(pose_from_rotation(skew, {0, INFINITY, 0}, CameraAxes::kOpenCV, "t"));

  Expected<Camera> wrong_count = Camera::make({CameraModel::kOpenCV, 100, 100, {1, 1, 50, 50}, {}});
  ASSERT_FALSE(wrong_count);
  EXPECT_EQ(wrong_count.error().message, "OPENCV takes 8 parameters, got 4");
  EXPECT_FALSE(Camera::make({CameraModel::kPinhole, 100, 100, {0, 1, 50, 50}, {}}));
  EXPECT_FALSE(Camera::make({CameraModel::kPinhole, 100, 100, {1, NAN, 50, 50}, {}}));
  EXPECT_FALSE(Camera::make({CameraModel::kPinhole, 0, 100, {1, 1, 50, 50}, {}}));
}

TEST(Camera, ModelNamesAndColmapIds) {
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
