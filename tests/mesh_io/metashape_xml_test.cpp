// Agisoft Metashape cameras.xml (mesh_io/metashape_xml.h): a camera worked
// out by hand from Agisoft's camera model (principal point as an offset from
// the image centre, b1 affinity, p1 p2 in Agisoft's roles, the chunk's
// rotation, translation and scale), a fisheye, components, and errors naming
// the line, the sensor or camera and the term.
#include "mesh_io/metashape_xml.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mesh_io/camera_formats.h"

namespace texbake {
namespace {

const char* kCalibration = R"(
        <calibration type="frame" class="adjusted">
          <resolution width="1000" height="800"/>
          <f>1000</f><cx>10</cx><cy>-20</cy><b1>5</b1>
          <k1>-0.1</k1><k2>0.01</k2><p1>0.001</p1><p2>0.002</p2>
        </calibration>)";

// A document with one frame sensor (calibration `calibration`), cameras
// `cameras` and the chunk's transform `chunk_transform`.
std::string document(const std::string& cameras, const std::string& chunk_transform = "",
                     const std::string& calibration = kCalibration, const std::string& extra = "",
                     const std::string& type = "frame") {
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<document version="1.5.0">
  <chunk label="Chunk 1" enabled="true">
    <sensors next_id="1">
      <sensor id="0" label="cam" type=")" +
         type + R"(">
        <resolution width="1000" height="800"/>)" +
         calibration + R"(
      </sensor>
    </sensors>)" +
         extra + R"(
    <cameras next_id="2" next_group_id="0">)" +
         cameras + R"(
    </cameras>)" +
         chunk_transform + R"(
  </chunk>
</document>
)";
}

// Camera-to-chunk: no rotation, centre (1, 0, 0).
const char* kCamera = R"(
      <camera id="0" sensor_id="0" label="IMG_0001.JPG">
        <transform>1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1</transform>
      </camera>)";

// The chunk's world: X = s R X_chunk + t, R 90 degrees about z
// (x -> y, y -> -x), t = (10, 20, 30), s = 2.
const char* kChunkTransform = R"(
    <transform>
      <rotation locked="false">0 -1 0 1 0 0 0 0 1</rotation>
      <translation locked="false">10 20 30</translation>
      <scale locked="true">2</scale>
    </transform>)";

Expected<CameraFile> read(const std::string& text) {
  return metashape_from_xml(text, "cameras.xml");
}

TEST(Metashape, ACameraWorkedOutByHand) {
  Expected<CameraFile> f = read(document(kCamera, kChunkTransform));
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->format, CameraFormat::kMetashape);
  ASSERT_EQ(f->cameras.size(), 1u);
  EXPECT_EQ(f->cameras[0].image, "IMG_0001.JPG");
  const CameraProjector& c = f->cameras[0].camera;
  // fx = f + b1 = 1005, fy = f = 1000, principal point (w/2 + cx, h/2 + cy)
  // = (510, 380); OpenCV's p1 is Agisoft's p2 (0.002), its p2 Agisoft's p1.
  EXPECT_EQ(c.spec().model, CameraModel::kOpenCV);
  EXPECT_EQ(c.spec().params, (std::vector<double>{1005, 1000, 510, 380, -0.1, 0.01, 0.002, 0.001}));
  // Centre: s R (1, 0, 0) + t = 2 (0, 1, 0) + (10, 20, 30) = (10, 22, 30);
  // the camera's axes in the world are R's columns: x (0, 1, 0), y
  // (-1, 0, 0), z (forward) (0, 0, 1).
  EXPECT_NEAR(length(c.centre() - Vec3{10, 22, 30}), 0, 1e-12);
  // P = C + 0.4 x - 0.2 y + 4 z = (10.2, 22.4, 34): camera (0.4, -0.2, 4),
  // x = 0.1, y = -0.05, r^2 = 0.0125, radial = 1 - 0.1 r^2 + 0.01 r^4 =
  // 0.9987515625. Agisoft's model:
  // x' = x radial + p1 (r^2 + 2x^2) + 2 p2 x y
  //    = 0.09987515625 + 0.001 * 0.0325 - 0.002 * 0.01 = 0.09988765625
  // y' = y radial + p2 (r^2 + 2y^2) + 2 p1 x y
  //    = -0.049937578125 + 0.002 * 0.0175 - 0.001 * 0.01 = -0.049912578125
  // u = 500 + 10 + x' (1000 + 5) = 610.38709453125
  // v = 400 - 20 + y' 1000 = 330.087421875
  const CameraProjection p = c.project({10.2, 22.4, 34});
  ASSERT_TRUE(p.inside);
  EXPECT_NEAR(p.pixel.x, 610.38709453125, 1e-9);
  EXPECT_NEAR(p.pixel.y, 330.087421875, 1e-9);
  EXPECT_NEAR(p.depth, 4, 1e-12);
  ASSERT_EQ(f->notes.size(), 1u);
  EXPECT_NE(f->notes[0].find("placed in the chunk's world frame"), std::string::npos);
}

