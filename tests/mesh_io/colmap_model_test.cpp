// COLMAP sparse models (mesh_io/colmap_model.h): a text model written here by
// hand, the same model in COLMAP's binary layout (written here byte by byte
// from doc/format.rst, independently of the reader), identical cameras from
// both, and every bad input an error naming the file and line or record.
#include "mesh_io/colmap_model.h"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "mesh_io/atomic_file.h"

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
       "cameras.txt line 1: camera id 1: a camera parameter is not a finite number (nan)"},
      // Bad intrinsics are the camera's line, not the first image using it.
      {"# c\n\n2 OPENCV 1920 1080 1400 1380 960.5 540.5 0 0 0 0\n"
       "1 PINHOLE 640 480 0 510 320 240\n",
       kImagesTxt,
       "cameras.txt line 4: camera id 1: PINHOLE: the focal length must be positive (got 0)"},
      {"1 PINHOLE 640 480 500 510 320 240\n2 SIMPLE_PINHOLE 1920 1080 -1400 960 540\n", kImagesTxt,
       "cameras.txt line 2: camera id 2: SIMPLE_PINHOLE: the focal length must be positive "
       "(got -1400)"},
      {"1 PINHOLE 640 480 1e-310 510 320 240\n", kImagesTxt,
       "cameras.txt line 1: camera id 1: PINHOLE: the focal length must be positive (got "
       "1e-310)"},
      {"1 PINHOLE 640 480 500 510 -320 240\n", kImagesTxt,
       "cameras.txt line 1: camera id 1: PINHOLE: the principal point (-320, 240) is outside "
       "the 640 x 480 image"},
      // (The last parameter too: it read as a missing one before.)
      {"1 PINHOLE 640 480 500 510 320 inf\n", kImagesTxt,
       "cameras.txt line 1: camera id 1: a camera parameter is not a finite number (inf)"},
      {"1 PINHOLE 640 480 500 510 320 1e999\n", kImagesTxt,
       "cameras.txt line 1: camera id 1: a camera parameter is not a finite number (1e999)"},
      {kCamerasTxt, "7 0.8 0.2 -0.4 0.4 0.1 -0.2 3.5 9 a.jpg\n\n",
       "images.txt line 1: image 7 names camera id 9, which cameras.txt does not define"},
      {kCamerasTxt, "7 0 0 0 0 0.1 -0.2 3.5 2 a.jpg\n\n",
       "images.txt line 1: the quaternion is zero (no rotation)"},
      // One line per image (no POINTS2D lines): the second image's line is
      // where its first image's points should be.
      {kCamerasTxt,
       "# one line per image\n3 1 0 0 0 0 0 5 1 a.png\n4 1 0 0 0 0 0 6 1 b.png\n"
       "5 1 0 0 0 0 0 7 1 c.png\n",
       "images.txt line 3: expected the 2D points of the image on line 2 (X Y POINT3D_ID "
       "triples, possibly none): COLMAP's images.txt has two lines per image"},
      {kCamerasTxt, "3 1 0 0 0 0 0 5 1 a.png\n1 2 -1 4 5\n",
       "images.txt line 2: expected the 2D points of the image on line 1"},
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

TEST_F(ColmapModel, SixDigitQuaternionsAreNormalised) {
  // (0.8, 0.2, -0.4, 0.4) with three components rounded down in the 6th
  // digit: |q| = 1 - 1.6e-6 (refused as not unit before), read as COLMAP
  // reads it (normalised): R within 2e-6 of the exact rotation's (the
  // differences are 1.2e-6, 2.4e-7 and 4.6e-7).
  write("cameras.txt", kCamerasTxt);
  write("images.txt", "7 0.799999 0.2 -0.399999 0.399999 0.1 -0.2 3.5 2 a.jpg\n\n");
  Expected<std::vector<ColmapImage>> m = read_colmap_model(dir_);
  ASSERT_TRUE(m) << m.error().message;
  EXPECT_NEAR((*m)[0].camera.spec().pose.r[0], 0.36, 2e-6);
  EXPECT_NEAR((*m)[0].camera.spec().pose.r[1], -0.8, 2e-6);
  EXPECT_NEAR((*m)[0].camera.spec().pose.r[2], -0.48, 2e-6);
}

