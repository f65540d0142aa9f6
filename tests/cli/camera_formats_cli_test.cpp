// Camera files of other tools through the executable (SPEC section 9,
// "Formats"): a COLMAP workspace written by `render --colmap`, its model
// re-written by hand as ns-process-data writes a nerfstudio transforms.json
// (camera-to-world, OpenGL axes, the world re-framed by applied_transform),
// as Metashape and as Meshroom write their cameras, baked and checked as the
// COLMAP model is; `cameras convert` into a COLMAP
// model that projects as the input does; errors with no output.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "mesh_io/camera_formats.h"
#include "mesh_io/colmap_model.h"
#include "mesh_io/read_mesh.h"
#include "tests/cli/run_texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using testing_cli::run_texbake;

std::string q(const fs::path& p) {
  return testing_cli::shell_quote(p.string());
}

const std::string kData = TEXBAKE_DATA_DIR;

class CameraFormatsCli : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("texbake_camera_formats_cli_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const testing_cli::RunResult r = testing_cli::render_bunny_workspace(*dir_, 4, "320x240");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    write_transforms();
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }

  // ws/transforms.json from ws/sparse/0 as nerfstudio's colmap_to_json
  // makes it: c2w = inverse of COLMAP's world-to-camera, its y and z
  // columns negated (OpenCV -> OpenGL axes), then the world's rows
  // re-ordered (x, z, -y): applied_transform rows (1,0,0,0), (0,0,1,0),
  // (0,-1,0,0). Shared intrinsics at the top level, file_path relative to
  // the file.
  static void write_transforms() {
    Expected<std::vector<ColmapImage>> model = read_colmap_model(*dir_ / "ws/sparse/0");
    ASSERT_TRUE(model);
    const CameraSpec& s0 = (*model)[0].camera.spec();
    ASSERT_EQ(s0.model, CameraModel::kPinhole);
    nlohmann::json j = {{"camera_model", "OPENCV"},
                        {"w", s0.width},
                        {"h", s0.height},
                        {"fl_x", s0.params[0]},
                        {"fl_y", s0.params[1]},
                        {"cx", s0.params[2]},
                        {"cy", s0.params[3]},
                        {"k1", 0.0},
                        {"k2", 0.0},
                        {"p1", 0.0},
                        {"p2", 0.0}};
    j["frames"] = nlohmann::json::array();
    for (const ColmapImage& image : *model) {
      const CameraPose& pose = image.camera.spec().pose;
      const Vec3 c = image.camera.centre();
      // c2w in OpenCV axes: columns = rows of r; then y, z negated.
      double m[3][4];
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) m[row][col] = pose.r[3 * col + row] * (col ? -1 : 1);
      }
      m[0][3] = c.x;
      m[1][3] = c.y;
      m[2][3] = c.z;
      nlohmann::json rows = nlohmann::json::array();
      for (int row : {0, 2, 1}) {
        const double sign = row == 1 ? -1 : 1;
        rows.push_back({sign * m[row][0], sign * m[row][1], sign * m[row][2], sign * m[row][3]});
      }
      rows.push_back({0, 0, 0, 1});
      j["frames"].push_back({{"file_path", "images/" + image.name}, {"transform_matrix", rows}});
    }
    j["applied_transform"] = {{1, 0, 0, 0}, {0, 0, 1, 0}, {0, -1, 0, 0}};
    std::ofstream(*dir_ / "ws/transforms.json") << j.dump(2);
  }

  static fs::path* dir_;
};
fs::path* CameraFormatsCli::dir_ = nullptr;

// Random points in the bunny's box (about [-0.5, 0.5] x [-0.5, 0.5] x [-0.4, 0.4]).
std::vector<Vec3> random_points() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  std::vector<Vec3> points(200);
  for (Vec3& p : points) p = {u(rng), u(rng), u(rng)};
  return points;
}

