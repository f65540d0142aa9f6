// COLMAP sparse models (mesh_io/colmap_model.h): a text model written here by
// hand, the same model in COLMAP's binary layout (written here byte by byte
// from doc/format.rst, independently of the reader), identical cameras from
// both, and every bad input an error naming the file and line or record.
#include "mesh_io/colmap_model.h"

#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

namespace texbake {
namespace {

namespace fs = std::filesystem;

class ColmapModel : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ =
        fs::path(::testing::TempDir()) /
        ("colmap_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
  }
  fs::path dir_;
};

const char* kCamerasTxt =
    "# CameraProjector list with one line of data per camera:\n"
    "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
    "# Number of cameras: 2\n"
    "1 PINHOLE 640 480 500 510 320 240\n"
    "2 OPENCV 1920 1080 1400 1380 960.5 540.5 -0.2 0.05 0.001 -0.002\n";

// Image 7 with camera 2 and a 2D-point line; image 3 with camera 1 and an
// empty 2D-point line. q of image 7: (0.8, 0.2, -0.4, 0.4) / |.| = 1.
const char* kImagesTxt =
    "# Image list with two lines of data per image:\n"
    "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
    "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
    "7 0.8 0.2 -0.4 0.4 0.1 -0.2 3.5 2 shots/IMG 0007.jpg\n"
    "100.5 200.25 -1 300 400 12\n"
    "3 1 0 0 0 0 0 5 1 IMG_0003.png\n"
    "\n";

template <class T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  out.append(b, sizeof(T));
}

std::string cameras_bin() {
  std::string b;
  put<uint64_t>(b, 2);
  put<uint32_t>(b, 1), put<int32_t>(b, 1), put<uint64_t>(b, 640), put<uint64_t>(b, 480);
  for (double v : {500.0, 510.0, 320.0, 240.0}) put(b, v);
  put<uint32_t>(b, 2), put<int32_t>(b, 4), put<uint64_t>(b, 1920), put<uint64_t>(b, 1080);
  for (double v : {1400.0, 1380.0, 960.5, 540.5, -0.2, 0.05, 0.001, -0.002}) put(b, v);
  return b;
}

std::string images_bin() {
  std::string b;
  put<uint64_t>(b, 2);
  put<uint32_t>(b, 7);
  for (double v : {0.8, 0.2, -0.4, 0.4, 0.1, -0.2, 3.5}) put(b, v);
  put<uint32_t>(b, 2);
  b += std::string("shots/IMG 0007.jpg") + '\0';
  put<uint64_t>(b, 2);
  for (int k = 0; k < 2; ++k) put(b, 100.5), put(b, 200.25), put<uint64_t>(b, 12);
  put<uint32_t>(b, 3);
  for (double v : {1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0}) put(b, v);
  put<uint32_t>(b, 1);
  b += std::string("IMG_0003.png") + '\0';
  put<uint64_t>(b, 0);
  return b;
}

void expect_the_model(const std::vector<ColmapImage>& images) {
  ASSERT_EQ(images.size(), 2u);
  EXPECT_EQ(images[0].image_id, 7u);
  EXPECT_EQ(images[0].camera_id, 2u);
  EXPECT_EQ(images[0].name, "shots/IMG 0007.jpg");
  EXPECT_EQ(images[0].camera.spec().model, CameraModel::kOpenCV);
  EXPECT_EQ(images[0].camera.spec().width, 1920);
  EXPECT_EQ(images[0].camera.spec().params.size(), 8u);
  EXPECT_EQ(images[0].camera.spec().params[6], 0.001);
  // The quaternion (0.8, 0.2, -0.4, 0.4): row 0 of R = (1 - 2(y^2 + z^2),
  // 2(xy - wz), 2(xz + wy)) = (0.36, -0.8, -0.48).
  EXPECT_NEAR(images[0].camera.spec().pose.r[0], 0.36, 1e-15);
  EXPECT_NEAR(images[0].camera.spec().pose.r[1], -0.8, 1e-15);
  EXPECT_NEAR(images[0].camera.spec().pose.r[2], -0.48, 1e-15);
  EXPECT_EQ(images[1].image_id, 3u);
  EXPECT_EQ(images[1].name, "IMG_0003.png");
  // Identity rotation, t = (0, 0, 5): the centre is (0, 0, -5); the origin
  // projects to the principal point (320, 240).
  EXPECT_EQ(images[1].camera.centre(), (Vec3{0, 0, -5}));
  const CameraProjection p = images[1].camera.project({0, 0, 0});
  EXPECT_TRUE(p.inside);
  EXPECT_DOUBLE_EQ(p.pixel.x, 320);
  EXPECT_DOUBLE_EQ(p.pixel.y, 240);
}