TEST_F(ColmapModel, BadBinaryIntrinsicsNameCamerasBinAndTheRecord) {
  // Camera 2 (record 2) with fy = NaN, then with cx = +inf and f = 0.
  auto with_param = [](int index, double value) {
    std::string b = cameras_bin();
    const std::size_t second = 8 + (24 + 4 * 8) + 24;  // camera 2's first parameter
    std::memcpy(&b[second + 8 * static_cast<std::size_t>(index)], &value, 8);
    return b;
  };
  const std::vector<std::pair<std::string, std::string>> cases = {
      {with_param(1, std::nan("")),
       "cameras.bin record 2: camera id 2: OPENCV: a camera parameter is not finite"},
      {with_param(2, INFINITY),
       "cameras.bin record 2: camera id 2: OPENCV: a camera parameter is not finite"},
      {with_param(0, 0.0),
       "cameras.bin record 2: camera id 2: OPENCV: the focal length must be positive (got 0)"},
      {with_param(1, 5e-324),
       "cameras.bin record 2: camera id 2: OPENCV: the focal length must be positive (got "
       "4.94066e-324)"},
      {with_param(3, -540.5),
       "cameras.bin record 2: camera id 2: OPENCV: the principal point (960.5, -540.5) is outside "
       "the 1920 x 1080 image"},
  };
  write("images.bin", images_bin());
  for (const auto& [cams, message] : cases) {
    write("cameras.bin", cams);
    Expected<std::vector<ColmapImage>> m = read_colmap_model(dir_);
    ASSERT_FALSE(m) << message;
    EXPECT_EQ(m.error().message.rfind(message, 0), 0u)
        << "got: " << m.error().message << "\nwant: " << message;
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

TEST_F(ColmapModel, LargeImagesBinIsReadUnderAMemoryCap) {
  // A valid images.bin of one image with 50 M 2D points (1.2 GB, a sparse
  // file: made in no time, no disk used). The points are skipped by seeking:
  // read in a child whose address space may grow by 256 MiB only (the
  // whole file held in memory cannot fit: the reader before this ended in
  // "out of memory").
  write("cameras.bin", cameras_bin());
  constexpr uint64_t kPoints = 50'000'000;
  std::string b;
  put<uint64_t>(b, 1);
  put<uint32_t>(b, 3);
  for (double v : {1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0}) put(b, v);
  put<uint32_t>(b, 1);
  b += std::string("IMG_0003.png") + '\0';
  put<uint64_t>(b, kPoints);
  write("images.bin", b);
  fs::resize_file(dir_ / "images.bin", b.size() + kPoints * 24);
  ASSERT_EQ(b.size(), 93u);  // 8 + 4 + 7 * 8 + 4 + 13 + 8
  ASSERT_EQ(fs::file_size(dir_ / "images.bin"), 1'200'000'093u);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    long pages = 0;
    std::ifstream("/proc/self/statm") >> pages;  // the address space in use, in pages
    const rlim_t cap = static_cast<rlim_t>(pages) * ::sysconf(_SC_PAGESIZE) + (rlim_t{256} << 20);
    const struct rlimit limit { cap, cap };
    if (::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(3);
    try {
      Expected<std::vector<ColmapImage>> m = read_colmap_model(dir_);
      ::_exit(m && m->size() == 1 && (*m)[0].name == "IMG_0003.png" ? 0 : 1);
    } catch (...) {
      ::_exit(2);  // std::bad_alloc
    }
  }
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "signal " << WTERMSIG(status);
  EXPECT_EQ(WEXITSTATUS(status), 0) << "1: not read, 2: out of memory, 3: no limit";
  // One point fewer than declared: truncated, named.
  fs::resize_file(dir_ / "images.bin", b.size() + kPoints * 24 - 24);
  Expected<std::vector<ColmapImage>> cut = read_colmap_model(dir_);
  ASSERT_FALSE(cut);
  EXPECT_EQ(cut.error().message, "images.bin: truncated in record 1");
}

TEST_F(ColmapModel, ImageNamesWithoutTheirNulStopAtALimit) {
  write("cameras.bin", cameras_bin());
  std::string b;
  put<uint64_t>(b, 1);
  put<uint32_t>(b, 3);
  for (double v : {1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 5.0}) put(b, v);
  put<uint32_t>(b, 1);
  b += std::string(10000, 'a');  // no NUL
  write("images.bin", b);
  Expected<std::vector<ColmapImage>> m = read_colmap_model(dir_);
  ASSERT_FALSE(m);
  EXPECT_EQ(m.error().message,
            "images.bin record 1: the image name is longer than 4096 bytes (no NUL: not a "
            "COLMAP images.bin?)");
}

TEST_F(ColmapModel, WritingOneFormReplacesTheOther) {
  // A stale binary model (the reader prefers it) and a folder's text model:
  // writing text removes the .bin files (points3D too) and writes
  // points3D.txt; writing binary then removes the .txt files.
  write("cameras.bin", cameras_bin());
  write("images.bin", images_bin());
  write("points3D.bin", std::string(8, '\0'));
  write("cameras.txt", kCamerasTxt);
  write("images.txt", kImagesTxt);
  Expected<std::vector<ColmapImage>> model = read_colmap_model(dir_ / ".");
  ASSERT_TRUE(model) << model.error().message;
  std::vector<ColmapImage> one(model->begin(), model->begin() + 1);
  ASSERT_TRUE(write_colmap_model(dir_, one, /*binary=*/false));
  for (const char* gone : {"cameras.bin", "images.bin", "points3D.bin"}) {
    EXPECT_FALSE(fs::exists(dir_ / gone)) << gone;
  }
  for (const char* kept : {"cameras.txt", "images.txt", "points3D.txt"}) {
    EXPECT_TRUE(fs::exists(dir_ / kept)) << kept;
  }
  Expected<std::vector<ColmapImage>> back = read_colmap_model(dir_);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->size(), 1u);  // the new model, not the stale one
  ASSERT_TRUE(write_colmap_model(dir_, *model, /*binary=*/true));
  for (const char* gone : {"cameras.txt", "images.txt", "points3D.txt"}) {
    EXPECT_FALSE(fs::exists(dir_ / gone)) << gone;
  }
  std::ifstream points(dir_ / "points3D.bin", std::ios::binary);
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(points), {}), std::string(8, '\0'));
  back = read_colmap_model(dir_);
  ASSERT_TRUE(back) << back.error().message;
  EXPECT_EQ(back->size(), 2u);
  EXPECT_TRUE(list_texbake_temporaries(dir_).empty());
}