void expect_same_projections(const std::vector<CameraProjector>& a,
                             const std::vector<CameraProjector>& b) {
  ASSERT_EQ(a.size(), b.size());
  int inside = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    for (const Vec3& p : random_points()) {
      const CameraProjection pa = a[k].project(p), pb = b[k].project(p);
      ASSERT_EQ(pa.inside, pb.inside) << k;
      inside += pa.inside;
      EXPECT_NEAR(pa.pixel.x, pb.pixel.x, 1e-9) << k;
      EXPECT_NEAR(pa.pixel.y, pb.pixel.y, 1e-9) << k;
      EXPECT_NEAR(pa.depth, pb.depth, 1e-9) << k;
    }
  }
  EXPECT_GT(inside, 100);  // the points are seen, not all off the photos
}

std::vector<CameraProjector> colmap_cameras(const fs::path& folder) {
  Expected<std::vector<ColmapImage>> model = read_colmap_model(folder);
  EXPECT_TRUE(model) << model.error().message;
  std::vector<CameraProjector> out;
  if (model) {
    for (const ColmapImage& i : *model) out.push_back(i.camera);
  }
  return out;
}

TEST_F(CameraFormatsCli, NerfstudioTransformsBakeAndCheckAsTheirColmapModel) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  // The same cameras, read back from the file: applied_transform undone.
  Expected<CameraFile> file = read_camera_file(d / "ws/transforms.json");
  ASSERT_TRUE(file) << file.error().message;
  std::vector<CameraProjector> from_file;
  for (const CameraListEntry& e : file->cameras) from_file.push_back(e.camera);
  expect_same_projections(from_file, colmap_cameras(d / "ws/sparse/0"));

  testing_cli::RunResult colmap = run_texbake("bake " + bunny + " --cameras " +
                                              q(d / "ws/sparse/0") + " -o " + q(d / "colmap.ply"));
  ASSERT_EQ(colmap.exit_code, 0) << colmap.err;
  // The photos are found beside the file (file_path images/view_NN.png).
  testing_cli::RunResult ns = run_texbake("bake " + bunny + " --cameras " +
                                          q(d / "ws/transforms.json") + " -o " + q(d / "ns.ply"));
  ASSERT_EQ(ns.exit_code, 0) << ns.err;
  EXPECT_NE(ns.err.find("transforms.json: the poses are taken back to the frame of the data they "
                        "were made from (applied_transform [[1, 0, 0, 0], [0, 0, 1, 0], [0, -1, "
                        "0, 0]] and applied_scale 1 undone"),
            std::string::npos)
      << ns.err;
  Expected<LoadedMesh> a = read_mesh(d / "colmap.ply");
  Expected<LoadedMesh> b = read_mesh(d / "ns.ply");
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->mesh.vertex_colors.size(), b->mesh.vertex_colors.size());
  for (std::size_t i = 0; i < a->mesh.vertex_colors.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(a->mesh.vertex_colors[i][c], b->mesh.vertex_colors[i][c], 1.01 / 255) << i;
    }
  }
  // cameras check reads it too, with the same figures.
  testing_cli::RunResult check_colmap =
      run_texbake("cameras check " + bunny + " --cameras " + q(d / "ws/sparse/0") + " --json");
  testing_cli::RunResult check_ns = run_texbake("cameras check " + bunny + " --cameras " +
                                                q(d / "ws/transforms.json") + " --json");
  ASSERT_EQ(check_ns.exit_code, 0) << check_ns.err;
  const nlohmann::json jc = nlohmann::json::parse(check_colmap.out);
  const nlohmann::json jn = nlohmann::json::parse(check_ns.out);
  ASSERT_EQ(jc.size(), jn.size());
  for (std::size_t k = 0; k < jc.size(); ++k) {
    EXPECT_EQ(jn[k]["image"], "images/" + jc[k]["image"].get<std::string>());
    for (const char* key : {"in_front", "inside", "visible"}) {
      EXPECT_NEAR(jn[k][key].get<double>(), jc[k][key].get<double>(), 1e-9) << key;
    }
  }
  EXPECT_NE(check_ns.err.find("applied_transform"), std::string::npos) << check_ns.err;
}

