// nerfstudio / instant-ngp transforms.json (mesh_io/nerfstudio_json.h) and
// the detection of camera files (mesh_io/camera_formats.h): cameras worked
// out by hand from the format's conventions (camera-to-world, OpenGL axes,
// cx cy as COLMAP's, applied_transform / applied_scale undone), the exact
// mapping of its lens onto COLMAP's models, and errors naming the frame and
// the key.
#include "mesh_io/nerfstudio_json.h"

#include <gtest/gtest.h>

#include <cmath>

#include "mesh_io/camera_formats.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

// The camera of every test below unless said otherwise: centre (0, -5, 0),
// looking along +y, +z up. In OpenGL axes its camera-to-world columns are x
// = right (1, 0, 0), y = up (0, 0, 1), z = back (0, -1, 0), and the centre.
const char* kLookingAlongY = R"([[1,0,0,0],[0,0,-1,-5],[0,1,0,0],[0,0,0,1]])";

std::string transforms(const std::string& top, const std::string& frame_extra = "",
                       const char* matrix = kLookingAlongY) {
  return "{" + top + (top.empty() ? "" : ",") +
         R"("frames":[{"file_path":"./images/a.png","transform_matrix":)" + matrix + frame_extra +
         "}]}";
}

const std::string kPinhole =
    R"("camera_model":"OPENCV","w":1280,"h":720,"fl_x":1000,"fl_y":1000,"cx":600.25,"cy":300.75)";

Expected<CameraFile> read(const std::string& text) {
  return nerfstudio_from_json(text, "t.json");
}

TEST(Nerfstudio, ACameraWorkedOutByHand) {
  Expected<CameraFile> f = read(transforms(kPinhole));
  ASSERT_TRUE(f) << f.error().message;
  ASSERT_EQ(f->cameras.size(), 1u);
  EXPECT_EQ(f->format, CameraFormat::kNerfstudio);
  EXPECT_EQ(f->cameras[0].image, "images/a.png");  // relative to the file's folder, "./" dropped
  EXPECT_TRUE(f->notes.empty());
  const CameraProjector& c = f->cameras[0].camera;
  // No distortion: PINHOLE, cx and cy as given (no half-pixel shift).
  EXPECT_EQ(c.spec().model, CameraModel::kPinhole);
  EXPECT_EQ(c.spec().params, (std::vector<double>{1000, 1000, 600.25, 300.75}));
  EXPECT_NEAR(length(c.centre() - Vec3{0, -5, 0}), 0, 1e-12);
  // P = (1, 0, 0.5) is 1 right, 0.5 up and 5 ahead: OpenCV (1, -0.5, 5), so
  // x = 600.25 + 1000 * 1 / 5 = 800.25, y = 300.75 + 1000 * -0.5 / 5 = 200.75.
  const CameraProjection p = c.project({1, 0, 0.5});
  ASSERT_TRUE(p.inside);
  EXPECT_NEAR(p.pixel.x, 800.25, 1e-9);
  EXPECT_NEAR(p.pixel.y, 200.75, 1e-9);
  EXPECT_NEAR(p.depth, 5, 1e-12);
  // A point behind it (y < -5) is behind.
  EXPECT_EQ(c.project({0, -6, 0}).outside, CameraOutside::kBehind);
}

