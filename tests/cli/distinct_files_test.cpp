// No output may be an input of the same job or another output, after links
// (SPEC section 12): one row per (command, input kind, output flag), over
// every command that writes and every kind of input a job reads: the mesh,
// --texture, --proxy-file, a COLMAP model's files and photos, a JSON camera
// list and its photos, a nerfstudio transforms.json's photos, the layers file and what it names
// (proxy file, texture, mask, a cameras layer's model and photos), the mesh's own texture, the
// batch's jobs file and --results. Each row asserts exit 2 (a batch job: its line's exit in
// --results), a message naming both files, and the folder byte for byte as it was: the input
// untouched, no output made.
#include <gtest/gtest.h>

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh_io/image_io.h"
#include "run_texbake.h"

namespace {

namespace fs = std::filesystem;
using texbake::testing_cli::quoted;
using texbake::testing_cli::run_texbake;
using texbake::testing_cli::RunResult;
using texbake::testing_cli::slurp;

const char* kSphere = "--proxy sphere --center 0,0,0 --radius 2 --pole 0,0,1 --equator 1,0,0";

// A PINHOLE camera of 8 x 6 pixels 5 units before the origin, looking along
// +z (world-to-camera t = (0, 0, 5)).
const char* kCamera = R"("kind":"camera","model":"PINHOLE","width":8,"height":6,)"
                      R"("params":[10,10,4,3],"pose":{"q_wxyz":[1,0,0,0],"t":[0,0,5]})";

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

// A w x h grey PNG (a texture, a mask or a photo).
void write_png(const fs::path& path, int w, int h) {
  fs::create_directories(path.parent_path());
  texbake::Image img;
  img.width = w;
  img.height = h;
  img.pixels.assign(static_cast<std::size_t>(w) * h * 4, 0.5f);
  ASSERT_TRUE(texbake::write_image(path, img.view()));
}

// Every file under `dir` and its bytes.
std::map<fs::path, std::string> tree(const fs::path& dir) {
  std::map<fs::path, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), dir)] = slurp(e.path());
  }
  return files;
}

struct Row {
  const char* name;
  // The command line; "@x" is the row's folder / x, "{sphere}" the sphere flags.
  std::vector<std::string> args;
  // What the message names: both files' flags or roles, and a file name.
  std::vector<std::string> message;
  // A batch row whose job fails: its --results file (else the command
  // itself exits 2), and the jobs file's line ("@" the folder + "/").
  const char* results = nullptr;
  const char* job = nullptr;
};

