// Camera projectors as JSON (mesh_io/camera_json.h): every pose form gives the
// camera the pose functions give (mapping/camera.h, tested by hand there),
// camera lists, and every bad input an error naming the key.
#include "mesh_io/camera_json.h"

#include <gtest/gtest.h>

#include <fstream>

namespace texbake {
namespace {

std::string camera_with(const std::string& pose) {
  return R"({"kind":"camera","model":"PINHOLE","width":1280,"height":720,)"
         R"("params":[1000,1000,640,360],"pose":)" +
         pose + "}";
}

TEST(CameraJson, EveryPoseFormReadsAsTheSameCamera) {
  // The look-at camera of tests/mapping/camera_test.cpp: eye (0, -5, 0)
  // looking at the origin, +z up: R rows right (1,0,0), down (0,0,-1),
  // forward (0,1,0); t = -R eye = (0, 0, 5); (1, 0, 0.5) lands on (840, 260).
  const std::vector<std::string> poses = {
      R"({"eye":[0,-5,0],"target":[0,0,0],"up":[0,0,1]})",
      R"({"R":[[1,0,0],[0,0,-1],[0,1,0]],"t":[0,0,5]})",
      R"({"center":[0,-5,0],"R":[[1,0,0],[0,0,-1],[0,1,0]]})",
      R"({"cam_to_world":[[1,0,0,0],[0,0,1,-5],[0,-1,0,0],[0,0,0,1]]})",
      // OpenGL axes: rows right (1,0,0), up (0,0,1), back (0,-1,0).
      R"({"center":[0,-5,0],"R":[[1,0,0],[0,0,1],[0,-1,0]],"axes":"opengl"})",
      R"({"cam_to_world":[[1,0,0,0],[0,0,-1,-5],[0,1,0,0],[0,0,0,1]],"axes":"opengl"})",
      // R = rotation of +90 degrees about x ([[1,0,0],[0,c,-s],[0,s,c]], c = 0,
      // s = 1): q = (cos 45, sin 45, 0, 0).
      R"({"q_wxyz":[0.7071067811865476,0.7071067811865476,0,0],"t":[0,0,5]})",
  };
  for (const std::string& pose : poses) {
    Expected<CameraProjector> c = camera_from_json(camera_with(pose));
    ASSERT_TRUE(c) << pose << ": " << c.error().message;
    const CameraProjection p = c->project({1, 0, 0.5});
    EXPECT_NEAR(p.pixel.x, 840, 1e-9) << pose;
    EXPECT_NEAR(p.pixel.y, 260, 1e-9) << pose;
    EXPECT_NEAR(length(c->centre() - Vec3{0, -5, 0}), 0, 1e-12) << pose;
  }
}

TEST(CameraJson, BadCamerasNameTheKey) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {R"({"kind":"camera","model":"FOO","width":1,"height":1,"params":[],"pose":{}})",
       "camera JSON: key 'model': unknown camera model 'FOO'"},
      {camera_with(R"({"eye":[0,-5,0],"target":[0,0,0]})"), "camera JSON: the pose needs key 'up'"},
      {camera_with(R"({"R":[[1,0,0],[0,1,0],[0,0,1]],"t":[0,0,1],"eye":[0,0,0]})"),
       "camera JSON: key 'eye' does not belong to this pose form"},
      {camera_with(R"({"R":[[1,0.1,0],[0,1,0],[0,0,1]],"t":[0,0,1]})"),
       "camera JSON: key 'pose': the rotation is not orthonormal"},
      {camera_with(R"({"q_wxyz":[1,0,0,0],"t":[0,0]})"),
       "camera JSON: key 't' must be an array of 3 numbers"},
      {camera_with(R"({"q_wxyz":[1,0,0,0],"t":[0,0,1],"axes":"blender"})"),
       "camera JSON: key 'axes' must be \"opencv\" or \"opengl\""},
      {camera_with(R"({})"), "camera JSON: the pose needs one of"},
      {R"({"kind":"camera","model":"OPENCV","width":1280,"height":720,"params":[1,1,1,1],"pose":{"eye":[0,-5,0],"target":[0,0,0],"up":[0,0,1]}})",
       "camera JSON: key 'params': OPENCV takes 8 parameters, got 4"},
      {R"({"kind":"camera","model":"PINHOLE","width":0,"height":720,"params":[1,1,1,1],"pose":{}})",
       "camera JSON: key 'width' must be a positive integer"},
      {R"({"kind":"camera","model":"PINHOLE","width":10,"height":720,"params":[1,1,1,1],"pose":{},"fov":3})",
       "camera JSON: unknown key 'fov' in a camera"},
      {R"({"kind":"camera","kind":"camera"})", "camera JSON: duplicate key 'kind'"},
  };
  for (const auto& [text, want] : cases) {
    Expected<CameraProjector> c = camera_from_json(text);
    ASSERT_FALSE(c) << text;
    EXPECT_EQ(c.error().code, ErrorCode::kParse);
    EXPECT_EQ(c.error().message.rfind(want, 0), 0u)
        << "got: " << c.error().message << "\nwant: " << want;
  }
}

