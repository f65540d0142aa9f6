// Non-regular input files (issue #12 item 6): a FIFO or a link to /dev/zero
// given as a mesh, an image, a material library or a texture is refused with
// "not a regular file" naming the path, before anything opens it (so the
// test cannot hang: see FifoWatchdog), and text inputs are capped in size.
#include "mesh_io/regular_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <thread>

#include "mesh_io/image_io.h"
#include "mesh_io/proxy_json.h"
#include "mesh_io/read_mesh.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using test::write_text;

const std::string kTriangleObj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

// If the code under test opens the FIFO (the bug), it blocks; after a few
// seconds this opens and closes the FIFO's writing end again and again, so
// every blocked open returns and reads an empty file: the test then fails on
// its message instead of hanging.
class FifoWatchdog {
 public:
  explicit FifoWatchdog(fs::path fifo)
      : fifo_(std::move(fifo)), thread_([this] {
          const auto start = std::chrono::steady_clock::now();
          while (!done_) {
            if (std::chrono::steady_clock::now() - start > std::chrono::seconds(5)) {
              const int fd = ::open(fifo_.c_str(), O_WRONLY | O_NONBLOCK);
              if (fd >= 0) ::close(fd);
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
          }
        }) {}
  ~FifoWatchdog() {
    done_ = true;
    thread_.join();
  }

 private:
  fs::path fifo_;
  std::atomic<bool> done_{false};
  std::thread thread_;
};

class RegularFile : public ::testing::Test {
 protected:
  fs::path dir = test::fresh_temp_dir("regular");
  void TearDown() override { fs::remove_all(dir); }

  fs::path fifo(const std::string& name) {
    const fs::path p = dir / name;
    EXPECT_EQ(::mkfifo(p.c_str(), 0600), 0) << p;
    return p;
  }
  fs::path link_to_dev_zero(const std::string& name) {
    const fs::path p = dir / name;
    fs::create_symlink("/dev/zero", p);
    return p;
  }
  // `error` is kIo and says "PATH: is not a regular file (KIND)".
  static void expect_not_regular(const Error& error, const fs::path& path, const char* kind) {
    EXPECT_EQ(error.code, ErrorCode::kIo) << error.message;
    const std::string says = path.string() + ": is not a regular file (" + kind + ")";
    EXPECT_EQ(error.message.rfind(says, 0), 0u) << error.message;
  }
};

TEST_F(RegularFile, CheckGivesEachKindItsMessage) {
  const fs::path file = write_text(dir / "a.txt", "x");
  EXPECT_TRUE(check_regular_file(file, "a thing").has_value());
  fs::create_symlink(file, dir / "link.txt");
  EXPECT_TRUE(check_regular_file(dir / "link.txt", "a thing").has_value());  // link followed

  const Status missing = check_regular_file(dir / "none.txt", "a thing");
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().code, ErrorCode::kIo);
  EXPECT_EQ(missing.error().message, (dir / "none.txt").string() + ": no such file");
  fs::create_symlink(dir / "none.txt", dir / "dangling.txt");
  const Status dangling = check_regular_file(dir / "dangling.txt", "a thing");
  ASSERT_FALSE(dangling.has_value());
  EXPECT_EQ(dangling.error().message, (dir / "dangling.txt").string() + ": no such file");

  const Status folder = check_regular_file(dir, "a thing");
  ASSERT_FALSE(folder.has_value());
  EXPECT_EQ(folder.error().message, dir.string() + ": is a folder, not a thing");

  const fs::path f = fifo("pipe");
  const Status pipe = check_regular_file(f, "a thing");
  ASSERT_FALSE(pipe.has_value());
  EXPECT_EQ(pipe.error().message,
            f.string() + ": is not a regular file (a FIFO), cannot be read as a thing");
  const Status zero = check_regular_file(link_to_dev_zero("zero"), "a thing");
  ASSERT_FALSE(zero.has_value());
  expect_not_regular(zero.error(), dir / "zero", "a character device");
}

TEST_F(RegularFile, TextFileSizeLimitIs16MiB) {
  // Sparse files: no disk space used.
  const fs::path at = dir / "at.json", above = dir / "above.json";
  write_text(at, "");
  fs::resize_file(at, 16u << 20);
  write_text(above, "");
  fs::resize_file(above, (16u << 20) + 1);
  EXPECT_TRUE(check_text_file(at, "a proxy file").has_value());
  const Status s = check_text_file(above, "a proxy file");
  ASSERT_FALSE(s.has_value());
  EXPECT_EQ(s.error().code, ErrorCode::kParse);
  EXPECT_EQ(
      s.error().message,
      above.string() + ": is 16777217 bytes, more than the 16 MiB texbake reads as a proxy file");
  const Status pipe = check_text_file(fifo("pipe.json"), "a proxy file");
  ASSERT_FALSE(pipe.has_value());
  expect_not_regular(pipe.error(), dir / "pipe.json", "a FIFO");
}