class DistinctFiles : public ::testing::TestWithParam<Row> {
 protected:
  void SetUp() override {
    dir_ = texbake::testing_cli::fresh_test_dir("distinct_files");
    // The mesh: a tetrahedron in front of the cameras.
    write(dir_ / "tet.ply",
          "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
          "property float z\nelement face 4\nproperty list uchar int vertex_indices\n"
          "end_header\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n");
    // The same with UVs and a texture, R/images/view_00.png (where render
    // --colmap R writes its first view).
    write(dir_ / "tetuv.obj",
          "mtllib tetuv.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
          "usemtl m\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/2\nf 2/1 3/2 4/3\n");
    write(dir_ / "tetuv.mtl", "newmtl m\nmap_Kd R/images/view_00.png\n");
    write_png(dir_ / "R/images/view_00.png", 4, 4);
    write_png(dir_ / "t.png", 4, 4);
    // An OBJ whose material library and texture an atlas -o could name, and
    // a .gltf naming an external buffer (percent-encoded) and image.
    write(dir_ / "tetm.obj",
          "mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvt 0 0\nvt 1 0\nvt 0 1\n"
          "usemtl m\nf 1/1 3/3 2/2\nf 1/1 2/2 4/3\nf 1/1 4/3 3/2\nf 2/1 3/2 4/3\n");
    write(dir_ / "m.mtl", "newmtl m\nmap_Kd mt.png\n");
    write_png(dir_ / "mt.png", 4, 4);
    write(dir_ / "g.gltf",
          R"({"asset":{"version":"2.0"},"buffers":[{"uri":"g%20b.bin","byteLength":4}],)"
          R"("images":[{"uri":"gi.png"}]})");
    write(dir_ / "g b.bin", "abcd");
    write_png(dir_ / "gi.png", 4, 4);
    // A camera proxy file and its photo.
    write(dir_ / "cam.json", std::string("{") + kCamera + "}");
    write_png(dir_ / "photo.png", 8, 6);
    // A COLMAP workspace W: sparse/0 (cameras, images, points3D) and images/a.png.
    write(dir_ / "W/sparse/0/cameras.txt", "1 PINHOLE 8 6 10 10 4 3\n");
    write(dir_ / "W/sparse/0/images.txt", "1 1 0 0 0 0 0 5 1 a.png\n\n");
    write(dir_ / "W/sparse/0/points3D.txt", "# no points\n");
    write_png(dir_ / "W/images/a.png", 8, 6);
    // A JSON camera list and its photo b.png beside it.
    write(dir_ / "cams.json", std::string(R"({"cameras":[{)") + kCamera + R"(,"image":"b.png"}]})");
    write_png(dir_ / "b.png", 8, 6);
    // A nerfstudio transforms.json of the same camera (camera-to-world,
    // OpenGL axes) and its photo T/images/c.png.
    write(dir_ / "T/transforms.json",
          R"({"w":8,"h":6,"fl_x":10,"fl_y":10,"cx":4,"cy":3,"frames":[{"file_path":)"
          R"("images/c.png","transform_matrix":[[1,0,0,0],[0,-1,0,0],[0,0,-1,-5],[0,0,0,1]]}]})");
    write_png(dir_ / "T/images/c.png", 8, 6);
    // A layers file: a proxy-file layer with a texture and a mask, and a
    // cameras layer over W's model.
    write(dir_ / "lp.json",
          R"({"kind":"sphere","center":[0,0,0],"radius":2,"pole":[0,0,1],"equator":[1,0,0]})");
    write_png(dir_ / "lt.png", 4, 4);
    write_png(dir_ / "lm.png", 4, 4);
    // A proxy file where render --colmap P writes its model.
    write(dir_ / "P/sparse/0/cameras.txt",
          R"({"kind":"sphere","center":[0,0,0],"radius":2,"pole":[0,0,1],"equator":[1,0,0]})");
    write(dir_ / "L.json",
          R"({"layers":[{"proxy_file":"lp.json","texture":"lt.png","mask":"lm.png"},)"
          R"({"cameras":"W/sparse/0"}]})");
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The row's argument, "@x" made a path in the row's folder.
  std::string arg(const std::string& a) const {
    if (a == "{sphere}") return kSphere;
    return a.rfind('@', 0) == 0 ? quoted(dir_ / a.substr(1)) : a;
  }

  fs::path dir_;
};

TEST_P(DistinctFiles, ExitTwoBeforeAnyWork) {
  const Row& row = GetParam();
  if (row.job) {
    std::string line = row.job;
    for (std::size_t at; (at = line.find('@')) != std::string::npos;) {
      line.replace(at, 1, dir_.string() + "/");
    }
    write(dir_ / "jobs.jsonl", line + "\n");
  }
  std::string command;
  for (const std::string& a : row.args) command += arg(a) + " ";
  const std::map<fs::path, std::string> before = tree(dir_);

  const RunResult r = run_texbake(command);
  std::string message = r.err;
  std::map<fs::path, std::string> after = tree(dir_);
  if (row.results) {
    // The batch runs on and fails (exit 1); the job's own line says exit 2.
    EXPECT_EQ(r.exit_code, 1) << r.err;
    ASSERT_TRUE(after.count(row.results)) << r.err;
    const nlohmann::json line = nlohmann::json::parse(after[row.results]);
    EXPECT_EQ(line["exit"], 2) << line.dump();
    EXPECT_EQ(line["status"], "failed") << line.dump();
    message = line["error"].is_string() ? line["error"].get<std::string>() : "";
    EXPECT_NE(r.err.find("texbake: error: "), std::string::npos) << r.err;
    after.erase(row.results);
  } else {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err.rfind("texbake: error: ", 0), 0u) << r.err;
  }
  EXPECT_NE(message.find("are the same file"), std::string::npos) << message;
  for (const std::string& part : row.message) {
    EXPECT_NE(message.find(part), std::string::npos) << "'" << part << "' in: " << message;
  }
  // Every input byte for byte, no output made (nor a temporary left).
  EXPECT_EQ(after.size(), before.size());
  for (const auto& [path, bytes] : before) {
    EXPECT_TRUE(after.count(path) && after[path] == bytes) << path << " changed or removed";
  }
  for (const auto& [path, bytes] : after) {
    EXPECT_TRUE(before.count(path)) << path << " was made";
  }
}