TEST_F(ColmapModel, ReadsTheTextModel) {
  write("cameras.txt", kCamerasTxt);
  write("images.txt", kImagesTxt);
  Expected<std::vector<ColmapImage>> m = read_colmap_model(dir_);
  ASSERT_TRUE(m) << m.error().message;
  expect_the_model(*m);
}

TEST_F(ColmapModel, BinaryAndTextGiveTheSameCameras) {
  write("cameras.bin", cameras_bin());
  write("images.bin", images_bin());
  Expected<std::vector<ColmapImage>> bin = read_colmap_model(dir_);
  ASSERT_TRUE(bin) << bin.error().message;
  expect_the_model(*bin);
  const fs::path text_dir = dir_ / "text";
  fs::create_directories(text_dir);
  std::ofstream(text_dir / "cameras.txt") << kCamerasTxt;
  std::ofstream(text_dir / "images.txt") << kImagesTxt;
  Expected<std::vector<ColmapImage>> txt = read_colmap_model(text_dir);
  ASSERT_TRUE(txt) << txt.error().message;
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ((*bin)[i].camera.spec().pose.r, (*txt)[i].camera.spec().pose.r);
    EXPECT_EQ((*bin)[i].camera.spec().pose.t, (*txt)[i].camera.spec().pose.t);
    EXPECT_EQ((*bin)[i].camera.spec().params, (*txt)[i].camera.spec().params);
  }
}

TEST_F(ColmapModel, BinaryIsPreferredWhenBothArePresent) {
  write("cameras.bin", cameras_bin());
  write("images.bin", images_bin());
  write("cameras.txt", "1 FOO 1 1\n");  // would be an error if read
  write("images.txt", kImagesTxt);
  EXPECT_TRUE(read_colmap_model(dir_));
}

struct BadText {
  const char* cameras;
  const char* images;
  const char* message;
};

TEST_F(ColmapModel, BadTextModelsNameTheFileAndLine) {
  const std::vector<BadText> cases = {
      {"1 FOO 640 480 1 2 3\n", kImagesTxt, "cameras.txt line 1: unknown camera model FOO"},
      {"# c\n1 PINHOLE 640 480 500 510 320\n", kImagesTxt,
       "cameras.txt line 2: PINHOLE takes 4 parameters, got 3"},
      {"1 PINHOLE 640 480 500 510 320 240\n1 PINHOLE 640 480 500 510 320 240\n", kImagesTxt,
       "cameras.txt line 2: camera id 1 appears twice"},
      {"1 PINHOLE 0 480 500 510 320 240\n", kImagesTxt,
       "cameras.txt line 1: the width and height must be positive"},
      {"1 PINHOLE 640 480 500 nan 320 240\n", kImagesTxt,
       "cameras.txt line 1: a camera parameter is not a finite number"},
      {kCamerasTxt, "7 0.8 0.2 -0.4 0.4 0.1 -0.2 3.5 9 a.jpg\n\n",
       "images.txt line 1: image 7 names camera id 9, which cameras.txt does not define"},
      {kCamerasTxt, "7 0.9 0.2 -0.4 0.4 0.1 -0.2 3.5 2 a.jpg\n\n",
       "images.txt line 1: the quaternion is not a unit quaternion"},
      {kCamerasTxt, "7 0.8 0.2 -0.4 0.4 0.1 -0.2 3.5 2\n\n",
       "images.txt line 1: expected IMAGE_ID QW QX QY QZ TX TY TZ CAMERA_ID NAME"},
      {kCamerasTxt, "3 1 0 0 0 0 0 5 1 a.png\n\n3 1 0 0 0 0 0 5 1 b.png\n\n",
       "images.txt line 3: image id 3 appears twice"},
      {kCamerasTxt, "# nothing\n", "images.txt: the model has no registered image"},
  };
  for (const BadText& c : cases) {
    write("cameras.txt", c.cameras);
    write("images.txt", c.images);
    Expected<std::vector<ColmapImage>> m = read_colmap_model(dir_);
    ASSERT_FALSE(m) << c.message;
    EXPECT_EQ(m.error().code, ErrorCode::kParse) << m.error().message;
    EXPECT_EQ(m.error().message.rfind(c.message, 0), 0u)
        << "got: " << m.error().message << "\nwant: " << c.message;
  }
}

