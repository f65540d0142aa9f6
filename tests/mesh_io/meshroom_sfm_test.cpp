// Meshroom / AliceVision SfMData (mesh_io/meshroom_sfm.h): a camera worked
// out by hand from AliceVision's conventions (focal in mm with the sensor
// width and pixel ratio, the principal point as an offset from the image
// centre, AliceVision's pixel centres at integers, the rotation stored
// column by column, brown's t1 t2), the older versions' focal and principal
// point, each distortion, views without a pose left out, and errors naming
// the view, intrinsic or pose and the key.
#include "mesh_io/meshroom_sfm.h"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>

#include "mesh_io/camera_formats.h"

namespace texbake {
namespace {

using nlohmann::json;

// An intrinsic as Meshroom 2023+ writes it (version 1.2.11, every value a
// string): 1000 x 800, 27 mm on a 36 mm wide sensor, pixel ratio 1.25,
// principal point offset (10, -20), brown distortion.
json intrinsic() {
  return {{"intrinsicId", "7"},
          {"width", "1000"},
          {"height", "800"},
          {"sensorWidth", "36"},
          {"sensorHeight", "28.8"},
          {"serialNumber", "-1"},
          {"type", "pinhole"},
          {"initializationMode", "estimated"},
          {"initialFocalLength", "27"},
          {"focalLength", "27"},
          {"pixelRatio", "1.25"},
          {"pixelRatioLocked", "true"},
          {"offsetLocked", "false"},
          {"scaleLocked", "false"},
          {"principalPoint", {"10", "-20"}},
          {"distortionLocked", "false"},
          {"distortionInitializationMode", "none"},
          {"distortionParams", {"-0.1", "0.01", "0", "0.001", "0.002"}},
          {"undistortionOffset", {"0", "0"}},
          {"undistortionParams", ""},
          {"distortionType", "brown"},
          {"undistortionType", "none"},
          {"locked", "false"}};
}

// World-to-camera R with rows (0, 1, 0), (-1, 0, 0), (0, 0, 1), stored
// column by column (Eigen's order): (0, -1, 0), (1, 0, 0), (0, 0, 1).
// Centre (1, 2, 3).
json pose(const char* id = "3") {
  return {{"poseId", id},
          {"pose",
           {{"transform",
             {{"rotation", {"0", "-1", "0", "1", "0", "0", "0", "0", "1"}},
              {"center", {"1", "2", "3"}}}},
            {"locked", "0"}}}};
}

json view(const char* view_id, const char* pose_id, const std::string& path) {
  return {{"viewId", view_id},  {"poseId", pose_id},  {"frameId", "1"},
          {"intrinsicId", "7"}, {"resectionId", "0"}, {"path", path},
          {"width", "1000"},    {"height", "800"},    {"metadata", {{"Make", "Canon"}}}};
}

json sfm(const json& in = intrinsic(), const char* version_minor_rev = "11") {
  return {{"version", {"1", "2", version_minor_rev}},
          {"featuresFolders", {"/tmp/features"}},
          {"matchesFolders", {"/tmp/matches"}},
          {"views", {view("100", "3", "/photos/IMG_1.JPG"), view("101", "4", "IMG_2.JPG")}},
          {"intrinsics", {in}},
          {"poses", {pose()}}};
}

Expected<CameraFile> read(const json& j) {
  return meshroom_from_json(j.dump(2), "cameras.sfm");
}

TEST(Meshroom, ACameraWorkedOutByHand) {
  Expected<CameraFile> f = read(sfm());
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->format, CameraFormat::kMeshroom);
  ASSERT_EQ(f->cameras.size(), 1u);
  EXPECT_EQ(f->cameras[0].image, "/photos/IMG_1.JPG");
  const CameraProjector& c = f->cameras[0].camera;
  // Focal (1.2.11): fy = 27 mm * 1000 px / 36 mm = 750, fx = fy / 1.25 =
  // 600. Principal point: (500 + 10, 400 - 20) in AliceVision's pixels
  // (centre of the top-left pixel at (0, 0)), + 0.5 in COLMAP's: (510.5,
  // 380.5). Brown k1 k2 k3 t1 t2 = OpenCV's k1 k2 (k3 = 0) p1 p2: OPENCV.
  EXPECT_EQ(c.spec().model, CameraModel::kOpenCV);
  EXPECT_EQ(c.spec().params,
            (std::vector<double>{600, 750, 510.5, 380.5, -0.1, 0.01, 0.001, 0.002}));
  EXPECT_NEAR(length(c.centre() - Vec3{1, 2, 3}), 0, 1e-12);
  // P = C + R^T (0.4, -0.2, 4) = (1, 2, 3) + 0.4 (0, 1, 0) - 0.2 (-1, 0, 0)
  // + 4 (0, 0, 1) = (1.2, 2.4, 7): a = 0.1, b = -0.05, r^2 = 0.0125,
  // radial = 1 - 0.1 r^2 + 0.01 r^4 = 0.9987515625. AliceVision's brown:
  // a' = a radial + t2 (r^2 + 2a^2) + 2 t1 a b
  //    = 0.09987515625 + 0.002 * 0.0325 - 0.002 * 0.005 = 0.09993015625
  // b' = b radial + t1 (r^2 + 2b^2) + 2 t2 a b
  //    = -0.049937578125 + 0.001 * 0.0175 - 0.004 * 0.005 = -0.049940078125
  // x = 600 a' + 510.5 = 570.45809375, y = 750 b' + 380.5 = 343.04494140625.
  const CameraProjection p = c.project({1.2, 2.4, 7});
  ASSERT_TRUE(p.inside);
  EXPECT_NEAR(p.pixel.x, 570.45809375, 1e-9);
  EXPECT_NEAR(p.pixel.y, 343.04494140625, 1e-9);
  EXPECT_NEAR(p.depth, 4, 1e-12);
  // View 101's pose 4 is not in the file: not reconstructed.
  ASSERT_EQ(f->notes.size(), 1u);
  EXPECT_EQ(f->notes[0], "cameras.sfm: 1 view is not reconstructed (no pose) and left out");
}

TEST(Meshroom, OlderVersionsFocalAndPrincipalPoint) {
  const auto params = [](const json& in, const char* rev) {
    Expected<CameraFile> f = read(sfm(in, rev));
    EXPECT_TRUE(f) << f.error().message;
    return f ? f->cameras[0].camera.spec().params : std::vector<double>{};
  };
  const std::vector<double> brown = {-0.1, 0.01, 0.001, 0.002};
  const auto with = [&](double fx, double fy, double cx, double cy) {
    std::vector<double> v = {fx, fy, cx, cy};
    v.insert(v.end(), brown.begin(), brown.end());
    return v;
  };
  // 1.2.5 .. 1.2.10: fx = 27 * 1000 / 36 = 750, fy = fx * 1.25 = 937.5.
  EXPECT_EQ(params(intrinsic(), "10"), with(750, 937.5, 510.5, 380.5));
  // 1.2.2 .. 1.2.4: pixelRatio held fx / fy: fy = 750 / 1.25 = 600.
  json old = intrinsic();
  old.erase("distortionType");
  old.erase("undistortionType");
  old["type"] = "brown";  // before 1.2.8 the type names the distortion
  EXPECT_EQ(params(old, "4"), with(750, 600, 510.5, 380.5));
  // 1.2.1: pxFocalLength [fx, fy] in pixels; the principal point an offset.
  old.erase("focalLength");
  old["pxFocalLength"] = {"600", "750"};
  EXPECT_EQ(params(old, "1"), with(600, 750, 510.5, 380.5));
  // 1.2.0: the principal point absolute (510, 380) -> (510.5, 380.5).
  old["principalPoint"] = {"510", "380"};
  EXPECT_EQ(params(old, "0"), with(600, 750, 510.5, 380.5));
  // 1.0.x: pxFocalLength one number.
  json oldest = old;
  oldest["pxFocalLength"] = "600";
  Expected<CameraFile> f = read({{"version", {"1", "0", "0"}},
                                 {"views", {view("1", "3", "a.jpg")}},
                                 {"intrinsics", {oldest}},
                                 {"poses", {pose()}}});
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->cameras[0].camera.spec().params, with(600, 600, 510.5, 380.5));
  // Plain JSON numbers are read as well as strings.
  json numeric = intrinsic();
  numeric["width"] = 1000;
  numeric["focalLength"] = 27.0;
  numeric["principalPoint"] = {10, -20};
  numeric["distortionParams"] = {-0.1, 0.01, 0, 0.001, 0.002};
  EXPECT_EQ(params(numeric, "11"), with(600, 750, 510.5, 380.5));
}