// The proxy bake's flags, the photo bake's, the layers bake's.
#define BAKE "bake", "@tet.ply", "--texture", "@t.png", "{sphere}"
#define PHOTOS "bake", "@tet.ply", "--cameras", "@W/sparse/0"
#define LAYERS "bake", "@tet.ply", "--layers", "@L.json"

const Row kRows[] = {
    // bake with a proxy: the mesh, the texture, a proxy file; two outputs.
    {"BakeOutputOntoMesh", {BAKE, "-o", "@tet.ply"}, {"-o ", "MESH ", "tet.ply"}},
    {"BakeAtlasImageOntoTexture",
     {BAKE, "--size", "8", "-o", "@t.obj"},
     {"the atlas image of -o", "--texture ", "t.png"}},
    {"BakeReportOntoOutput",
     {BAKE, "-o", "@x.ply", "--report", "@x.ply"},
     {"--report ", "-o ", "two outputs"}},
    {"BakeReportOntoTexture",
     {BAKE, "-o", "@x.ply", "--report", "@t.png"},
     {"--report ", "--texture "}},
    // ... and the files the mesh names (an OBJ's material library and its
    // texture, a .gltf's buffers and images).
    {"BakeAtlasMaterialOntoMeshMaterial",
     {"bake", "@tetm.obj", "--texture", "@t.png", "{sphere}", "--uv", "generate", "--size", "8",
      "-o", "@m.obj"},
     {"the material of -o", "a file MESH names: ", "m.mtl"}},
    {"BakeAtlasImageOntoMeshTexture",
     {"bake", "@tetm.obj", "--texture", "@t.png", "{sphere}", "--uv", "generate", "--size", "8",
      "-o", "@mt.obj"},
     {"the atlas image of -o", "a file MESH names: ", "mt.png"}},
    {"BakeReportOntoGltfBuffer",
     {"bake", "@g.gltf", "--texture", "@t.png", "{sphere}", "-o", "@x.ply", "--report", "@g b.bin"},
     {"--report ", "a file MESH names: ", "g b.bin"}},
    {"BakeReportOntoGltfImage",
     {"bake", "@g.gltf", "--texture", "@t.png", "{sphere}", "-o", "@x.ply", "--report", "@gi.png"},
     {"--report ", "a file MESH names: ", "gi.png"}},
    {"BakeReportOntoProxyFile",
     {"bake", "@tet.ply", "--texture", "@t.png", "--proxy-file", "@lp.json", "-o", "@x.ply",
      "--report", "@lp.json"},
     {"--report ", "--proxy-file ", "lp.json"}},
    // A camera --proxy-file with its photo as --texture.
    {"CameraProxyReportOntoCameraFile",
     {"bake", "@tet.ply", "--texture", "@photo.png", "--proxy-file", "@cam.json", "-o", "@x.ply",
      "--report", "@cam.json"},
     {"--report ", "--proxy-file ", "cam.json"}},
    {"CameraProxyAtlasImageOntoPhoto",
     {"bake", "@tet.ply", "--texture", "@photo.png", "--proxy-file", "@cam.json", "--uv",
      "generate", "--size", "8", "-o", "@photo.obj"},
     {"the atlas image of -o", "--texture ", "photo.png"}},
    // bake --cameras with a COLMAP model: its files and its photos.
    {"PhotosReportOntoCamerasTxt",
     {PHOTOS, "-o", "@x.ply", "--report", "@W/sparse/0/cameras.txt"},
     {"--report ", "--cameras ", "cameras.txt"}},
    {"PhotosReportOntoImagesTxt",
     {PHOTOS, "-o", "@x.ply", "--report", "@W/sparse/0/images.txt"},
     {"--report ", "--cameras ", "images.txt"}},
    {"PhotosReportOntoPoints3D",
     {PHOTOS, "-o", "@x.ply", "--report", "@W/sparse/0/points3D.txt"},
     {"--report ", "--cameras ", "points3D.txt"}},
    {"PhotosReportOntoPhoto",
     {PHOTOS, "-o", "@x.ply", "--report", "@W/images/a.png"},
     {"--report ", "a photo of --cameras ", "a.png"}},
    {"PhotosAtlasImageOntoPhoto",
     {PHOTOS, "--uv", "generate", "--size", "8", "-o", "@W/images/a.obj"},
     {"the atlas image of -o", "a photo of --cameras ", "a.png"}},
    {"PhotosOutputOntoMesh", {PHOTOS, "-o", "@tet.ply"}, {"-o ", "MESH "}},
    {"PhotosWithImagesReportOntoPhoto",
     {PHOTOS, "--images", "@W/images", "-o", "@x.ply", "--report", "@W/images/./a.png"},
     {"--report ", "a photo of --cameras ", "a.png"}},
    // bake --cameras with a JSON camera list: the list and its photos.
    {"CameraListReportOntoList",
     {"bake", "@tet.ply", "--cameras", "@cams.json", "-o", "@x.ply", "--report", "@cams.json"},
     {"--report ", "--cameras ", "cams.json"}},
    {"CameraListReportOntoPhoto",
     {"bake", "@tet.ply", "--cameras", "@cams.json", "-o", "@x.ply", "--report", "@b.png"},
     {"--report ", "a photo of --cameras ", "b.png"}},
    // bake --layers: the layers file and everything it names.
    {"LayersOutputOntoMesh", {LAYERS, "-o", "@tet.ply"}, {"-o ", "MESH "}},
    {"LayersReportOntoLayersFile",
     {LAYERS, "-o", "@x.ply", "--report", "@L.json"},
     {"--report ", "--layers ", "L.json"}},
    {"LayersReportOntoProxyFile",
     {LAYERS, "-o", "@x.ply", "--report", "@lp.json"},
     {"--report ", "layers[0].proxy_file ", "lp.json"}},
    {"LayersAtlasImageOntoTexture",
     {LAYERS, "--size", "8", "--uv", "generate", "-o", "@lt.obj"},
     {"the atlas image of -o", "layers[0].texture ", "lt.png"}},
    {"LayersReportOntoMask",
     {LAYERS, "-o", "@x.ply", "--report", "@lm.png"},
     {"--report ", "layers[0].mask ", "lm.png"}},
    {"LayersReportOntoCamerasLayerModel",
     {LAYERS, "-o", "@x.ply", "--report", "@W/sparse/0/images.txt"},
     {"--report ", "layers[1].cameras ", "images.txt"}},
    {"LayersReportOntoCamerasLayerPhoto",
     {LAYERS, "-o", "@x.ply", "--report", "@W/images/a.png"},
     {"--report ", "a photo of layers[1].cameras ", "a.png"}},
    // fit -o.
    {"FitOutputOntoMesh",
     {"fit", "@tet.ply", "--proxy", "sphere", "-o", "@tet.ply"},
     {"-o ", "MESH "}},
    // render: -o, the --colmap workspace's views and model.
    {"RenderOutputOntoTexture",
     {"render", "@tet.ply", "--texture", "@t.png", "{sphere}", "--size", "8x8", "-o", "@t.png"},
     {"-o ", "--texture "}},
    {"RenderOutputOntoMesh",
     {"render", "@tet.ply", "--size", "8x8", "-o", "@tet.ply"},
     {"-o ", "MESH "}},
    {"RenderColmapViewOntoTexture",
     {"render", "@tet.ply", "--texture", "@R/images/view_00.png", "{sphere}", "--size", "8x8",
      "--colmap", "@R"},
     {"--colmap ", "--texture ", "view_00.png"}},
    {"RenderColmapModelOntoProxyFile",
     {"render", "@tet.ply", "--texture", "@t.png", "--proxy-file", "@P/sparse/0/cameras.txt",
      "--size", "8x8", "--colmap", "@P"},
     {"--colmap ", "--proxy-file ", "cameras.txt"}},
    {"RenderColmapViewOntoMeshTexture",
     {"render", "@tetuv.obj", "--size", "8x8", "--colmap", "@R"},
     {"--colmap ", "a file MESH names: ", "view_00.png"}},
    {"RenderOutputOntoMeshTexture",
     {"render", "@tetuv.obj", "--size", "8x8", "-o", "@R/images/view_00.png"},
     {"-o ", "a file MESH names: "}},
    // bake --cameras with a nerfstudio file: its photos are inputs.
    {"AtlasImageOntoNerfstudioPhoto",
     {"bake", "@tet.ply", "--cameras", "@T/transforms.json", "--uv", "generate", "--size", "8",
      "-o", "@T/images/c.obj"},
     {"the atlas image of -o", "a photo of --cameras ", "c.png"}},
    // cameras convert: the model it writes (and the other form's files it
    // removes) may not be the input model's files.
    {"CamerasConvertOntoItsInputModel",
     {"cameras", "convert", "@W/sparse/0", "-o", "@W/sparse/0"},
     {"-o ", "IN ", "cameras.txt"}},
    // batch: the jobs file and --results are an input and an output of
    // every job; each job's own files as bake's.
    {"BatchResultsOntoJobs",
     {"batch", "@jobs.jsonl", "--results", "@jobs.jsonl"},
     {"--results ", "JOBS ", "jobs.jsonl"},
     nullptr,
     R"({"mesh":"@tet.ply","texture":"@t.png","proxy":"sphere","output":"@x.ply"})"},
    {"BatchJobReportOntoJobs",
     {"batch", "@jobs.jsonl", "--results", "@r.jsonl"},
     {"--report ", "JOBS ", "jobs.jsonl"},
     "r.jsonl",
     R"({"mesh":"@tet.ply","texture":"@t.png","proxy":"sphere","output":"@x.ply",)"
     R"("report":"@jobs.jsonl"})"},
    {"BatchJobOutputOntoResults",
     {"batch", "@jobs.jsonl", "--results", "@r.ply"},
     {"-o ", "--results ", "r.ply"},
     "r.ply",
     R"({"mesh":"@tet.ply","texture":"@t.png","proxy":"sphere","output":"@r.ply"})"},
    {"BatchJobReportOntoResults",
     {"batch", "@jobs.jsonl", "--results", "@r.jsonl"},
     {"--report ", "--results ", "r.jsonl"},
     "r.jsonl",
     R"({"mesh":"@tet.ply","texture":"@t.png","proxy":"sphere","output":"@x.ply",)"
     R"("report":"@r.jsonl"})"},
    {"BatchJobAtlasImageOntoPhoto",
     {"batch", "@jobs.jsonl", "--results", "@r.jsonl"},
     {"the atlas image of -o", "a photo of --cameras ", "a.png"},
     "r.jsonl",
     R"({"mesh":"@tet.ply","cameras":"@W/sparse/0","uv":"generate","size":8,)"
     R"("output":"@W/images/a.obj"})"},
    {"BatchJobReportOntoLayerMask",
     {"batch", "@jobs.jsonl", "--results", "@r.jsonl"},
     {"--report ", "layers[0].mask ", "lm.png"},
     "r.jsonl",
     R"({"mesh":"@tet.ply","layers":"@L.json","output":"@x.ply","report":"@lm.png"})"},
};

INSTANTIATE_TEST_SUITE_P(EveryCommandAndInput, DistinctFiles, ::testing::ValuesIn(kRows),
                         [](const ::testing::TestParamInfo<Row>& info) {
                           return std::string(info.param.name);
                         });

TEST_F(DistinctFiles, ThroughALinkToo) {
  // A symbolic link to a photo is the photo.
  fs::create_symlink(dir_ / "W/images/a.png", dir_ / "link.json");
  const std::string before = slurp(dir_ / "W/images/a.png");
  const RunResult r =
      run_texbake("bake " + quoted(dir_ / "tet.ply") + " --cameras " + quoted(dir_ / "W/sparse/0") +
                  " -o " + quoted(dir_ / "x.ply") + " --report " + quoted(dir_ / "link.json"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("a photo of --cameras"), std::string::npos) << r.err;
  EXPECT_EQ(slurp(dir_ / "W/images/a.png"), before);
  EXPECT_FALSE(fs::exists(dir_ / "x.ply"));
}

}  // namespace
