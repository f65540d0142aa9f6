// The bad-input corpus (tests/data/bad, SPEC section 8): each file gives an
// error of the right kind whose message names the file and says what is wrong.
#include <gtest/gtest.h>

#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "mesh_io/write_mesh.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

struct BadMesh {
  const char* file;
  ErrorCode code;
  const char* says;  // substring of the message
};

class BadMeshInput : public ::testing::TestWithParam<BadMesh> {};

TEST_P(BadMeshInput, GivesItsErrorNamingTheFile) {
  const BadMesh& c = GetParam();
  const fs::path path = test::bad_dir() / c.file;
  Expected<LoadedMesh> m = read_mesh(path);
  ASSERT_FALSE(m.has_value()) << c.file << " was accepted";
  EXPECT_EQ(m.error().code, c.code) << m.error().message;
  EXPECT_NE(m.error().message.find(path.string()), std::string::npos) << m.error().message;
  EXPECT_NE(m.error().message.find(c.says), std::string::npos) << m.error().message;
}

INSTANTIATE_TEST_SUITE_P(
    Corpus, BadMeshInput,
    ::testing::Values(
        BadMesh{"truncated_binary.ply", ErrorCode::kParse, "truncated or lying header"},
        BadMesh{"truncated_ascii.ply", ErrorCode::kParse, "truncated or lying header"},
        BadMesh{"truncated_binary_quad.ply", ErrorCode::kParse,
                "truncated: the file ends in face 1 of 2"},
        BadMesh{"truncated_ascii_quad.ply", ErrorCode::kParse,
                "truncated: the file ends in face 1 of 2 (line 16)"},
        BadMesh{"lying_header_binary.ply", ErrorCode::kParse, "lying header"},
        BadMesh{"lying_header_ascii.ply", ErrorCode::kParse,
                "line 15: data after the last element"},
        BadMesh{"out_of_range_binary.ply", ErrorCode::kParse,
                "face 1 refers to vertex 4 but there are 4"},
        BadMesh{"negative_index_binary.ply", ErrorCode::kParse, "face 1 refers to vertex -1"},
        BadMesh{"negative_index_ascii.ply", ErrorCode::kParse,
                "line 15: face 1 refers to vertex -1"},
        BadMesh{"nan_binary.ply", ErrorCode::kParse, "vertex 1 has a non-finite coordinate"},
        BadMesh{"nan.off", ErrorCode::kParse,
                "line 5: vertex coordinate 'nan' is not a finite number"},
        BadMesh{"out_of_range.off", ErrorCode::kParse, "line 8: face index '4' is out of range"},
        BadMesh{"truncated.off", ErrorCode::kParse, "truncated"},
        BadMesh{"empty.off", ErrorCode::kParse, "no faces"},
        BadMesh{"inf.obj", ErrorCode::kParse,
                "line 3: vertex coordinate 'inf' is not a finite number"},
        BadMesh{"out_of_range.obj", ErrorCode::kParse, "line 5: face index 4 is out of range"},
        BadMesh{"negative_out_of_range.obj", ErrorCode::kParse,
                "line 4: face index -4 is out of range"},
        BadMesh{"zero_index.obj", ErrorCode::kParse, "line 4: face index 0 is out of range"},
        BadMesh{"empty.obj", ErrorCode::kParse, "no faces"},
        BadMesh{"empty_file.ply", ErrorCode::kParse, "empty"},
        BadMesh{"truncated_binary.stl", ErrorCode::kParse, "truncated binary STL"},
        BadMesh{"mesh.xyz", ErrorCode::kParse, "unknown mesh format '.xyz'"},
        BadMesh{"missing.ply", ErrorCode::kIo, "no such file"}),
    [](const auto& info) {
      std::string n = info.param.file;
      for (char& ch : n) {
        if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
      }
      return n;
    });

TEST(BadMeshInputFolder, FolderGivenAsMeshFile) {
  const fs::path dir = test::fresh_temp_dir("folder") / "looks_like.ply";
  fs::create_directories(dir);
  Expected<LoadedMesh> m = read_mesh(dir);
  ASSERT_FALSE(m.has_value());
  EXPECT_EQ(m.error().code, ErrorCode::kIo);
  EXPECT_NE(m.error().message.find(dir.string() + ": is a folder"), std::string::npos)
      << m.error().message;
  fs::remove_all(dir.parent_path());
}

class BadImageInput : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("badimg");
  void TearDown() override { fs::remove_all(dir); }

  void expect_error(const fs::path& path, ErrorCode code, const std::string& says) {
    Expected<Image> img = read_image(path);
    ASSERT_FALSE(img.has_value()) << path << " was accepted";
    EXPECT_EQ(img.error().code, code) << img.error().message;
    EXPECT_NE(img.error().message.find(path.string()), std::string::npos) << img.error().message;
    EXPECT_NE(img.error().message.find(says), std::string::npos) << img.error().message;
  }
  // A valid 64x64 noisy image written by texbake, then cut to half its size.
  fs::path truncated(const std::string& name) {
    Image img;
    img.width = img.height = 64;
    img.pixels.resize(64 * 64 * 4);
    for (std::size_t i = 0; i < img.pixels.size(); ++i)
      img.pixels[i] = static_cast<float>((i * 7919) % 256) / 255.f;
    const fs::path full = dir / ("full_" + name);
    EXPECT_TRUE(write_image(full, img.view()).has_value());
    const std::string bytes = test::read_bytes(full);
    return test::write_text(dir / name, bytes.substr(0, bytes.size() / 2));
  }
};

TEST_F(BadImageInput, ZeroBytePng) {
  expect_error(test::write_text(dir / "zero.png", ""), ErrorCode::kParse, "empty");
}
TEST_F(BadImageInput, ZeroByteJpeg) {
  expect_error(test::write_text(dir / "zero.jpg", ""), ErrorCode::kParse, "empty");
}
TEST_F(BadImageInput, TruncatedPng) {
  expect_error(truncated("cut.png"), ErrorCode::kParse, "cannot decode");
}
TEST_F(BadImageInput, TruncatedJpeg) {
  expect_error(truncated("cut.jpg"), ErrorCode::kParse, "cannot decode");
}
TEST_F(BadImageInput, NotAnImage) {
  expect_error(test::write_text(dir / "text.png", "this is not a PNG file at all\n"),
               ErrorCode::kParse, "cannot read as an image");
}
TEST_F(BadImageInput, MissingFile) {
  expect_error(dir / "missing.png", ErrorCode::kIo, "no such file");
}
TEST_F(BadImageInput, FolderGivenAsImage) {
  fs::create_directories(dir / "img.png");
  expect_error(dir / "img.png", ErrorCode::kIo, "is a folder");
}

TEST(BadOutput, MissingFolderLeavesNoFile) {
  const fs::path dir = test::fresh_temp_dir("badout");
  MeshData mesh;
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  mesh.face_offsets = {0, 3};
  mesh.face_vertices = {0, 1, 2};
  Status s = write_mesh(dir / "no" / "such" / "out.ply", mesh);
  ASSERT_FALSE(s.has_value());
  EXPECT_EQ(s.error().code, ErrorCode::kIo);
  EXPECT_NE(s.error().message.find("out.ply"), std::string::npos);
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace texbake