TEST(Meshroom, EachDistortionMapsExactly) {
  const auto spec = [](const char* type, const json& k) {
    json in = intrinsic();
    in["pixelRatio"] = "1";  // fx = fy = 750
    in["principalPoint"] = {"0", "0"};
    in["distortionType"] = type;
    in["distortionParams"] = k;
    Expected<CameraFile> f = read(sfm(in));
    EXPECT_TRUE(f) << type << ": " << f.error().message;
    return f ? f->cameras[0].camera : CameraProjector();
  };
  // none: PINHOLE (Meshroom writes an empty array).
  CameraProjector c = spec("none", json::array());
  EXPECT_EQ(c.spec().model, CameraModel::kPinhole);
  EXPECT_EQ(c.spec().params, (std::vector<double>{750, 750, 500.5, 400.5}));
  // radialk1: (a, b)(1 + k1 r^2): OPENCV with k2 = p1 = p2 = 0.
  c = spec("radialk1", {"-0.2"});
  EXPECT_EQ(c.spec().model, CameraModel::kOpenCV);
  EXPECT_EQ(c.spec().params, (std::vector<double>{750, 750, 500.5, 400.5, -0.2, 0, 0, 0}));
  // (a, b) = (0.2, 0.1): r^2 = 0.05, 1 - 0.2 r^2 = 0.99: x = 750 * 0.198 +
  // 500.5 = 648.999..., y = 750 * 0.099 + 400.5 = 474.75.
  Vec2 px = c.pixel_of_normalised(0.2, 0.1);
  EXPECT_NEAR(px.x, 649, 1e-9);
  EXPECT_NEAR(px.y, 474.75, 1e-9);
  // radialk3 with k3: FULL_OPENCV, p1 = p2 = 0, k4..k6 = 0.
  c = spec("radialk3", {"-0.2", "0.05", "0.01"});
  EXPECT_EQ(c.spec().model, CameraModel::kFullOpenCV);
  EXPECT_EQ(c.spec().params,
            (std::vector<double>{750, 750, 500.5, 400.5, -0.2, 0.05, 0, 0, 0.01, 0, 0, 0}));
  // radial = 1 - 0.2 * 0.05 + 0.05 * 0.0025 + 0.01 * 0.000125 = 0.99012625.
  px = c.pixel_of_normalised(0.2, 0.1);
  EXPECT_NEAR(px.x, 500.5 + 750 * 0.2 * 0.99012625, 1e-9);
  // radialk3 without k3: OPENCV.
  EXPECT_EQ(spec("radialk3", {"-0.2", "0.05", "0"}).spec().model, CameraModel::kOpenCV);
  // brown with k3: FULL_OPENCV with t1 t2 as p1 p2.
  c = spec("brown", {"-0.2", "0.05", "0.01", "0.001", "0.002"});
  EXPECT_EQ(c.spec().params,
            (std::vector<double>{750, 750, 500.5, 400.5, -0.2, 0.05, 0.001, 0.002, 0.01, 0, 0, 0}));
  // fisheye (fisheye4 before 1.2.8): theta_d = theta + k1 theta^3 + ... +
  // k4 theta^9 = OpenCV's fisheye. (a, b) = (1, 0): theta = pi/4, x = 500.5
  // + 750 theta (1 + 0.05 theta^2 + 0.001 theta^8), y = 400.5.
  c = spec("fisheye", {"0.05", "0", "0", "0.001"});
  EXPECT_EQ(c.spec().model, CameraModel::kOpenCVFisheye);
  EXPECT_EQ(c.spec().params, (std::vector<double>{750, 750, 500.5, 400.5, 0.05, 0, 0, 0.001}));
  const double t = std::numbers::pi / 4;
  px = c.pixel_of_normalised(1, 0);
  EXPECT_NEAR(px.x, 500.5 + 750 * t * (1 + 0.05 * t * t + 0.001 * std::pow(t, 8)), 1e-9);
  EXPECT_NEAR(px.y, 400.5, 1e-12);
}