// A layers file's "cameras" layer reads camera files as --cameras does, and
// the reader's note is printed as bake --cameras prints it (not with -q).
TEST_F(CameraFormatsCli, ACamerasLayersFileNotesArePrinted) {
  const fs::path& d = *dir_;
  const std::string bunny = q(kData + "/bunny00.off");
  const fs::path layers = d / "ns_layers.json";
  std::ofstream(layers) << nlohmann::json{{"base", {0.5, 0.5, 0.5, 1}},
                                          {"layers", {{{"cameras", "ws/transforms.json"}}}}}
                               .dump();
  const std::string note =
      (d / "ws/transforms.json").string() +
      ": the poses are taken back to the frame of the data they were made from";
  for (const std::string ext : {".ply", ".glb"}) {
    const std::string size = ext == ".glb" ? " --size 64" : "";
    testing_cli::RunResult r = run_texbake("bake " + bunny + " --layers " + q(layers) + size +
                                           " -o " + q(d / ("layers" + ext)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("texbake: " + note), std::string::npos) << r.err;
    r = run_texbake("bake " + bunny + " --layers " + q(layers) + size + " -q -o " +
                    q(d / ("quiet" + ext)));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err, "");
  }
}

TEST_F(CameraFormatsCli, ConvertWritesAColmapModelThatProjectsAsTheInput) {
  const fs::path& d = *dir_;
  // A stale binary model in the output folder is replaced, not left to win.
  fs::create_directories(d / "conv");
  std::ofstream(d / "conv/cameras.bin") << "stale";
  std::ofstream(d / "conv/images.bin") << "stale";
  testing_cli::RunResult r =
      run_texbake("cameras convert " + q(d / "ws/transforms.json") + " -o " + q(d / "conv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("converted 4 images from a nerfstudio transforms.json into a COLMAP "
                       "model: "),
            std::string::npos)
      << r.out;
  EXPECT_NE(r.err.find("applied_transform"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("the images' names are relative to " + (d / "ws").string() +
                       ": bake with --cameras " + (d / "conv").string() + " --images " +
                       (d / "ws").string()),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "conv/cameras.bin"));
  EXPECT_FALSE(fs::exists(d / "conv/images.bin"));
  EXPECT_TRUE(fs::exists(d / "conv/points3D.txt"));
  // Converted -> COLMAP -> read: the same projections as the file's and the
  // original model's cameras.
  Expected<CameraFile> file = read_camera_file(d / "ws/transforms.json");
  ASSERT_TRUE(file);
  std::vector<CameraProjector> from_file;
  for (const CameraListEntry& e : file->cameras) from_file.push_back(e.camera);
  expect_same_projections(colmap_cameras(d / "conv"), from_file);
  expect_same_projections(colmap_cameras(d / "conv"), colmap_cameras(d / "ws/sparse/0"));
  Expected<std::vector<ColmapImage>> conv = read_colmap_model(d / "conv");
  ASSERT_TRUE(conv);
  EXPECT_EQ((*conv)[0].name, "images/view_00.png");
  // Baking from the converted model with --images as the note says gives
  // the photos back.
  r = run_texbake("bake " + q(kData + "/bunny00.off") + " --cameras " + q(d / "conv") +
                  " --images " + q(d / "ws") + " -o " + q(d / "conv.ply"));
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // A COLMAP model converts to its binary form with its image ids.
  r = run_texbake("cameras convert " + q(d / "ws/sparse/0") + " -o " + q(d / "bin") + " --binary");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::exists(d / "bin/images.bin"));
  expect_same_projections(colmap_cameras(d / "bin"), colmap_cameras(d / "ws/sparse/0"));
  Expected<std::vector<ColmapImage>> bin = read_colmap_model(d / "bin");
  Expected<std::vector<ColmapImage>> orig = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(bin && orig);
  for (std::size_t k = 0; k < bin->size(); ++k) {
    EXPECT_EQ((*bin)[k].image_id, (*orig)[k].image_id);
    EXPECT_EQ((*bin)[k].name, (*orig)[k].name);
  }
}