TEST_F(ColmapModel, AModelThatCannotBeWrittenChangesNothing) {
  // images.txt is a folder: nothing is written, the stale binary model stays.
  write("cameras.bin", cameras_bin());
  write("images.bin", images_bin());
  fs::create_directories(dir_ / "images.txt");
  Expected<std::vector<ColmapImage>> model = read_colmap_model(dir_);
  ASSERT_TRUE(model);
  const Status s = write_colmap_model(dir_, *model, /*binary=*/false);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_NE(s.error().message.find("images.txt: it is a folder"), std::string::npos)
      << s.error().message;
  EXPECT_FALSE(fs::exists(dir_ / "cameras.txt"));
  EXPECT_FALSE(fs::exists(dir_ / "points3D.txt"));
  EXPECT_TRUE(fs::exists(dir_ / "cameras.bin"));
  EXPECT_TRUE(fs::exists(dir_ / "images.bin"));
  EXPECT_TRUE(list_texbake_temporaries(dir_).empty());
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

// The sparse points (read_colmap_points): X Y Z of each line or record,
// colours, errors and tracks skipped; the binary file when the model is binary.
TEST_F(ColmapModel, SparsePointsAreReadFromTextAndBinary) {
  write("cameras.txt", kCamerasTxt);
  write("images.txt", kImagesTxt);
  EXPECT_TRUE(read_colmap_points(dir_).value().empty());  // no points3D: none
  write("points3D.txt",
        "# 3D point list with one line of data per point:\n"
        "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
        "1 0.5 -1.25 3 255 0 0 0.7 7 0 3 1\n"
        "\n"
        "2 1e-3 2 -4.5 10 20 30 1.5\n");
  Expected<std::vector<Vec3>> text = read_colmap_points(dir_);
  ASSERT_TRUE(text) << text.error().message;
  EXPECT_EQ(*text, (std::vector<Vec3>{{0.5, -1.25, 3}, {1e-3, 2, -4.5}}));

  // The same two points in points3D.bin, beside a binary model: read instead.
  write("cameras.bin", cameras_bin());
  write("images.bin", images_bin());
  std::string b;
  put<uint64_t>(b, 2);
  put<uint64_t>(b, 1);
  for (double v : {0.5, -1.25, 3.0}) put(b, v);
  b += std::string("\xff\x00\x00", 3);
  put(b, 0.7);
  put<uint64_t>(b, 2);
  for (uint32_t v : {7u, 0u, 3u, 1u}) put(b, v);
  put<uint64_t>(b, 2);
  for (double v : {1e-3, 2.0, -4.5}) put(b, v);
  b += std::string("\x0a\x14\x1e", 3);
  put(b, 1.5);
  put<uint64_t>(b, 0);
  write("points3D.bin", b);
  Expected<std::vector<Vec3>> binary = read_colmap_points(dir_);
  ASSERT_TRUE(binary) << binary.error().message;
  EXPECT_EQ(*binary, *text);

  // Truncated in the second record's track, or trailing bytes: errors naming the file.
  write("points3D.bin", b.substr(0, b.size() - 4));
  Expected<std::vector<Vec3>> cut = read_colmap_points(dir_);
  ASSERT_FALSE(cut);
  EXPECT_NE(cut.error().message.find("points3D.bin: truncated in record 1"), std::string::npos)
      << cut.error().message;
  write("points3D.bin", b + "x");
  Expected<std::vector<Vec3>> trailing = read_colmap_points(dir_);
  ASSERT_FALSE(trailing);
  EXPECT_NE(trailing.error().message.find("trailing bytes"), std::string::npos);
  // A count that the file cannot hold is refused before anything is allocated.
  std::string huge;
  put<uint64_t>(huge, uint64_t{1} << 60);
  write("points3D.bin", huge);
  EXPECT_FALSE(read_colmap_points(dir_));
}

TEST_F(ColmapModel, BadSparsePointLinesNameTheLine) {
  write("cameras.txt", kCamerasTxt);
  write("images.txt", kImagesTxt);
  for (const char* line :
       {"1 0 0\n", "1 0 nan 0 1 2 3 0\n", "1 0 1e999 0 1 2 3 0\n", "x 0 0 0 1 2 3 0\n"}) {
    write("points3D.txt", std::string("# header\n") + line);
    Expected<std::vector<Vec3>> p = read_colmap_points(dir_);
    ASSERT_FALSE(p) << line;
    EXPECT_EQ(p.error().code, ErrorCode::kParse);
    EXPECT_NE(p.error().message.find("points3D.txt line 2"), std::string::npos)
        << p.error().message;
  }
}

}  // namespace
}  // namespace texbake
