// The job front door (texbake/job.h): run_job against the calls it stands
// for. Its outputs must be the bytes the separate calls write (read_mesh,
// read_image, complete_proxy, bake_*, write_*), its refusals must come before
// any file is written, and a failed job must leave nothing behind.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "texbake/job.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

const fs::path kData = TEXBAKE_DATA_DIR;

std::string bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class JobTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_job_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The bunny and the Earth map through a sphere with its pole given (+Y):
  // centre and radius are left to the fit.
  Job bunny_job(const fs::path& output) const {
    Job job;
    job.mesh = kData / "bunny00.off";
    job.texture = kData / "earth.jpg";
    job.spec.kind = ProxyKind::kSphere;
    job.spec.up = Vec3{0, 1, 0};
    job.output = output;
    job.threads = 2;
    return job;
  }

  // The same sphere completed by the separate call.
  static Proxy fitted_sphere(const MeshData& mesh) {
    ProxySpec spec;
    spec.kind = ProxyKind::kSphere;
    spec.up = Vec3{0, 1, 0};
    return complete_proxy(spec, mesh).value().proxy;
  }

  fs::path dir_;
};

TEST_F(JobTest, AVertexJobWritesTheBytesOfTheSeparateCalls) {
  const fs::path out = dir_ / "job.ply";
  std::vector<std::string> notes;
  Job job = bunny_job(out);
  job.on_note = [&](const std::string& note) { notes.push_back(note); };
  const JobResult r = run_job(job);
  ASSERT_TRUE(r.ok()) << r.error->message;
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_EQ(r.outputs, std::vector<fs::path>{out});
  // The centre and the radius were fitted, and said so (by key).
  EXPECT_NE(std::find(r.fitted.begin(), r.fitted.end(), "center"), r.fitted.end());
  EXPECT_NE(std::find(r.fitted.begin(), r.fitted.end(), "radius"), r.fitted.end());
  ASSERT_EQ(notes.size(), 1u);
  EXPECT_NE(notes[0].find("fitted sphere"), std::string::npos) << notes[0];
  EXPECT_NE(r.summary.find(out.string()), std::string::npos) << r.summary;

  auto mesh = read_mesh(kData / "bunny00.off");
  ASSERT_TRUE(mesh);
  auto image = read_image(kData / "earth.jpg");
  ASSERT_TRUE(image);
  auto colors = bake_vertex_colors(mesh->mesh, image->view(), fitted_sphere(mesh->mesh));
  ASSERT_TRUE(colors);
  const fs::path direct = dir_ / "direct.ply";
  ASSERT_TRUE(write_vertex_colors(direct, mesh->mesh, colors->colors));
  EXPECT_EQ(r.stats.counts.vertices, mesh->mesh.vertex_count());
  EXPECT_EQ(r.stats.counts.occluded, colors->stats.counts.occluded);
  EXPECT_EQ(bytes(out), bytes(direct));
  EXPECT_TRUE(r.report.find("\"vertices\"") != std::string::npos) << r.report;

  // A field given is not fitted.
  Job given = bunny_job(dir_ / "given.ply");
  given.spec.values["radius"] = 2.0;
  const JobResult g = run_job(given);
  ASSERT_TRUE(g.ok()) << g.error->message;
  EXPECT_EQ(std::find(g.fitted.begin(), g.fitted.end(), "radius"), g.fitted.end());
  EXPECT_NE(std::find(g.fitted.begin(), g.fitted.end(), "center"), g.fitted.end());
}

TEST_F(JobTest, AnAtlasJobWritesTheObjSetThenTheReport) {
  const fs::path out = dir_ / "a.obj";
  Job job = bunny_job(out);
  job.target = JobTarget::kAtlas;
  job.atlas.uv = UvLayout::kGenerate;
  job.atlas.bake.size = 128;
  job.report = dir_ / "a.json";
  const JobResult r = run_job(job);
  ASSERT_TRUE(r.ok()) << r.error->message;
  const std::vector<fs::path> expected{out, dir_ / "a.mtl", dir_ / "a.png", dir_ / "a.json"};
  EXPECT_EQ(r.outputs, expected);
  for (const fs::path& p : expected) EXPECT_TRUE(fs::exists(p)) << p;
  EXPECT_EQ(bytes(dir_ / "a.json"), r.report);

  // The separate calls, with the job's atlas options, give the same files.
  auto mesh = read_mesh(kData / "bunny00.off");
  ASSERT_TRUE(mesh);
  auto image = read_image(kData / "earth.jpg");
  ASSERT_TRUE(image);
  const Proxy proxy = fitted_sphere(mesh->mesh);
  auto atlas = bake_atlas_texture(std::move(mesh->mesh), image->view(), proxy, job.atlas);
  ASSERT_TRUE(atlas);
  ASSERT_TRUE(write_atlas(dir_ / "b.obj", *atlas));
  EXPECT_EQ(bytes(dir_ / "a.png"), bytes(dir_ / "b.png"));
  // The OBJ names its own material file: compare past its mtllib line.
  std::string a = bytes(out), b = bytes(dir_ / "b.obj");
  ASSERT_NE(a.find("mtllib a.mtl"), std::string::npos);
  a.replace(a.find("mtllib a.mtl"), 12, "mtllib b.mtl");
  EXPECT_EQ(a, b);
}