TEST_F(RegularFile, FifoAsMeshIsRefusedBeforeOpening) {
  for (const char* name : {"pipe.obj", "pipe.ply", "pipe.off", "pipe.stl"}) {
    const fs::path f = fifo(name);
    FifoWatchdog watchdog(f);
    Expected<LoadedMesh> m = read_mesh(f);
    ASSERT_FALSE(m.has_value()) << name;
    expect_not_regular(m.error(), f, "a FIFO");
  }
}

TEST_F(RegularFile, LinkToDevZeroAsMeshIsRefused) {
  const fs::path zero = link_to_dev_zero("zero.ply");
  Expected<LoadedMesh> m = read_mesh(zero);
  ASSERT_FALSE(m.has_value());
  expect_not_regular(m.error(), zero, "a character device");
  EXPECT_NE(m.error().message.find("cannot be read as a mesh file"), std::string::npos);
}

TEST_F(RegularFile, FifoAsImageIsRefusedBeforeOpening) {
  const fs::path f = fifo("pipe.png");
  FifoWatchdog watchdog(f);
  Expected<Image> img = read_image(f);
  ASSERT_FALSE(img.has_value());
  expect_not_regular(img.error(), f, "a FIFO");
  EXPECT_NE(img.error().message.find("cannot be read as an image"), std::string::npos);
}

TEST_F(RegularFile, FifoOrDevZeroAsProxyFileIsRefused) {
  const fs::path f = fifo("pipe.json");
  {
    FifoWatchdog watchdog(f);
    Expected<Proxy> p = read_proxy_file(f);
    ASSERT_FALSE(p.has_value());
    expect_not_regular(p.error(), f, "a FIFO");
    EXPECT_NE(p.error().message.find("cannot be read as a proxy file"), std::string::npos);
  }
  // Read until memory ran out before the check.
  const fs::path zero = link_to_dev_zero("zero.json");
  Expected<Proxy> p = read_proxy_file(zero);
  ASSERT_FALSE(p.has_value());
  expect_not_regular(p.error(), zero, "a character device");
}

TEST_F(RegularFile, LinkToDevZeroAsImageIsRefused) {
  const fs::path zero = link_to_dev_zero("zero.jpg");
  Expected<Image> img = read_image(zero);
  ASSERT_FALSE(img.has_value());
  expect_not_regular(img.error(), zero, "a character device");
}

TEST_F(RegularFile, MaterialLibraryFifoOrDevZeroIsRefused) {
  const fs::path f = fifo("pipe.mtl");
  FifoWatchdog watchdog(f);
  link_to_dev_zero("zero.mtl");
  for (const char* lib : {"pipe.mtl", "zero.mtl"}) {
    const fs::path obj =
        write_text(dir / "a.obj", "# material\nmtllib " + std::string(lib) + "\n" + kTriangleObj);
    Expected<LoadedMesh> m = read_mesh(obj);
    ASSERT_FALSE(m.has_value()) << lib;
    EXPECT_EQ(m.error().message,
              obj.string() + ": line 2: material library '" + lib + "' is not a regular file");
  }
}

TEST_F(RegularFile, MaterialLibraryAbove16MiBIsRefused) {
  const fs::path mtl = dir / "big.mtl";
  write_text(mtl, "");
  fs::resize_file(mtl, (16u << 20) + 1);
  const fs::path obj = write_text(dir / "a.obj", "mtllib big.mtl\n" + kTriangleObj);
  Expected<LoadedMesh> m = read_mesh(obj);
  ASSERT_FALSE(m.has_value());
  EXPECT_EQ(m.error().code, ErrorCode::kParse);
  EXPECT_EQ(m.error().message,
            obj.string() +
                ": line 1: material library 'big.mtl' is larger than texbake reads "
                "(16 MiB)");
}

TEST_F(RegularFile, TextureLinkedToDevZeroLoadsTheMeshButNotTheImage) {
  // The OBJ and its MTL are fine; the texture they name is a link to
  // /dev/zero: the mesh loads (a texture is read only when used) and
  // reading the texture is refused.
  link_to_dev_zero("tex.png");
  write_text(dir / "m.mtl", "newmtl m\nmap_Kd tex.png\n");
  const fs::path obj = write_text(dir / "a.obj",
                                  "mtllib m.mtl\nusemtl m\nvt 0 0\nvt 1 0\nvt 0 1\n"
                                  "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1/1 2/2 3/3\n");
  Expected<LoadedMesh> m = read_mesh(obj);
  ASSERT_TRUE(m.has_value()) << m.error().message;
  ASSERT_EQ(m->mesh.texture_path, (dir / "tex.png").string());
  Expected<Image> img = read_image(m->mesh.texture_path);
  ASSERT_FALSE(img.has_value());
  expect_not_regular(img.error(), dir / "tex.png", "a character device");
}

}  // namespace
}  // namespace texbake