TEST(Nerfstudio, AppliedTransformAndScaleAreUndone) {
  // The camera above in the original frame, re-framed as ns-process-data
  // does: A = rows (1,0,0), (0,0,1), (0,-1,0) (colmap_to_json's), here with
  // an offset a = (0.5, 0, 0) and scale s = 2: X_file = s (A X + a).
  // Centre: 2 (A (0,-5,0) + a) = 2 ((0,0,5) + (0.5,0,0)) = (1, 0, 10).
  // Axes: A (1,0,0) = (1,0,0), A (0,0,1) = (0,1,0), A (0,-1,0) = (0,0,1).
  const char* in_file = R"([[1,0,0,1],[0,1,0,0],[0,0,1,10],[0,0,0,1]])";
  const std::string top =
      kPinhole + R"(,"applied_transform":[[1,0,0,0.5],[0,0,1,0],[0,-1,0,0]],"applied_scale":2)";
  Expected<CameraFile> f = read(transforms(top, "", in_file));
  ASSERT_TRUE(f) << f.error().message;
  const CameraProjector& c = f->cameras[0].camera;
  EXPECT_NEAR(length(c.centre() - Vec3{0, -5, 0}), 0, 1e-12);
  // So the original point (1, 0, 0.5) lands where it did above.
  const CameraProjection p = c.project({1, 0, 0.5});
  EXPECT_NEAR(p.pixel.x, 800.25, 1e-9);
  EXPECT_NEAR(p.pixel.y, 200.75, 1e-9);
  // And the file's own frame is not used: its image of that point,
  // 2 (A (1,0,0.5) + a) = (3, 1, 0), is not where the camera is looking.
  ASSERT_EQ(f->notes.size(), 1u);
  EXPECT_NE(f->notes[0].find("applied_transform [[1, 0, 0, 0.5], [0, 0, 1, 0], [0, -1, 0, 0]] and "
                             "applied_scale 2 undone"),
            std::string::npos)
      << f->notes[0];
  // The identity re-frames nothing and is not noted.
  f = read(transforms(kPinhole + R"(,"applied_transform":[[1,0,0,0],[0,1,0,0],[0,0,1,0]])"));
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_TRUE(f->notes.empty());
}

TEST(Nerfstudio, LensesMapExactlyOntoColmapModels) {
  const std::string base = R"("w":1280,"h":720,"fl_x":1000,"fl_y":990,"cx":640,"cy":360)";
  struct Case {
    std::string keys;
    CameraModel model;
    std::vector<double> params;
  };
  const std::vector<Case> cases = {
      {R"("camera_model":"OPENCV","k1":-0.1,"k2":0.01,"p1":0.001,"p2":-0.002)",
       CameraModel::kOpenCV,
       {1000, 990, 640, 360, -0.1, 0.01, 0.001, -0.002}},
      // k3 (r^6): FULL_OPENCV with k4..k6 = 0, whose radial is then the same.
      {R"("camera_model":"OPENCV","k1":-0.1,"k2":0.01,"k3":0.003,"p1":0.001)",
       CameraModel::kFullOpenCV,
       {1000, 990, 640, 360, -0.1, 0.01, 0.001, 0, 0.003, 0, 0, 0}},
      {R"("camera_model":"OPENCV_FISHEYE","k1":0.1,"k2":0.02,"k3":0.003,"k4":0.0004)",
       CameraModel::kOpenCVFisheye,
       {1000, 990, 640, 360, 0.1, 0.02, 0.003, 0.0004}},
      // instant-ngp's flag for the same lens.
      {R"("is_fisheye":true,"k1":0.1)",
       CameraModel::kOpenCVFisheye,
       {1000, 990, 640, 360, 0.1, 0, 0, 0}},
      // No camera_model: nerfstudio's perspective lens.
      {R"("k1":0.1)", CameraModel::kOpenCV, {1000, 990, 640, 360, 0.1, 0, 0, 0}},
      {R"("camera_model":"SIMPLE_PINHOLE","k1":0,"k2":0,"p1":0,"p2":0)",
       CameraModel::kPinhole,
       {1000, 990, 640, 360}},
  };
  for (const Case& c : cases) {
    Expected<CameraFile> f = read(transforms(base + "," + c.keys));
    ASSERT_TRUE(f) << c.keys << ": " << f.error().message;
    EXPECT_EQ(f->cameras[0].camera.spec().model, c.model) << c.keys;
    EXPECT_EQ(f->cameras[0].camera.spec().params, c.params) << c.keys;
  }
  // The FULL_OPENCV camera bends a point off the axis as k3 says: a = 0.2,
  // b = 0.1 (r^2 = 0.05), k3 only: radial = 1 + 0.5 * 0.05^3 = 1.0000625;
  // x = 640 + 1000 * 0.2 * radial = 840.0125, y = 360 + 990 * 0.1 * radial.
  Expected<CameraFile> f = read(transforms(base + R"(,"k3":0.5)"));
  ASSERT_TRUE(f) << f.error().message;
  const Vec2 px = f->cameras[0].camera.pixel_of_normalised(0.2, 0.1);
  EXPECT_NEAR(px.x, 840.0125, 1e-9);
  EXPECT_NEAR(px.y, 360 + 99 * 1.0000625, 1e-9);
}

