// mesh_named_files (mesh_io/mesh_files.h): the files an OBJ, a .gltf and
// a .glb name, written out by hand, wherever they sit in the file.
#include "mesh_io/mesh_files.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace texbake {
namespace {

namespace fs = std::filesystem;

class MeshFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_mesh_files_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
  }
  fs::path dir_;
};

TEST_F(MeshFiles, AnObjNamesItsLibrariesAndTheirTexturesAnywhereInTheFile) {
  // Over 1 MiB of vertices first, so that the second library's line comes
  // after the first block (and a CRLF line end, and a name with a space).
  std::string obj = "mtllib a.mtl\r\n";
  while (obj.size() < (std::size_t{3} << 20) / 2) obj += "v 0.125 0.25 0.5\n";
  obj += "  mtllib my lib.mtl\nmtllib missing.mtl\nf 1 1 1\n# mtllib comment.mtl\n";
  write("m.obj", obj);
  write("a.mtl", "newmtl a\nmap_Kd ta.png\n");
  write("my lib.mtl", "newmtl b\n\tmap_Kd sub/tb.png\nmap_Kd gone.png\n");
  write("comment.mtl", "");
  write("ta.png", "x");
  fs::create_directories(dir_ / "sub");
  write("sub/tb.png", "x");
  const std::vector<fs::path> expected{dir_ / "a.mtl", dir_ / "ta.png", dir_ / "my lib.mtl",
                                       dir_ / "sub/tb.png"};
  std::vector<fs::path> got = mesh_named_files(dir_ / "m.obj");
  for (fs::path& p : got) p = p.lexically_normal();
  EXPECT_EQ(got, expected);
}

TEST_F(MeshFiles, AGltfNamesItsExternalBuffersAndImagesButNotDataUris) {
  write("g.gltf",
        R"({"asset":{"version":"2.0"},"buffers":[{"uri":"b%201.bin"},{"uri":"data:,abcd"}],)"
        R"("images":[{"uri":"i.png"},{"uri":"none.png"},{"bufferView":0}]})");
  write("b 1.bin", "abcd");
  write("i.png", "x");
  std::vector<fs::path> got = mesh_named_files(dir_ / "g.gltf");
  EXPECT_EQ(got, (std::vector<fs::path>{dir_ / "b 1.bin", dir_ / "i.png"}));
}

// A .glb whose JSON chunk names an external image and buffer (a binary
// glTF may; most embed them), laid out by hand: the 12-byte header
// "glTF", 2, total length; the chunk's length, "JSON", the text padded
// with spaces to 4 bytes.
TEST_F(MeshFiles, AGlbNamesTheExternalFilesOfItsJsonChunk) {
  std::string json = R"({"asset":{"version":"2.0"},"buffers":[{"uri":"ext.bin"}],)"
                     R"("images":[{"uri":"tex%20a.png"}]})";
  while (json.size() % 4) json += ' ';
  auto le32 = [](std::uint32_t v) {
    return std::string{static_cast<char>(v & 255), static_cast<char>((v >> 8) & 255),
                       static_cast<char>((v >> 16) & 255), static_cast<char>(v >> 24)};
  };
  const std::uint32_t total = 12 + 8 + static_cast<std::uint32_t>(json.size());
  write("m.glb", "glTF" + le32(2) + le32(total) + le32(json.size()) + "JSON" + json);
  write("ext.bin", "abcd");
  write("tex a.png", "x");
  EXPECT_EQ(mesh_named_files(dir_ / "m.glb"),
            (std::vector<fs::path>{dir_ / "ext.bin", dir_ / "tex a.png"}));
  // A chunk that claims more than the file holds, or a file that is not a
  // binary glTF, names nothing.
  write("long.glb", "glTF" + le32(2) + le32(total) + le32(1u << 30) + "JSON" + json);
  write("text.glb", "solid not a glb\n");
  EXPECT_TRUE(mesh_named_files(dir_ / "long.glb").empty());
  EXPECT_TRUE(mesh_named_files(dir_ / "text.glb").empty());
}

TEST_F(MeshFiles, OtherFormatsAndUnreadableFilesNameNothing) {
  write("m.ply", "ply\n");
  write("bad.gltf", "{not json");
  EXPECT_TRUE(mesh_named_files(dir_ / "m.ply").empty());
  EXPECT_TRUE(mesh_named_files(dir_ / "bad.gltf").empty());
  EXPECT_TRUE(mesh_named_files(dir_ / "absent.obj").empty());
  // A device is not scanned (an endless /dev/zero would hang the job's
  // file check; read_mesh reports it instead).
  fs::create_symlink("/dev/zero", dir_ / "zero.obj");
  fs::create_directories(dir_ / "folder.obj");
  EXPECT_TRUE(mesh_named_files(dir_ / "zero.obj").empty());
  EXPECT_TRUE(mesh_named_files(dir_ / "folder.obj").empty());
}

}  // namespace
}  // namespace texbake
