// The files of a job (texbake/texbake.h: job_inputs, job_outputs,
// camera_files, layers_files, colmap_workspace_files, check_distinct_files):
// the lists written out by hand for a folder of every input kind, and the
// identity rule (links, paths of files not made yet).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "texbake/texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

using Listed = std::vector<std::pair<std::string, fs::path>>;

Listed listed(const std::vector<NamedFile>& files) {
  Listed out;
  for (const NamedFile& f : files) out.emplace_back(f.name, f.path);
  return out;
}

void write(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

class JobFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_job_files_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    // A COLMAP workspace with two photos (which need not exist to be listed).
    write(dir_ / "W/sparse/0/cameras.txt", "1 PINHOLE 8 6 10 10 4 3\n");
    write(dir_ / "W/sparse/0/images.txt",
          "1 1 0 0 0 0 0 5 1 a.png\n\n2 1 0 0 0 0 0 6 1 sub/b.png\n\n");
    write(dir_ / "W/sparse/0/points3D.txt", "");
    write(dir_ / "lp.json",
          R"({"kind":"sphere","center":[0,0,0],"radius":2,"pole":[0,0,1],"equator":[1,0,0]})");
    write(dir_ / "L/L.json",
          R"({"layers":[{"proxy_file":"../lp.json","texture":"t.png","mask":"m.png"},)"
          R"({"cameras":"../W/sparse/0","images":"/abs/photos"}]})");
    write(dir_ / "cams.json",
          R"({"cameras":[{"kind":"camera","model":"PINHOLE","width":8,"height":6,)"
          R"("params":[10,10,4,3],"pose":{"q_wxyz":[1,0,0,0],"t":[0,0,5]},"image":"c.png"}]})");
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(JobFiles, CameraFilesOfAColmapModelAndAList) {
  const fs::path model = dir_ / "W/sparse/0";
  // Photos from COLMAP's workspace layout (W/images, found after links), the
  // model files that exist.
  const fs::path images = fs::canonical(dir_) / "W/images";
  EXPECT_EQ(listed(camera_files(model, {}, "--cameras")),
            (Listed{{"--cameras", model / "cameras.txt"},
                    {"--cameras", model / "images.txt"},
                    {"--cameras", model / "points3D.txt"},
                    {"a photo of --cameras", images / "a.png"},
                    {"a photo of --cameras", images / "sub/b.png"}}));
  // --images given; the binary form's files when they are there.
  write(model / "cameras.bin", "");
  EXPECT_EQ(listed(camera_files(model, dir_ / "P", "--cameras")),
            (Listed{{"--cameras", model / "cameras.txt"},
                    {"--cameras", model / "cameras.bin"},
                    {"--cameras", model / "images.txt"},
                    {"--cameras", model / "points3D.txt"},
                    {"a photo of --cameras", dir_ / "P/a.png"},
                    {"a photo of --cameras", dir_ / "P/sub/b.png"}}));
  // A JSON list: the list, and its photos beside it.
  EXPECT_EQ(listed(camera_files(dir_ / "cams.json", {}, "--cameras")),
            (Listed{{"--cameras", dir_ / "cams.json"}, {"a photo of --cameras", dir_ / "c.png"}}));
}

TEST_F(JobFiles, LayersFilesNameEverythingTheFileNames) {
  const fs::path l = dir_ / "L";
  EXPECT_EQ(listed(layers_files(l / "L.json")),
            (Listed{{"--layers", l / "L.json"},
                    {"layers[0].proxy_file", l / "../lp.json"},
                    {"layers[0].texture", l / "t.png"},
                    {"layers[0].mask", l / "m.png"},
                    {"layers[1].cameras", l / "../W/sparse/0/cameras.txt"},
                    {"layers[1].cameras", l / "../W/sparse/0/images.txt"},
                    {"layers[1].cameras", l / "../W/sparse/0/points3D.txt"},
                    {"a photo of layers[1].cameras", "/abs/photos/a.png"},
                    {"a photo of layers[1].cameras", "/abs/photos/sub/b.png"}}));
  // A layers file that cannot be read: itself only (the job fails reading it).
  EXPECT_EQ(listed(layers_files(dir_ / "missing.json")),
            (Listed{{"--layers", dir_ / "missing.json"}}));
}

TEST_F(JobFiles, JobInputsAndOutputs) {
  JobFileNames job;
  job.mesh = "m.obj";
  job.texture = "t.png";
  job.proxy_file = "p.json";
  job.cameras = dir_ / "cams.json";
  job.manifest = "jobs.jsonl";
  job.output = "out.obj";
  job.atlas = true;
  job.report = "r.json";
  job.results = "res.jsonl";
  EXPECT_EQ(listed(job_inputs(job)), (Listed{{"MESH", "m.obj"},
                                             {"--texture", "t.png"},
                                             {"--proxy-file", "p.json"},
                                             {"--cameras", dir_ / "cams.json"},
                                             {"a photo of --cameras", dir_ / "c.png"},
                                             {"JOBS", "jobs.jsonl"}}));
  EXPECT_EQ(listed(job_outputs(job)), (Listed{{"-o", "out.obj"},
                                              {"the material of -o", "out.mtl"},
                                              {"the atlas image of -o", "out.png"},
                                              {"--report", "r.json"},
                                              {"--results", "res.jsonl"}}));
  job.atlas = false;  // vertex colours in an OBJ: the one file
  job.report.clear();
  job.results.clear();
  EXPECT_EQ(listed(job_outputs(job)), (Listed{{"-o", "out.obj"}}));
}

TEST_F(JobFiles, ColmapWorkspaceFiles) {
  EXPECT_EQ(colmap_view_name(7), "view_07.png");
  EXPECT_EQ(listed(colmap_workspace_files("R", 2)),
            (Listed{{"--colmap", fs::path("R/images/view_00.png")},
                    {"--colmap", fs::path("R/images/view_01.png")},
                    {"--colmap", fs::path("R/sparse/0/cameras.txt")},
                    {"--colmap", fs::path("R/sparse/0/images.txt")}}));
}

TEST_F(JobFiles, SameFileAfterLinksOrByItsResolvedPath) {
  const fs::path a = dir_ / "lp.json";
  fs::create_hard_link(a, dir_ / "hard.json");
  fs::create_symlink(dir_ / "W", dir_ / "linked");
  struct Case {
    fs::path output;
    bool same;
  };
  const Case cases[] = {
      {dir_ / "hard.json", true},                  // another name of one inode
      {dir_ / "L/../lp.json", true},               // ".." resolved
      {dir_ / "W/./sparse/0/cameras.txt", false},  // another file
      {dir_ / "new.png", false},
  };
  for (const Case& c : cases) {
    const Status s = check_distinct_files({{"--proxy-file", a}}, {{"-o", c.output}});
    EXPECT_EQ(!s, c.same) << c.output;
    if (!s) {
      EXPECT_EQ(category(s.error()), ErrorCategory::kUsage);
      EXPECT_EQ(s.error().message, "-o " + c.output.string() + " and --proxy-file " + a.string() +
                                       " are the same file: texbake never overwrites an input");
    }
  }
  // Files not made yet: one path through a link to a folder and its target.
  const Status s = check_distinct_files(
      {{"a photo of --cameras", dir_ / "W/images/none.png"}},
      {{"--report", dir_ / "x.json"}, {"-o", dir_ / "linked/images/none.png"}});
  ASSERT_FALSE(s);
  EXPECT_NE(s.error().message.find("-o " + (dir_ / "linked/images/none.png").string() +
                                   " and a photo of --cameras"),
            std::string::npos)
      << s.error().message;
  // Two outputs, one not made yet, spelled two ways.
  const Status two =
      check_distinct_files({}, {{"-o", dir_ / "x.ply"}, {"--report", dir_ / "L/../x.ply"}});
  ASSERT_FALSE(two);
  EXPECT_NE(two.error().message.find("two outputs cannot share one file"), std::string::npos);
  // Empty paths are not files.
  EXPECT_TRUE(check_distinct_files({{"--texture", ""}}, {{"-o", ""}, {"--report", ""}}));
}

}  // namespace
}  // namespace texbake