TEST_F(JobTest, AnOutputThatIsAnInputIsRefusedBeforeAnyWork) {
  const fs::path mesh = dir_ / "m.ply";
  auto loaded = read_mesh(kData / "bunny00.off");
  ASSERT_TRUE(loaded);
  ASSERT_TRUE(write_vertex_colors(
      mesh, loaded->mesh, std::vector<Rgba>(loaded->mesh.vertex_count(), Rgba{1, 0, 0, 1})));
  const std::string before = bytes(mesh);
  Job job = bunny_job(mesh);
  job.mesh = mesh;
  const JobResult r = run_job(job);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(category(*r.error), ErrorCategory::kUsage);
  EXPECT_NE(r.error->message.find(mesh.string()), std::string::npos) << r.error->message;
  EXPECT_TRUE(r.outputs.empty());
  EXPECT_EQ(bytes(mesh), before);

  // The report may not be the texture either.
  Job job2 = bunny_job(dir_ / "out.ply");
  job2.report = job2.texture;
  const JobResult r2 = run_job(job2);
  ASSERT_FALSE(r2.ok());
  EXPECT_EQ(r2.exit_code, 2);
  EXPECT_FALSE(fs::exists(dir_ / "out.ply"));
}

TEST_F(JobTest, AFailedJobLeavesNothingBehind) {
  const fs::path out = dir_ / "a.obj";
  Job job = bunny_job(out);
  job.target = JobTarget::kAtlas;
  job.atlas.uv = UvLayout::kGenerate;
  job.atlas.bake.size = 64;
  job.report = dir_ / "a.json";
  job.texture = dir_ / "missing.png";
  const JobResult r = run_job(job);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.error->message.find("missing.png"), std::string::npos) << r.error->message;
  EXPECT_TRUE(r.outputs.empty());
  EXPECT_TRUE(r.report.empty());
  EXPECT_TRUE(r.summary.empty());
  EXPECT_TRUE(fs::is_empty(dir_)) << "a failed job wrote into " << dir_;
}

TEST_F(JobTest, AJobWithoutATextureCamerasOrLayersIsAUsageError) {
  Job job = bunny_job(dir_ / "out.ply");
  job.texture.clear();
  const JobResult r = run_job(job);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST(JobTarget, TheOutputsExtensionDecidesUnlessGiven) {
  EXPECT_EQ(job_target("", "a.ply").value(), JobTarget::kVertex);
  EXPECT_EQ(job_target("", "a.obj").value(), JobTarget::kAtlas);
  EXPECT_EQ(job_target("", "a.glb").value(), JobTarget::kAtlas);
  EXPECT_EQ(job_target("vertex", "a.obj").value(), JobTarget::kVertex);
  EXPECT_EQ(job_target("vertex", "a.glb").value(), JobTarget::kVertex);
  EXPECT_EQ(job_target("atlas", "a.obj").value(), JobTarget::kAtlas);
  for (const auto& [target, output] : std::vector<std::pair<std::string, std::string>>{
           {"atlas", "a.ply"}, {"", "a.png"}, {"texture", "a.obj"}}) {
    auto t = job_target(target, output);
    ASSERT_FALSE(t) << target << " " << output;
    EXPECT_EQ(category(t.error()), ErrorCategory::kUsage);
  }
}

TEST(JobExitCode, UsageIsTwoAndEverythingElseOne) {
  // SPEC section 5: 2 for a usage error, 1 for a bad file, a failure or a cancel.
  EXPECT_EQ(exit_code(make_error(ErrorCode::kInvalidArgument, "x")), 2);
  EXPECT_EQ(exit_code(make_error(ErrorCode::kUnsupported, "x")), 2);
  EXPECT_EQ(exit_code(make_error(ErrorCode::kParse, "x")), 1);
  EXPECT_EQ(exit_code(make_error(ErrorCode::kIo, "x")), 1);
  EXPECT_EQ(exit_code(make_error(ErrorCode::kInternal, "x")), 1);
  EXPECT_EQ(exit_code(make_error(ErrorCode::kCancelled, "x")), 1);
}

}  // namespace
}  // namespace texbake