TEST(Meshroom, BadFilesNameTheViewIntrinsicAndKey) {
  const auto with_intrinsic = [](const char* key, const json& value) {
    json in = intrinsic();
    if (value.is_null()) {
      in.erase(key);
    } else {
      in[key] = value;
    }
    return sfm(in);
  };
  json rig = sfm();
  rig["views"][0]["rigId"] = "0";
  rig["views"][0]["subPoseId"] = "1";
  json bad_rotation = sfm();
  bad_rotation["poses"][0]["pose"]["transform"]["rotation"][1] = "-0.9";
  json no_path = sfm();
  no_path["views"][0].erase("path");
  json no_intrinsic = sfm();
  no_intrinsic["views"][0]["intrinsicId"] = "8";
  json newer = sfm();
  newer["version"] = {"1", "3", "0"};
  json no_version = sfm();
  no_version.erase("version");
  json old_type = intrinsic();
  old_type["type"] = "3deanamorphic4";
  const std::vector<std::pair<json, std::string>> cases = {
      {with_intrinsic("distortionType", "fisheye1"),
       "cameras.sfm: intrinsic 7: distortionType 'fisheye1': no COLMAP camera model describes "
       "this distortion"},
      {with_intrinsic("distortionType", "radialk3pt"),
       "cameras.sfm: intrinsic 7: distortionType 'radialk3pt': no COLMAP camera model"},
      {with_intrinsic("undistortionType", "3deanamorphic4"),
       "cameras.sfm: intrinsic 7: undistortionType '3deanamorphic4': an undistortion model"},
      {with_intrinsic("type", "equidistant"),
       "cameras.sfm: intrinsic 7: type 'equidistant': no COLMAP camera model describes it"},
      {with_intrinsic("distortionParams", {"0.1", "0.2"}),
       "cameras.sfm: intrinsic 7: key 'distortionParams' holds 2 numbers; a brown distortion "
       "has 5"},
      {with_intrinsic("focalLength", nullptr),
       "cameras.sfm: intrinsic 7: missing key 'focalLength'"},
      {with_intrinsic("focalLength", "abc"),
       "cameras.sfm: intrinsic 7: key 'focalLength' must be a finite number"},
      {with_intrinsic("principalPoint", {"1"}),
       "cameras.sfm: intrinsic 7: key 'principalPoint' must be an array of 2 numbers"},
      {with_intrinsic("sensorWidth", "0"),
       "cameras.sfm: intrinsic 7: key 'sensorWidth' must be positive"},
      {with_intrinsic("width", "10.5"),
       "cameras.sfm: intrinsic 7: key 'width' must be a positive whole number of pixels"},
      {sfm(old_type, "4"),
       "cameras.sfm: intrinsic 7: type '3deanamorphic4': no COLMAP camera model"},
      {rig, "cameras.sfm: view 100: key 'rigId': the view belongs to a camera rig"},
      {bad_rotation, "cameras.sfm: pose 3: key 'rotation': the rotation is not orthonormal"},
      {no_path, "cameras.sfm: view 100: missing key 'path'"},
      {no_intrinsic, "cameras.sfm: view 100: intrinsicId 8 names no intrinsic"},
      {newer, "cameras.sfm: version 1.3.0 is newer than the SfMData version 1.2.11"},
      {no_version, "cameras.sfm: missing key 'version'"},
  };
  for (const auto& [j, message] : cases) {
    Expected<CameraFile> f = read(j);
    ASSERT_FALSE(f) << message;
    EXPECT_EQ(f.error().code, ErrorCode::kParse);
    EXPECT_EQ(f.error().message.rfind(message, 0), 0u)
        << "got: " << f.error().message << "\n  want: " << message;
  }
  // An intrinsic no reconstructed view uses is not read.
  json unused = sfm();
  json fisheye1 = intrinsic();
  fisheye1["intrinsicId"] = "9";
  fisheye1["distortionType"] = "fisheye1";
  unused["intrinsics"].push_back(fisheye1);
  EXPECT_TRUE(read(unused));
}

TEST(Meshroom, ToldByItsContent) {
  Expected<CameraFile> f = camera_file_from_text(sfm().dump(), "sfm.json");
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->format, CameraFormat::kMeshroom);
  EXPECT_EQ(camera_format_name(f->format), "Meshroom .sfm");
}

}  // namespace
}  // namespace texbake
