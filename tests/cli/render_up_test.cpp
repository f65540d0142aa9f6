// texbake render --up without a proxy: the world up of the preview camera
// (bake/render/render_preview.h), e.g. --up y for the y-up meshes of most scanners.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "mesh_io/image_compare.h"

namespace {

namespace fs = std::filesystem;

int run_render(const std::string& args) {
  const std::string cmd =
      std::string("\"") + TEXBAKE_BINARY + "\" render " + args + " >/dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// An irregular tetrahedron (no symmetry, so a wrong up or a mirror shows).
void write_tetra(const fs::path& path, bool rotated) {
  const float p[4][3] = {
      {0.1f, -0.2f, 0.0f}, {1.0f, 0.1f, 0.2f}, {0.2f, 0.9f, -0.1f}, {0.3f, 0.2f, 0.8f}};
  std::ofstream out(path);
  out << "OFF\n4 4 0\n";
  for (const auto& v : p) {
    // The rotation (x, y, z) -> (x, -z, y) takes +y to +z and the camera
    // frame of --up y (east +x, north -z) to that of --up z (east +x, north +y).
    if (rotated) {
      out << v[0] << ' ' << -v[2] << ' ' << v[1] << '\n';
    } else {
      out << v[0] << ' ' << v[1] << ' ' << v[2] << '\n';
    }
  }
  out << "3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
}

TEST(RenderCliUp, UpYEqualsUpZOnTheRotatedMesh) {
  const fs::path dir =
      fs::temp_directory_path() / ("texbake_render_up_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_tetra(dir / "y_up.off", false);
  write_tetra(dir / "z_up.off", true);
  const std::string common = " --size 48x40 --view 30,20 --samples 4 -o ";
  ASSERT_EQ(run_render("\"" + (dir / "y_up.off").string() + "\" --up y" + common + "\"" +
                       (dir / "y.png").string() + "\""),
            0);
  ASSERT_EQ(run_render("\"" + (dir / "z_up.off").string() + "\" --up z" + common + "\"" +
                       (dir / "z.png").string() + "\""),
            0);
  ASSERT_EQ(run_render("\"" + (dir / "y_up.off").string() + "\" --up z" + common + "\"" +
                       (dir / "wrong.png").string() + "\""),
            0);
  auto same = texbake::compare_image_files(dir / "y.png", dir / "z.png", {});
  auto wrong = texbake::compare_image_files(dir / "y.png", dir / "wrong.png", {});
  fs::remove_all(dir);
  ASSERT_TRUE(same.has_value()) << same.error().message;
  ASSERT_TRUE(wrong.has_value()) << wrong.error().message;
  EXPECT_GE(same->psnr, 50);   // the same picture up to float rounding
  EXPECT_LT(wrong->psnr, 30);  // the up axis does change the picture
}

// With --proxy-file the file holds the whole proxy, and --up is the
// camera's alone: it is allowed, and means what it means without a proxy
// (issue #11 item 6: it used to be exit 2).
TEST(RenderCliUp, UpWithAProxyFileOrientsTheCamera) {
  const fs::path dir =
      fs::temp_directory_path() / ("texbake_render_up_file_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  write_tetra(dir / "y_up.off", false);
  std::ofstream(dir / "s.json")
      << R"({"kind":"sphere","center":[0.4,0.3,0.2],"radius":1,"pole":[0,1,0],"equator":[0,0,1]})";
  const std::string mesh = "\"" + (dir / "y_up.off").string() + "\"";
  const std::string texture = " --texture \"" TEXBAKE_DATA_DIR "/earth.jpg\"";
  const std::string common = " --size 48x40 --view 30,20 --samples 4 -o ";
  ASSERT_EQ(run_render(mesh + texture + " --proxy-file \"" + (dir / "s.json").string() +
                       "\" --up y" + common + "\"" + (dir / "file.png").string() + "\""),
            0);
  ASSERT_EQ(run_render(mesh + texture +
                       " --proxy sphere --center 0.4,0.3,0.2 --radius 1 --pole 0,1,0 --equator "
                       "0,0,1 --up y" +
                       common + "\"" + (dir / "flags.png").string() + "\""),
            0);
  ASSERT_EQ(run_render(mesh + texture + " --proxy-file \"" + (dir / "s.json").string() +
                       "\" --up z" + common + "\"" + (dir / "z.png").string() + "\""),
            0);
  auto same = texbake::compare_image_files(dir / "file.png", dir / "flags.png", {});
  auto other = texbake::compare_image_files(dir / "file.png", dir / "z.png", {});
  fs::remove_all(dir);
  ASSERT_TRUE(same.has_value()) << same.error().message;
  ASSERT_TRUE(other.has_value()) << other.error().message;
  EXPECT_TRUE(std::isinf(same->psnr)) << "the file and the flags give the same proxy and camera";
  EXPECT_LT(other->psnr, 30) << "--up still turns the camera";
}

}  // namespace
