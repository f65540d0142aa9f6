// bake --layers through the executable (SPEC section 10): one layer over
// base "none" is the single projection (in linear light, bilinear), a layer
// over the mesh's own colours leaves them where it does not reach, the
// coverage is the output's alpha (PLY alpha, GLB alphaMode BLEND), and bad
// files and flags are errors with no output.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "mesh_io/image_io.h"
#include "mesh_io/read_mesh.h"
#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;

std::string q(const fs::path& p) {
  return testing_cli::quoted(p);
}

const std::string kData = TEXBAKE_DATA_DIR;
const char* kEarthSphere =
    R"({"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,1,0],"equator":[0,0,1]})";

class LayersCli : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing_cli::fresh_test_dir("texbake_layers_cli"); }
  void TearDown() override { fs::remove_all(dir_); }
  void write(const fs::path& name, const std::string& text) {
    std::ofstream(dir_ / name, std::ios::binary) << text;
  }
  std::vector<std::array<int, 4>> colours(const fs::path& ply) {
    Expected<LoadedMesh> m = read_mesh(ply);
    EXPECT_TRUE(m) << m.error().message;
    std::vector<std::array<int, 4>> out;
    for (const auto& c : m->mesh.vertex_colors) {
      out.push_back({int(c[0] * 255 + 0.5f), int(c[1] * 255 + 0.5f), int(c[2] * 255 + 0.5f),
                     int(c[3] * 255 + 0.5f)});
    }
    return out;
  }
  fs::path dir_;
};