TEST(Nerfstudio, SharedOrPerFrameIntrinsicsAndDefaults) {
  // Per-frame intrinsics (colmap_to_json with several cameras), and the
  // focal length from camera_angle_x alone: fl_x = (w / 2) / tan(angle / 2).
  const double angle = 2 * std::atan(640.0 / 1000.0);
  const std::string text =
      R"({"w":1280,"h":720,"frames":[)"
      R"({"file_path":"a.png","fl_x":1000,"cx":600,"cy":350,"transform_matrix":)" +
      std::string(kLookingAlongY) + R"(},{"file_path":"/abs/b.png","camera_angle_x":)" +
      std::to_string(angle) + R"(,"transform_matrix":)" + kLookingAlongY + "}]}";
  Expected<CameraFile> f = read(text);
  ASSERT_TRUE(f) << f.error().message;
  ASSERT_EQ(f->cameras.size(), 2u);
  // fl_y defaults to fl_x; cx, cy given.
  EXPECT_EQ(f->cameras[0].camera.spec().params, (std::vector<double>{1000, 1000, 600, 350}));
  // cx, cy default to the image's centre (instant-ngp's rule).
  const std::vector<double>& p = f->cameras[1].camera.spec().params;
  EXPECT_NEAR(p[0], 1000, 1e-3);  // std::to_string printed the angle with 6 decimals
  EXPECT_EQ(p[2], 640);
  EXPECT_EQ(p[3], 360);
  EXPECT_EQ(f->cameras[1].image, "/abs/b.png");
}