TEST(Metashape, AComponentsTransformWinsAndUnalignedCamerasAreLeftOut) {
  // Metashape 2: the camera's component holds the transform (the chunk's,
  // here a wrong one, is not used for it).
  const std::string components = R"(
    <components next_id="1" active_id="0">
      <component id="0" label="Component 1">
        <transform>
          <rotation locked="true">0 -1 0 1 0 0 0 0 1</rotation>
          <translation locked="true">10 20 30</translation>
          <scale locked="true">2</scale>
        </transform>
      </component>
    </components>)";
  const std::string cameras = R"(
      <group id="0" label="Group 1" type="folder">
        <camera id="0" sensor_id="0" component_id="0" label="IMG_0001.JPG">
          <transform>1 0 0 1 0 1 0 0 0 0 1 0 0 0 0 1</transform>
        </camera>
      </group>
      <camera id="1" sensor_id="0" component_id="0" label="IMG_0002.JPG"/>)";
  const std::string wrong = R"(
    <transform><translation>100 0 0</translation></transform>)";
  Expected<CameraFile> f = read(document(cameras, wrong, kCalibration, components));
  ASSERT_TRUE(f) << f.error().message;
  ASSERT_EQ(f->cameras.size(), 1u);
  EXPECT_NEAR(length(f->cameras[0].camera.centre() - Vec3{10, 22, 30}), 0, 1e-12);
  ASSERT_EQ(f->notes.size(), 2u);
  EXPECT_NE(f->notes[1].find("1 camera is not aligned (no <transform>) and left out"),
            std::string::npos)
      << f->notes[1];
  // Without any transform the chunk is the world: no note.
  f = read(document(kCamera));
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_TRUE(f->notes.empty());
  EXPECT_NEAR(length(f->cameras[0].camera.centre() - Vec3{1, 0, 0}), 0, 1e-12);
}

TEST(Metashape, LensesMapExactly) {
  // No distortion: PINHOLE, square pixels without b1.
  Expected<CameraFile> f = read(document(kCamera, "", R"(
        <calibration type="frame" class="adjusted">
          <resolution width="1000" height="800"/><f>900</f><k1>0</k1>
        </calibration>)"));
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->cameras[0].camera.spec().model, CameraModel::kPinhole);
  EXPECT_EQ(f->cameras[0].camera.spec().params, (std::vector<double>{900, 900, 500, 400}));
  // k3: FULL_OPENCV with k4..k6 = 0.
  f = read(document(kCamera, "", R"(
        <calibration type="frame" class="adjusted">
          <resolution width="1000" height="800"/><f>900</f><k1>0.1</k1><k3>0.02</k3>
        </calibration>)"));
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->cameras[0].camera.spec().params,
            (std::vector<double>{900, 900, 500, 400, 0.1, 0, 0, 0, 0.02, 0, 0, 0}));
  // A fisheye: (x, y) = (x0, y0) atan(r0) / r0 then Agisoft's radial on
  // theta = OpenCV's fisheye. X = (1, 0, 1): theta = pi/4, u = 500 + 500
  // theta (1 + 0.05 theta^2) = 904.8109085269663, v = 400.
  f = read(document(kCamera, "", R"(
        <calibration type="fisheye" class="adjusted">
          <resolution width="1000" height="800"/><f>500</f><k1>0.05</k1><k4>0.001</k4>
        </calibration>)",
                    "", "fisheye"));
  ASSERT_TRUE(f) << f.error().message;
  const CameraProjector& c = f->cameras[0].camera;
  EXPECT_EQ(c.spec().model, CameraModel::kOpenCVFisheye);
  EXPECT_EQ(c.spec().params, (std::vector<double>{500, 500, 500, 400, 0.05, 0, 0, 0.001}));
  const double t = std::numbers::pi / 4;
  const Vec2 px = c.pixel_of_normalised(1, 0);
  EXPECT_NEAR(px.x, 500 + 500 * t * (1 + 0.05 * t * t + 0.001 * std::pow(t, 8)), 1e-9);
  EXPECT_NEAR(px.y, 400, 1e-12);
}