TEST_F(CameraFormatsCli, ConvertErrorsLeaveNoOutput) {
  const fs::path& d = *dir_;
  // The output is the input model's folder: its files would be replaced.
  testing_cli::RunResult r =
      run_texbake("cameras convert " + q(d / "ws/sparse/0") + " -o " + q(d / "ws/sparse/0"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("texbake never overwrites an input"), std::string::npos) << r.err;
  // -o names a file.
  std::ofstream(d / "afile") << "x";
  r = run_texbake("cameras convert " + q(d / "ws/transforms.json") + " -o " + q(d / "afile"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("-o names the COLMAP model's folder"), std::string::npos) << r.err;
  // A lens texbake cannot model: the frame and the key, and no folder made.
  std::ofstream(d / "bad.json")
      << R"({"camera_model":"EQUIRECTANGULAR","w":640,"h":320,"fl_x":320,)"
         R"("frames":[{"file_path":"a.png","transform_matrix":[[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]})";
  r = run_texbake("cameras convert " + q(d / "bad.json") + " -o " + q(d / "badout"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("texbake: error: " + (d / "bad.json").string() +
                       ": frames[0]: key 'camera_model': 'EQUIRECTANGULAR' is not a camera "
                       "texbake models"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(d / "badout"));
  // Neither format: named.
  std::ofstream(d / "neither.json") << R"({"views":[]})";
  r = run_texbake("cameras convert " + q(d / "neither.json") + " -o " + q(d / "badout"));
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("not a camera file texbake reads"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "badout"));
  // Usage: -o is required.
  r = run_texbake("cameras convert " + q(d / "ws/transforms.json"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
}

TEST_F(CameraFormatsCli, MetashapeCamerasBakeAsTheirColmapModel) {
  const fs::path& d = *dir_;
  // ws/sparse/0 written as Metashape exports it: cx, cy as offsets from the
  // image centre; camera-to-chunk transforms, with the chunk's world X = s R
  // X_chunk + t (R 90 degrees about z, t = (1, 2, 3), s = 2), so each
  // camera-to-chunk is R^T (camera-to-world) with its centre R^T (C - t) / s;
  // labels without the photo's extension.
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  const CameraSpec& s0 = (*model)[0].camera.spec();
  ASSERT_EQ(s0.params[0], s0.params[1]);  // square pixels: f, no b1
  std::ostringstream xml;
  xml.precision(17);
  xml << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<document version=\"1.5.0\">\n<chunk>\n"
      << "<sensors><sensor id=\"0\" type=\"frame\"><resolution width=\"" << s0.width
      << "\" height=\"" << s0.height << "\"/><calibration type=\"frame\"><f>" << s0.params[0]
      << "</f><cx>" << s0.params[2] - s0.width / 2.0 << "</cx><cy>"
      << s0.params[3] - s0.height / 2.0 << "</cy></calibration></sensor></sensors>\n<cameras>\n";
  const double rt[9] = {0, 1, 0, -1, 0, 0, 0, 0, 1};  // R^T, R = rows (0,-1,0), (1,0,0), (0,0,1)
  for (const ColmapImage& image : *model) {
    const CameraPose& pose = image.camera.spec().pose;
    const Vec3 c = image.camera.centre() - Vec3{1, 2, 3};
    double m[16] = {0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1};
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) {
        // (R^T c2w)_ij = sum_k rt_ik c2w_kj, c2w_kj = pose.r[3 j + k]
        for (int k = 0; k < 3; ++k) m[4 * i + j] += rt[3 * i + k] * pose.r[3 * j + k];
      }
      m[4 * i + 3] = (rt[3 * i] * c.x + rt[3 * i + 1] * c.y + rt[3 * i + 2] * c.z) / 2;
    }
    const std::string label = fs::path(image.name).stem().string();
    xml << "<camera id=\"" << image.image_id << "\" sensor_id=\"0\" label=\"" << label
        << "\"><transform>";
    for (double v : m) xml << v << ' ';
    xml << "</transform></camera>\n";
  }
  xml << "</cameras>\n<transform><rotation>0 -1 0 1 0 0 0 0 1</rotation><translation>1 2 3"
      << "</translation><scale>2</scale></transform>\n</chunk>\n</document>\n";
  std::ofstream(d / "cameras.xml") << xml.str();
  Expected<CameraFile> file = read_camera_file(d / "cameras.xml");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_EQ(file->format, CameraFormat::kMetashape);
  std::vector<CameraProjector> from_file;
  for (const CameraListEntry& e : file->cameras) from_file.push_back(e.camera);
  expect_same_projections(from_file, colmap_cameras(d / "ws/sparse/0"));
  // Baked with the photos found by their labels plus ".png".
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r =
      run_texbake("bake " + bunny + " --cameras " + q(d / "cameras.xml") + " --images " +
                  q(d / "ws/images") + " -o " + q(d / "ms.ply") + " --strict-photos");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("placed in the chunk's world frame"), std::string::npos) << r.err;
  testing_cli::RunResult colmap = run_texbake("bake " + bunny + " --cameras " +
                                              q(d / "ws/sparse/0") + " -o " + q(d / "colmap2.ply"));
  ASSERT_EQ(colmap.exit_code, 0) << colmap.err;
  Expected<LoadedMesh> a = read_mesh(d / "colmap2.ply");
  Expected<LoadedMesh> b = read_mesh(d / "ms.ply");
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->mesh.vertex_colors.size(), b->mesh.vertex_colors.size());
  for (std::size_t i = 0; i < a->mesh.vertex_colors.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(a->mesh.vertex_colors[i][c], b->mesh.vertex_colors[i][c], 1.01 / 255) << i;
    }
  }
  // And converted: the same projections from the COLMAP model, the labels
  // completed with the extension of the photos found in --images.
  r = run_texbake("cameras convert " + q(d / "cameras.xml") + " -o " + q(d / "msconv") +
                  " --images " + q(d / "ws/images"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("from a Metashape cameras.xml"), std::string::npos) << r.out;
  expect_same_projections(colmap_cameras(d / "msconv"), from_file);
  Expected<std::vector<ColmapImage>> conv = read_colmap_model(d / "msconv");
  ASSERT_TRUE(conv);
  EXPECT_EQ((*conv)[0].name, "view_00.png");
  r = run_texbake("bake " + bunny + " --cameras " + q(d / "msconv") + " --images " +
                  q(d / "ws/images") + " -o " + q(d / "msconv.ply") + " --strict-photos");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  // Without the photos' folder the labels stay as they are, with a note.
  r = run_texbake("cameras convert " + q(d / "cameras.xml") + " -o " + q(d / "msconv2"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("4 labels have no extension and no photo of that name was found"),
            std::string::npos)
      << r.err;
}

TEST_F(CameraFormatsCli, MeshroomCamerasBakeAsTheirColmapModel) {
  const fs::path& d = *dir_;
  // ws/sparse/0 written as Meshroom's StructureFromMotion writes cameras.sfm
  // (SfMData version 1.2.11, every value a string): the focal in mm on a
  // 36 mm wide sensor (fy = focalLength w / sensorWidth, fx = fy /
  // pixelRatio), the principal point as an offset from the image centre in
  // AliceVision's pixels (COLMAP's minus 0.5), the world-to-camera rotation
  // column by column with the centre, absolute photo paths; one more view
  // not reconstructed (its pose is not in the file).
  Expected<std::vector<ColmapImage>> model = read_colmap_model(d / "ws/sparse/0");
  ASSERT_TRUE(model);
  const CameraSpec& s0 = (*model)[0].camera.spec();
  ASSERT_EQ(s0.model, CameraModel::kPinhole);
  const auto str = [](double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return std::string(buf);
  };
  const double w = s0.width, h = s0.height;
  nlohmann::json in = {
      {"intrinsicId", "1"},
      {"width", std::to_string(s0.width)},
      {"height", std::to_string(s0.height)},
      {"sensorWidth", "36"},
      {"sensorHeight", str(36 * h / w)},
      {"type", "pinhole"},
      {"focalLength", str(s0.params[1] * 36 / w)},
      {"pixelRatio", str(s0.params[1] / s0.params[0])},
      {"principalPoint", {str(s0.params[2] - 0.5 - w / 2), str(s0.params[3] - 0.5 - h / 2)}},
      {"distortionParams", nlohmann::json::array()},
      {"distortionType", "none"},
      {"undistortionType", "none"},
      {"locked", "false"}};
  nlohmann::json j = {{"version", {"1", "2", "11"}},
                      {"featuresFolders", {(d / "features").string()}},
                      {"matchesFolders", {(d / "matches").string()}},
                      {"intrinsics", {in}}};
  j["views"] = nlohmann::json::array();
  j["poses"] = nlohmann::json::array();
  for (const ColmapImage& image : *model) {
    const CameraPose& pose = image.camera.spec().pose;
    const std::string id = std::to_string(1000 + image.image_id);
    j["views"].push_back({{"viewId", id},
                          {"poseId", id},
                          {"frameId", std::to_string(image.image_id)},
                          {"intrinsicId", "1"},
                          {"path", fs::absolute(d / "ws/images" / image.name).string()},
                          {"width", std::to_string(s0.width)},
                          {"height", std::to_string(s0.height)}});
    nlohmann::json rotation = nlohmann::json::array();
    for (int col = 0; col < 3; ++col) {
      for (int row = 0; row < 3; ++row) rotation.push_back(str(pose.r[3 * row + col]));
    }
    const Vec3 c = image.camera.centre();
    j["poses"].push_back(
        {{"poseId", id},
         {"pose",
          {{"transform", {{"rotation", rotation}, {"center", {str(c.x), str(c.y), str(c.z)}}}},
           {"locked", "0"}}}});
  }
  j["views"].push_back({{"viewId", "9"},
                        {"poseId", "9"},
                        {"intrinsicId", "1"},
                        {"path", (d / "ws/images/missing.png").string()}});
  std::ofstream(d / "cameras.sfm") << j.dump(4);
  Expected<CameraFile> file = read_camera_file(d / "cameras.sfm");
  ASSERT_TRUE(file) << file.error().message;
  EXPECT_EQ(file->format, CameraFormat::kMeshroom);
  std::vector<CameraProjector> from_file;
  for (const CameraListEntry& e : file->cameras) from_file.push_back(e.camera);
  expect_same_projections(from_file, colmap_cameras(d / "ws/sparse/0"));
  // Baked with the photos at their absolute paths.
  const std::string bunny = q(kData + "/bunny00.off");
  testing_cli::RunResult r = run_texbake("bake " + bunny + " --cameras " + q(d / "cameras.sfm") +
                                         " -o " + q(d / "mr.ply") + " --strict-photos");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("1 view is not reconstructed (no pose) and left out"), std::string::npos)
      << r.err;
  testing_cli::RunResult colmap = run_texbake("bake " + bunny + " --cameras " +
                                              q(d / "ws/sparse/0") + " -o " + q(d / "colmap3.ply"));
  ASSERT_EQ(colmap.exit_code, 0) << colmap.err;
  Expected<LoadedMesh> a = read_mesh(d / "colmap3.ply");
  Expected<LoadedMesh> b = read_mesh(d / "mr.ply");
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->mesh.vertex_colors.size(), b->mesh.vertex_colors.size());
  for (std::size_t i = 0; i < a->mesh.vertex_colors.size(); ++i) {
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(a->mesh.vertex_colors[i][c], b->mesh.vertex_colors[i][c], 1.01 / 255) << i;
    }
  }
  // Converted: the same projections; the absolute paths made relative to
  // --images, so the model bakes with --images as COLMAP's does.
  r = run_texbake("cameras convert " + q(d / "cameras.sfm") + " -o " + q(d / "mrconv") +
                  " --images " + q(d / "ws/images"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("from a Meshroom .sfm"), std::string::npos) << r.out;
  expect_same_projections(colmap_cameras(d / "mrconv"), from_file);
  Expected<std::vector<ColmapImage>> conv = read_colmap_model(d / "mrconv");
  ASSERT_TRUE(conv);
  EXPECT_EQ((*conv)[0].name, "view_00.png");
  r = run_texbake("bake " + bunny + " --cameras " + q(d / "mrconv") + " --images " +
                  q(d / "ws/images") + " -o " + q(d / "mrconv.ply") + " --strict-photos");
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

}  // namespace
}  // namespace texbake