TEST(Nerfstudio, BadFilesNameTheFrameAndTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"frames":[]})", "t.json: key 'frames' must be a non-empty array of frames"},
      {transforms(R"("h":720,"fl_x":1000)"),
       "t.json: frames[0]: missing key 'w' (the photo's width in pixels)"},
      {transforms(R"("w":1280.5,"h":720,"fl_x":1000)"),
       "t.json: frames[0]: key 'w' must be a positive whole number of pixels"},
      {transforms(R"("w":1280,"h":720)"),
       "t.json: frames[0]: missing key 'fl_x' (the focal length in pixels)"},
      {transforms(kPinhole + R"(,"k4":0.01)"),
       "t.json: frames[0]: key 'k4' is 0.01: nerfstudio's perspective k4 is a radial r^8 term"},
      {transforms(R"("camera_model":"OPENCV_FISHEYE","w":1280,"h":720,"fl_x":1000,"p1":0.1)"),
       "t.json: frames[0]: key 'p1' is 0.1: OPENCV_FISHEYE has no tangential terms"},
      {transforms(R"("camera_model":"EQUIRECTANGULAR","w":1280,"h":720,"fl_x":1000)"),
       "t.json: frames[0]: key 'camera_model': 'EQUIRECTANGULAR' is not a camera texbake models"},
      {transforms(kPinhole, R"(,"k5":0.1)"),
       "t.json: frames[0]: key 'k5': texbake has no camera model for it"},
      {transforms(kPinhole + R"(,"rolling_shutter":[0,0.1,0,0])"),
       "t.json: frames[0]: key 'rolling_shutter': texbake models no rolling shutter"},
      {transforms(kPinhole, R"(,"fl_x":1010)"),
       "t.json: frames[0]: key 'fl_x' is 1010 here and 1000 at the top level"},
      {transforms(kPinhole + R"(,"k1":0.1)", R"(,"k2":0.01)"),
       "t.json: frames[0]: key 'k2' is given here while the top level gives the distortion "
       "(key 'k1')"},
      {transforms(kPinhole + R"(,"camera_angle_x":1.0)"),
       "t.json: frames[0]: key 'camera_angle_x' (1) gives the focal length 1171.5"},
      {transforms(kPinhole + R"(,"is_fisheye":true)"),
       "t.json: frames[0]: key 'is_fisheye' contradicts key 'camera_model' (OPENCV)"},
      {transforms(kPinhole, "", R"([[1,0,0,0],[0,1,0,0],[0,0,1,0]])"),
       "t.json: frames[0]: key 'transform_matrix' must be 4 rows of 4 numbers"},
      {transforms(kPinhole, "", R"([[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]])"),
       "t.json: frames[0]: key 'transform_matrix': the bottom row of cam_to_world must be 0 0 0 1"},
      {transforms(kPinhole, "", R"([[1,0.1,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]])"),
       "t.json: frames[0]: key 'transform_matrix': the rotation is not orthonormal"},
      {transforms(kPinhole + R"(,"applied_transform":[[1,0,0,0],[0,1,0,0],[0,0,-1,0]])"),
       "t.json: key 'applied_transform': the rotation is a reflection"},
      {transforms(kPinhole + R"(,"applied_scale":0)"),
       "t.json: key 'applied_scale' must be a positive number"},
      {R"({"w":1280,"h":720,"fl_x":1000,"frames":[{"transform_matrix":)" +
           std::string(kLookingAlongY) + "}]}",
       "t.json: frames[0]: key 'file_path' must name the photo"},
      // The strict JSON rules hold here too.
      {transforms(kPinhole + R"(,"w":1280)"), "t.json: duplicate key 'w'"},
      // The principal point far outside the photo: CameraProjector's own check.
      {transforms(R"("w":1280,"h":720,"fl_x":1000,"cx":5000)"), "t.json: frames[0]: "},
  };
  for (const auto& [text, message] : cases) {
    Expected<CameraFile> f = read(text);
    ASSERT_FALSE(f) << text;
    EXPECT_EQ(f.error().code, ErrorCode::kParse) << text;
    EXPECT_EQ(f.error().message.rfind(message, 0), 0u)
        << text << "\n  got: " << f.error().message << "\n  want: " << message;
  }
}

TEST(CameraFormats, TheFormatIsToldByTheContent) {
  Expected<CameraFile> f = camera_file_from_text(transforms(kPinhole), "x.dat");
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->format, CameraFormat::kNerfstudio);
  f = camera_file_from_text(
      R"({"cameras":[{"kind":"camera","model":"PINHOLE","width":1280,"height":720,)"
      R"("params":[1000,1000,640,360],"pose":{"q_wxyz":[1,0,0,0],"t":[0,0,5]},"image":"a.png"}]})",
      "x.dat");
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->format, CameraFormat::kCameraList);
  EXPECT_EQ(f->cameras[0].image, "a.png");
  f = camera_file_from_text(R"({"views":[]})", "x.dat");
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error().message.rfind("x.dat: not a camera file texbake reads", 0), 0u)
      << f.error().message;
  // Meshroom's cameras.sfm goes to its reader (mesh_io/meshroom_sfm.h).
  f = camera_file_from_text(R"({"version":["1","2","4"],"views":[],"intrinsics":[],"poses":[]})",
                            "cameras.sfm");
  ASSERT_FALSE(f);
  EXPECT_EQ(f.error().message,
            "cameras.sfm: no reconstructed view (no view's poseId names a pose)");
  // A file of a COLMAP model is not taken for a camera file.
  const std::filesystem::path dir = test::fresh_temp_dir("camera-formats");
  f = read_camera_file(test::write_text(dir / "cameras.txt", "1 PINHOLE 2 2 1 1 1 1\n"));
  ASSERT_FALSE(f);
  EXPECT_NE(f.error().message.find("a file of a COLMAP model: give the model's folder"),
            std::string::npos)
      << f.error().message;
  f = read_camera_file(test::write_text(dir / "transforms.json", transforms(kPinhole)));
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->cameras[0].image, "images/a.png");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace texbake