TEST_F(ColmapModel, BadBinaryModelsNameTheFileAndRecord) {
  const std::string cams = cameras_bin(), imgs = images_bin();
  struct Case {
    std::string cameras, images;
    const char* message;
  };
  std::string unknown_model = cams;
  unknown_model[8 + 4] = 9;  // the first camera's model id
  std::string huge_count = imgs;
  huge_count[7] = 1;  // 2^56 + 2 images
  const std::vector<Case> cases = {
      {cams.substr(0, cams.size() - 3), imgs, "cameras.bin: truncated in record 2"},
      {cams, imgs.substr(0, imgs.size() - 20), "images.bin: truncated in record 2"},
      {cams, imgs.substr(0, 100), "images.bin: declares 2 records, more than the file can hold"},
      {cams + "xyz", imgs, "cameras.bin: 3 bytes after the last record"},
      {unknown_model, imgs, "cameras.bin record 1: unknown camera model id 9"},
      {cams, huge_count, "images.bin: declares"},
      {cams.substr(0, 5), imgs, "cameras.bin: truncated in record 0"},
  };
  for (const Case& c : cases) {
    write("cameras.bin", c.cameras);
    write("images.bin", c.images);
    Expected<std::vector<ColmapImage>> m = read_colmap_model(dir_);
    ASSERT_FALSE(m) << c.message;
    EXPECT_EQ(m.error().code, ErrorCode::kParse) << m.error().message;
    EXPECT_EQ(m.error().message.rfind(c.message, 0), 0u)
        << "got: " << m.error().message << "\nwant: " << c.message;
  }
}

TEST_F(ColmapModel, WrittenModelsReadBackInBothForms) {
  write("cameras.txt", kCamerasTxt);
  write("images.txt", kImagesTxt);
  Expected<std::vector<ColmapImage>> model = read_colmap_model(dir_);
  ASSERT_TRUE(model) << model.error().message;
  for (bool binary : {false, true}) {
    const fs::path out = dir_ / (binary ? "bin" : "txt");
    ASSERT_TRUE(write_colmap_model(out, *model, binary));
    EXPECT_TRUE(fs::exists(out / (binary ? "cameras.bin" : "cameras.txt")));
    Expected<std::vector<ColmapImage>> back = read_colmap_model(out);
    ASSERT_TRUE(back) << back.error().message;
    ASSERT_EQ(back->size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      const CameraSpec &a = (*model)[i].camera.spec(), &b = (*back)[i].camera.spec();
      EXPECT_EQ((*back)[i].name, (*model)[i].name);
      EXPECT_EQ((*back)[i].image_id, (*model)[i].image_id);
      EXPECT_EQ(b.model, a.model);
      EXPECT_EQ(b.params, a.params);
      EXPECT_EQ(b.pose.t, a.pose.t);
      // R -> quaternion -> R: equal to rounding.
      for (int k = 0; k < 9; ++k) EXPECT_NEAR(b.pose.r[k], a.pose.r[k], 1e-15);
    }
  }
  // Text and binary hold the same numbers: the cameras read from them are equal.
  Expected<std::vector<ColmapImage>> txt = read_colmap_model(dir_ / "txt");
  Expected<std::vector<ColmapImage>> bin = read_colmap_model(dir_ / "bin");
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ((*txt)[i].camera.spec().pose.r, (*bin)[i].camera.spec().pose.r);
  }
}

TEST_F(ColmapModel, MissingModelsAreIoErrors) {
  Expected<std::vector<ColmapImage>> none = read_colmap_model(dir_);
  ASSERT_FALSE(none);
  EXPECT_EQ(none.error().code, ErrorCode::kIo);
  EXPECT_NE(none.error().message.find("no COLMAP model"), std::string::npos);
  write("cameras.txt", kCamerasTxt);  // images.txt missing
  EXPECT_FALSE(read_colmap_model(dir_));
  Expected<std::vector<ColmapImage>> folder = read_colmap_model(dir_ / "missing");
  ASSERT_FALSE(folder);
  EXPECT_EQ(folder.error().code, ErrorCode::kIo);
}

}  // namespace
}  // namespace texbake