TEST_F(LayersCli, OneLayerOverNoneIsTheSingleProjectionInLinearLight) {
  const std::string bunny = q(kData + "/bunny00.off");
  write("L.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                      kData + R"(/earth.jpg"}]})");
  testing_cli::RunResult r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") +
                                         " --occluded 1,0,1 -q --report " + q(dir_ / "r.json") +
                                         " -o " + q(dir_ / "layers.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") +
                  " --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1 "
                  "--filter bilinear --linear --occluded 1,0,1 -q -o " +
                  q(dir_ / "direct.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto layers = colours(dir_ / "layers.ply"), direct = colours(dir_ / "direct.ply");
  ASSERT_EQ(layers.size(), direct.size());
  std::size_t covered = 0;
  for (std::size_t v = 0; v < layers.size(); ++v) {
    const bool occluded = direct[v][0] == 255 && direct[v][1] == 0 && direct[v][2] == 255;
    // Same RGB everywhere (measured identical); alpha: the coverage.
    for (int c = 0; c < 3; ++c) ASSERT_NEAR(layers[v][c], direct[v][c], 1) << "vertex " << v;
    EXPECT_EQ(layers[v][3], occluded ? 0 : 255) << "vertex " << v;
    covered += !occluded;
  }
  EXPECT_GT(covered, 30000u);
  const std::string report = testing_cli::slurp(dir_ / "r.json");
  EXPECT_NE(report.find("\"visible\": " + std::to_string(covered)), std::string::npos) << report;
  EXPECT_NE(report.find("\"blended\": " + std::to_string(covered)), std::string::npos) << report;
}

TEST_F(LayersCli, ALayersFilterIsTheSingleProjectionsFilter) {
  // "filter": "area" and "ewa" through a layer are bake --filter area / ewa
  // --linear through the proxy: the same colours, byte for byte, wherever
  // the sphere sees the vertex (the occluded ones: the coverage differs).
  const std::string bunny = q(kData + "/bunny00.off");
  for (const std::string filter : {"area", "ewa"}) {
    write("L.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                        kData + R"(/earth.jpg","filter":")" + filter + R"("}]})");
    testing_cli::RunResult r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") +
                                           " --occluded 1,0,1 -q -o " + q(dir_ / "layers.ply"));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto direct_bake = [&](const std::string& with, const std::string& out) {
      return run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") +
                         " --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator "
                         "0,0,1 --filter " +
                         with + " --linear --occluded 1,0,1 -q -o " + q(dir_ / out));
    };
    ASSERT_EQ(direct_bake(filter, "direct.ply").exit_code, 0);
    ASSERT_EQ(direct_bake("bilinear", "bilinear.ply").exit_code, 0);
    const auto layers = colours(dir_ / "layers.ply"), direct = colours(dir_ / "direct.ply"),
               bilinear = colours(dir_ / "bilinear.ply");
    ASSERT_EQ(layers.size(), direct.size());
    std::size_t covered = 0, filtered = 0;
    for (std::size_t v = 0; v < layers.size(); ++v) {
      if (direct[v][0] == 255 && direct[v][1] == 0 && direct[v][2] == 255) continue;
      ++covered;
      for (int c = 0; c < 3; ++c) ASSERT_EQ(layers[v][c], direct[v][c]) << filter << " " << v;
      filtered += layers[v] != bilinear[v];
    }
    EXPECT_GT(covered, 30000u) << filter;
    EXPECT_GT(filtered, 100u) << filter << ": the filter is not the bilinear lookup";
  }
}

TEST_F(LayersCli, AFilterOrWrapThatDoesNotApplyIsRefused) {
  const std::string bunny = q(kData + "/bunny00.off");
  const std::string earth = std::string(R"(,"texture":")") + kData + R"(/earth.jpg")";
  const char* camera =
      R"({"kind":"camera","model":"PINHOLE","width":64,"height":64,"params":[64,64,32,32],)"
      R"("pose":{"eye":[0,0,3],"target":[0,0,0],"up":[0,1,0]}})";
  struct Case {
    std::string layer, flags, message;
    int exit_code;
  };
  const std::vector<Case> cases = {
      {std::string(R"({"proxy":)") + camera + earth + R"(,"filter":"ewa"})", "",
       "layers[0].filter: \"ewa\" needs an analytic proxy", 1},
      {R"({"cameras":"sparse/0","filter":"area"})", "",
       "layers[0].filter: a cameras layer takes the photo bake's bilinear lookup", 1},
      {std::string(R"({"proxy":)") + kEarthSphere + earth + R"(,"wrap":"repeat"})", "",
       "layers[0].wrap: applies to a plane proxy only", 1},
      {std::string(R"({"proxy":)") + kEarthSphere + earth + R"(,"samples":4})", "",
       "layers[0].samples: applies to \"filter\": \"area\" only", 1},
      {std::string(R"({"proxy":)") + kEarthSphere + earth + R"(,"filter":"box"})", "",
       "layers[0].filter: must be one of \"bilinear\", \"area\", \"ewa\"", 1},
      {std::string(R"({"proxy":)") + kEarthSphere + earth + R"(,"filter":"area"})", " --size 64",
       "layers[0].filter: \"area\" applies to the vertex target only", 2},
  };
  for (const Case& c : cases) {
    write("F.json", R"({"layers":[)" + c.layer + "]}");
    const fs::path out = dir_ / (c.flags.empty() ? "o.ply" : "o.obj");
    const testing_cli::RunResult r = run_texbake("bake " + bunny + " --layers " +
                                                 q(dir_ / "F.json") + c.flags + " -o " + q(out));
    EXPECT_EQ(r.exit_code, c.exit_code) << c.layer << "\n" << r.err;
    EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("F.json: " + c.message), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(out)) << c.layer;
  }
}

TEST_F(LayersCli, ADecalOverTheMeshColoursLeavesThemElsewhere) {
  // The base: the bunny's Earth bake (vertex colours). The decal: a plane
  // proxy over the bunny's front (z > 0 faces towards +z), 0.2 x 0.2 units,
  // a half-opaque white image.
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --texture " + q(kData + "/earth.jpg") +
                  " --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1 -q -o " +
                  q(dir_ / "base.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Image white;
  white.width = white.height = 4;
  white.pixels.assign(4 * 4 * 4, 1.0f);
  for (std::size_t i = 3; i < white.pixels.size(); i += 4) white.pixels[i] = 0.5f;
  ASSERT_TRUE(write_image(dir_ / "decal.png", white.view()));
  write("L.json", R"({"base":"mesh","layers":[{"proxy":{"kind":"plane","origin":[-0.1,-0.1,0],)"
                  R"("u_axis":[0.2,0,0],"v_axis":[0,0.2,0]},"texture":"decal.png"}]})");
  r = run_texbake("bake " + q(dir_ / "base.ply") + " --layers " + q(dir_ / "L.json") + " -q -o " +
                  q(dir_ / "out.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Expected<LoadedMesh> mesh = read_mesh(dir_ / "base.ply");
  ASSERT_TRUE(mesh);
  const auto base = colours(dir_ / "base.ply"), out = colours(dir_ / "out.ply");
  std::size_t inside = 0, lighter = 0;
  for (std::size_t v = 0; v < out.size(); ++v) {
    const Float3 p = mesh->mesh.positions[v];
    EXPECT_EQ(out[v][3], 255);  // an opaque base stays opaque
    const bool in_decal = p.x > -0.1f && p.x < 0.1f && p.y > -0.1f && p.y < 0.1f;
    if (!in_decal) {
      for (int c = 0; c < 3; ++c) ASSERT_EQ(out[v][c], base[v][c]) << "vertex " << v;
      continue;
    }
    // Where the plane sees the vertex: half white over the base, in linear light.
    ++inside;
    if (out[v][0] > base[v][0] && out[v][1] > base[v][1] && out[v][2] > base[v][2]) ++lighter;
  }
  EXPECT_GT(inside, 100u);
  EXPECT_GT(lighter, inside / 3);  // the front half of the slab the decal projects through
}

// A "cameras" layer (a COLMAP workspace rendered from the bunny's Earth
// bake) over base "none" is `bake --cameras` where some photo sees the
// vertex (identical RGB, alpha 255) and transparent elsewhere; on the
// atlas (same layout: the bunny has no UVs, both generate them the same
// way) every texel all of whose samples are seen is the photo atlas's.
TEST_F(LayersCli, ACamerasLayerIsThePhotoBakeWherePhotosSeeTheSurface) {
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r = run_texbake(
      "render " + bunny + " --texture " + q(kData + "/earth.jpg") +
      " --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1 --unlit --views 4 "
      "--size 320x240 --colmap " +
      q(dir_ / "ws"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  write("L.json", R"({"layers":[{"cameras":"ws/sparse/0"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") + " -q --report " +
                  q(dir_ / "r.json") + " -o " + q(dir_ / "layers.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --cameras " + q(dir_ / "ws/sparse/0") + " -q -o " +
                  q(dir_ / "photos.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto layers = colours(dir_ / "layers.ply"), photos = colours(dir_ / "photos.ply");
  ASSERT_EQ(layers.size(), photos.size());
  std::size_t seen = 0;
  for (std::size_t v = 0; v < layers.size(); ++v) {
    ASSERT_TRUE(layers[v][3] == 0 || layers[v][3] == 255) << "vertex " << v;
    if (layers[v][3] == 0) continue;
    ++seen;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(layers[v][c], photos[v][c]) << "vertex " << v;
  }
  EXPECT_GT(seen, 20000u);
  EXPECT_LT(seen, layers.size());
  const std::string report = testing_cli::slurp(dir_ / "r.json");
  EXPECT_NE(report.find("\"cameras\": \"sparse/0\""), std::string::npos) << report;
  EXPECT_NE(report.find("\"visible\": " + std::to_string(seen)), std::string::npos) << report;
  EXPECT_NE(report.find("\"per_layer\": ["), std::string::npos) << report;

  // The atlas target.
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") +
                  " --target atlas --size 256 --padding 0 -q -o " + q(dir_ / "layers.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --cameras " + q(dir_ / "ws/sparse/0") +
                  " --target atlas --size 256 --padding 0 -q -o " + q(dir_ / "photos.obj"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  Expected<Image> a = read_image(dir_ / "layers.png"), b = read_image(dir_ / "photos.png");
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->width, b->width);
  std::size_t opaque = 0, transparent = 0;
  for (std::size_t t = 0; t < a->pixels.size() / 4; ++t) {
    const float alpha = a->pixels[4 * t + 3];
    if (alpha == 1) {
      ++opaque;
      for (int c = 0; c < 3; ++c) {
        ASSERT_NEAR(a->pixels[4 * t + c], b->pixels[4 * t + c], 1.01 / 255) << "texel " << t;
      }
    } else if (alpha == 0) {
      ++transparent;
    }
  }
  EXPECT_GT(opaque, 10000u);
  EXPECT_GT(transparent, 1000u);
}

// The camera of a one-view COLMAP text model as a camera file (SPEC section
// 9): cameras.txt's model, size and parameters, images.txt's pose.
std::string camera_json_of(const fs::path& model) {
  auto first_data_line = [](const fs::path& file) {
    std::ifstream in(file);
    std::string line;
    while (std::getline(in, line)) {
      if (!line.empty() && line[0] != '#') return line;
    }
    return std::string();
  };
  std::istringstream cam(first_data_line(model / "cameras.txt"));
  std::istringstream img(first_data_line(model / "images.txt"));
  std::string id, kind, value;
  int width = 0, height = 0;
  cam >> id >> kind >> width >> height;
  std::string params, q_wxyz, t;
  for (int k = 0; cam >> value; ++k) params += (k ? "," : "") + value;
  img >> id;
  for (int k = 0; k < 4 && img >> value; ++k) q_wxyz += (k ? "," : "") + value;
  for (int k = 0; k < 3 && img >> value; ++k) t += (k ? "," : "") + value;
  return R"({"kind":"camera","model":")" + kind + R"(","width":)" + std::to_string(width) +
         R"(,"height":)" + std::to_string(height) + R"(,"params":[)" + params +
         R"(],"pose":{"q_wxyz":[)" + q_wxyz + "],\"t\":[" + t + "]}}";
}

TEST_F(LayersCli, ACameraProxyFileIsAOnePhotoCamerasLayer) {
  // One rendered view: bake --proxy-file camera.json --texture photo (the
  // one-photo bake up to 90 degrees) and the layer {"cameras": model} (the
  // photo bake's blend, cut at 75 degrees) agree wherever both see the
  // vertex.
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r = run_texbake(
      "render " + bunny + " --texture " + q(kData + "/earth.jpg") +
      " --proxy sphere --center 0,0,0 --radius 1 --pole 0,1,0 --equator 0,0,1 --unlit --views 1 "
      "--size 320x240 --colmap " +
      q(dir_ / "ws"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  write("camera.json", camera_json_of(dir_ / "ws/sparse/0"));
  std::vector<fs::path> photos;
  for (const auto& e : fs::directory_iterator(dir_ / "ws/images")) photos.push_back(e.path());
  ASSERT_EQ(photos.size(), 1u);
  write("L.json", R"({"layers":[{"cameras":"ws/sparse/0"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") + " -q -o " +
                  q(dir_ / "layers.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  r = run_texbake("bake " + bunny + " --proxy-file " + q(dir_ / "camera.json") + " --texture " +
                  q(photos[0]) + " --occluded 1,0,1 -q -o " + q(dir_ / "camera.ply"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto layers = colours(dir_ / "layers.ply"), camera = colours(dir_ / "camera.ply");
  ASSERT_EQ(layers.size(), camera.size());
  std::size_t both = 0, camera_only = 0;
  for (std::size_t v = 0; v < layers.size(); ++v) {
    const bool camera_sees = !(camera[v][0] == 255 && camera[v][1] == 0 && camera[v][2] == 255);
    if (layers[v][3] == 0) {
      camera_only += camera_sees;
      continue;
    }
    ASSERT_TRUE(camera_sees) << "vertex " << v << ": the layer sees what the camera does not";
    ++both;
    for (int c = 0; c < 3; ++c) ASSERT_EQ(layers[v][c], camera[v][c]) << "vertex " << v;
  }
  EXPECT_GT(both, 5000u);      // measured: 9,642 of the bunny's 37,706 vertices, all identical
  EXPECT_GT(camera_only, 0u);  // seen between 75 and 90 degrees
}

TEST_F(LayersCli, CoverageIsTheGlbAlphaMode) {
  write("L.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                      kData + R"(/earth.jpg","opacity":0.5}]})");
  const testing_cli::RunResult r =
      run_texbake("bake " + q(kData + "/bunny00.off") + " --layers " + q(dir_ / "L.json") +
                  " --target vertex -q -o " + q(dir_ / "out.glb"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(testing_cli::slurp(dir_ / "out.glb").find("\"alphaMode\":\"BLEND\""),
            std::string::npos);
}

TEST_F(LayersCli, BadFilesAndFlagsAreErrorsWithNoOutput) {
  const std::string bunny = q(kData + "/bunny00.off");
  write("bad.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere +
                        R"(,"texture":"earth.jpg","opacity":2}]})");
  testing_cli::RunResult r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "bad.json") +
                                         " -o " + q(dir_ / "o.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("bad.json: layers[0].opacity: must be a number in [0, 1]"),
            std::string::npos)
      << r.err;
  write("missing.json",
        std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":"nowhere.png"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "missing.json") + " -o " +
                  q(dir_ / "o.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("nowhere.png"), std::string::npos) << r.err;
  write("L.json", std::string(R"({"layers":[{"proxy":)") + kEarthSphere + R"(,"texture":")" +
                      kData + R"(/earth.jpg"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") + " --texture " +
                  q(kData + "/earth.jpg") + " -o " + q(dir_ / "o.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--texture does not apply to --layers"), std::string::npos) << r.err;
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "L.json") + " --radius 2 -o " +
                  q(dir_ / "o.ply"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  // base "mesh" on a mesh without colours is the mesh's problem.
  write("M.json", std::string(R"({"base":"mesh","layers":[{"proxy":)") + kEarthSphere +
                      R"(,"texture":")" + kData + R"(/earth.jpg"}]})");
  r = run_texbake("bake " + bunny + " --layers " + q(dir_ / "M.json") + " -o " + q(dir_ / "o.ply"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("no vertex colours"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir_ / "o.ply"));
}

}  // namespace
}  // namespace texbake