TEST(CameraJson, DeepNestingAndHugeNumbersNameTheKey) {
  Expected<CameraProjector> c =
      camera_from_json(R"({"kind":"camera","pose":{"eye":)" + std::string(100000, '['), "cam.json");
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().code, ErrorCode::kParse);
  // `{"kind":"camera","pose":{"eye":` is 31 characters; root and pose are
  // levels 1 and 2: the 127th '[' is level 129.
  EXPECT_EQ(c.error().message,
            "cam.json: key 'pose.eye' nests deeper than 128 levels (line 1, column 158)");
  c = camera_from_json(camera_with(R"({"eye":[0,-5e999,0],"target":[0,0,0],"up":[0,0,1]})"),
                       "cam.json");
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error().message.rfind(
                "cam.json: key 'pose.eye' holds a number that is not finite (-5e999 at line 1", 0),
            0u)
      << c.error().message;
}

TEST(CameraJson, CameraLists) {
  const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "camera_list";
  std::filesystem::create_directories(dir);
  const std::string cam =
      R"("kind":"camera","model":"PINHOLE","width":1280,"height":720,"params":[1000,1000,640,360],"pose":{"eye":[0,-5,0],"target":[0,0,0],"up":[0,0,1]})";
  std::ofstream(dir / "good.json") << R"({"cameras":[{)" << cam << R"(,"image":"a.png"},{)" << cam
                                   << R"(,"image":"sub/b.jpg"}]})";
  Expected<std::vector<CameraListEntry>> list = read_camera_list(dir / "good.json");
  ASSERT_TRUE(list) << list.error().message;
  ASSERT_EQ(list->size(), 2u);
  EXPECT_EQ((*list)[1].image, "sub/b.jpg");
  std::ofstream(dir / "no_image.json") << R"({"cameras":[{)" << cam << R"(},{)" << cam << "}]}";
  Expected<std::vector<CameraListEntry>> bad = read_camera_list(dir / "no_image.json");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message,
            (dir / "no_image.json").string() + ": cameras[0]: key 'image' must name the photo");
  // A camera list nested too deep: the file, the line and the keys.
  std::ofstream(dir / "deep.json") << "{\"cameras\":[\n{\"pose\":" << std::string(90000, '[');
  bad = read_camera_list(dir / "deep.json");
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, (dir / "deep.json").string() +
                                     ": key 'cameras.pose' nests deeper than 128 levels (line 2, "
                                     "column 134)");
  std::ofstream(dir / "empty.json") << R"({"cameras":[]})";
  EXPECT_FALSE(read_camera_list(dir / "empty.json"));
  Expected<std::vector<CameraListEntry>> missing = read_camera_list(dir / "missing.json");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().code, ErrorCode::kIo);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace texbake