TEST(Metashape, BadFilesNameTheLineAndTheTerm) {
  const auto calib = [](const std::string& terms) {
    return "\n        <calibration type=\"frame\" class=\"adjusted\">\n          <resolution "
           "width=\"1000\" height=\"800\"/><f>900</f>" +
           terms + "\n        </calibration>";
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {document(kCamera, "", calib("<b2>0.5</b2>")),
       "cameras.xml line 5: sensor 0: b2 is 0.5: skew (non-orthogonality) has no COLMAP camera "
       "model"},
      {document(kCamera, "", calib("<k4>0.01</k4>")),
       "cameras.xml line 5: sensor 0: k4 is 0.01: a radial r^8 term"},
      {document(kCamera, "", calib("<p3>0.01</p3>")),
       "cameras.xml line 5: sensor 0: p3 is 0.01: higher-order tangential terms"},
      {document(kCamera, "", calib("<p5>0.01</p5>")),
       "cameras.xml line 8: sensor 0: <p5> is not a term of Agisoft's camera model"},
      {document(kCamera, "", calib("<k1>abc</k1>")),
       "cameras.xml line 8: sensor 0: <k1>: 'abc' is not a finite number"},
      {document(kCamera, "", "<calibration type=\"spherical\"/>", "", "spherical"),
       "cameras.xml line 5: sensor 0: a spherical sensor, which no COLMAP camera model describes"},
      {document(kCamera, "", ""), "cameras.xml line 5: sensor 0 has no <calibration>"},
      {document(R"(
      <camera id="0" sensor_id="3" label="a.jpg"><transform>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</transform></camera>)"),
       "cameras.xml line 15: camera 0 (a.jpg): sensor_id 3 names no <sensor>"},
      {document(R"(
      <camera id="0" sensor_id="0" label="a.jpg"><transform>1 0 0 0 0 1 0 0 0 0 1 0</transform></camera>)"),
       "cameras.xml line 15: camera 0 (a.jpg): <transform> must hold 16 numbers, not 12"},
      {document(R"(
      <camera id="0" sensor_id="0" label="a.jpg"><transform>1 0.1 0 0 0 1 0 0 0 0 1 0 0 0 0 1</transform></camera>)"),
       "cameras.xml line 15: camera 0 (a.jpg): <transform>: the rotation is not orthonormal"},
      {document(kCamera, R"(
    <transform><rotation>1 0 0 0 1 0 0 0 -1</rotation></transform>)"),
       "cameras.xml line 19: the chunk's <transform>: <rotation>: the rotation is a reflection"},
      {document(kCamera, R"(
    <transform><scale>0</scale></transform>)"),
       "cameras.xml line 19: the chunk's <transform>: <scale> must be positive"},
      {document(R"(
      <camera id="0" sensor_id="0" label="a.jpg"/>)"),
       "cameras.xml line 14: no aligned camera"},
      {"<document><chunk></chunk><chunk></chunk></document>",
       "cameras.xml line 1: more than one <chunk>"},
      {"<document>\n<chunk>\n<sensors>\n</chunk>", "cameras.xml line 4: not valid XML"},
      {"<doc/>", "cameras.xml: not a Metashape cameras file (no <document> element)"},
  };
  for (const auto& [text, message] : cases) {
    Expected<CameraFile> f = read(text);
    ASSERT_FALSE(f) << text;
    EXPECT_EQ(f.error().code, ErrorCode::kParse);
    EXPECT_EQ(f.error().message.rfind(message, 0), 0u)
        << "got: " << f.error().message << "\n  want: " << message;
  }
}

TEST(Metashape, ToldByItsContent) {
  Expected<CameraFile> f = camera_file_from_text("\n  " + document(kCamera), "x.dat");
  ASSERT_TRUE(f) << f.error().message;
  EXPECT_EQ(f->format, CameraFormat::kMetashape);
}

}  // namespace
}  // namespace texbake
