// The job options (texbake/job_options.h): the table's own consistency, the
// settings a client gives turned into the Job it means (values worked out
// from SPEC sections 4, 5 and 12 by hand), the refusals with the command
// line's messages, the JSON form of a batch line, and run_batch (each job's
// record, in order, appended to the results file as it ends).
#include "texbake/job_options.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "bake/trace/embree_scene.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;

const fs::path kData = TEXBAKE_DATA_DIR;

std::string bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> lines_of(const fs::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(JobOptions, EveryKeyIsItsFlagsLongNameAndBothAreUnique) {
  std::set<std::string> keys, flags;
  for (const JobOption& o : job_options()) {
    EXPECT_TRUE(keys.insert(std::string(o.key)).second) << o.key;
    EXPECT_NE(o.bakes, 0u) << o.key;
    EXPECT_FALSE(o.help.empty()) << o.key;
    if (o.key == "mesh") {
      EXPECT_TRUE(o.flag.empty());  // the positional MESH
      continue;
    }
    std::string expected = "--" + std::string(o.key);
    std::replace(expected.begin(), expected.end(), '_', '-');
    EXPECT_EQ(o.flag, expected);
    EXPECT_TRUE(flags.insert(std::string(o.flag)).second) << o.flag;
    EXPECT_EQ(o.type == JobOptionType::kFlag, o.value_name.empty()) << o.key;
  }
  // Every geometry parameter of mapping/proxy_schema.h is a proxy bake's option.
  for (const GeometryParam& p : geometry_params()) {
    const JobOption* o = find_job_option(p.key);
    ASSERT_NE(o, nullptr) << p.key;
    EXPECT_EQ(o->bakes, bakes::kProxy) << p.key;
  }
  EXPECT_EQ(find_job_option("quiet"), nullptr);  // the command line's own
  EXPECT_EQ(find_job_option("help"), nullptr);
}

TEST(JobOptions, TheTablesBakesAreTheSpecs) {
  // SPEC section 4: the atlas's own options; section 9: the photos'.
  for (const char* key : {"size", "padding", "uv", "format"})
    EXPECT_EQ(find_job_option(key)->bakes, bakes::kAtlas) << key;
  EXPECT_EQ(find_job_option("ascii")->bakes, bakes::kVertex);
  for (const char* key : {"cameras", "images", "blend", "exposure"})
    EXPECT_EQ(find_job_option(key)->bakes, bakes::kPhotos) << key;
  EXPECT_EQ(find_job_option("strict_photos")->bakes, bakes::kPhotos | bakes::kLayers);
  EXPECT_EQ(find_job_option("layers")->bakes, bakes::kLayers);
  // --samples: the proxy vertex bake's area samples, every atlas's supersamples.
  EXPECT_EQ(find_job_option("samples")->bakes, bakes::kProxy | bakes::kAtlas);
}

std::vector<JobSetting> bunny(std::vector<JobSetting> more, const std::string& output) {
  std::vector<JobSetting> s = {{"mesh", (kData / "bunny00.off").string()},
                               {"texture", (kData / "earth.jpg").string()},
                               {"output", output}};
  s.insert(s.end(), more.begin(), more.end());
  return s;
}

TEST(JobFromSettings, AProxyVertexJobWithTheDefaults) {
  Expected<Job> job = job_from_settings(bunny({{"proxy", "sphere"}, {"up", "y"}}, "o.ply"));
  ASSERT_TRUE(job) << job.error().message;
  EXPECT_EQ(job->target, JobTarget::kVertex);  // .ply
  EXPECT_FALSE(job->proxy);                    // centre and radius to be fitted
  EXPECT_EQ(job->spec.kind, ProxyKind::kSphere);
  ASSERT_TRUE(job->spec.up);
  EXPECT_EQ(*job->spec.up, (Vec3{0, 1, 0}));
  // SPEC section 4/5 defaults: --filter area, 16 samples, visibility first,
  // occluded fill, outside clamp, stored encoding.
  EXPECT_EQ(job->shading.filter, VertexFilter::kArea);
  EXPECT_EQ(job->shading.samples, 16);
  EXPECT_EQ(job->shading.visibility, Visibility::kFirst);
  EXPECT_EQ(job->shading.occluded, OccludedMode::kFill);
  EXPECT_EQ(job->shading.outside, OutsideMode::kClamp);
  EXPECT_FALSE(job->shading.linear);
  EXPECT_EQ(job->cache_mb, kDefaultCacheMb);
  EXPECT_EQ(job->threads, 0);
  EXPECT_EQ(job->naming, ParamNaming::kFlag);
}

TEST(JobFromSettings, AGivenProxyIsBuiltAndTheAtlasOptionsSet) {
  Expected<Job> job = job_from_settings(bunny({{"proxy", "sphere"},
                                               {"center", "0,0.1,0"},
                                               {"radius", "2"},
                                               {"size", "256"},
                                               {"samples", "2"},
                                               {"filter", "ewa"},
                                               {"occluded", "1,0,0"},
                                               {"threads", "3"},
                                               {"linear", "true"},
                                               {"ascii", "false"}},
                                              "o.obj"));
  ASSERT_TRUE(job) << job.error().message;
  EXPECT_EQ(job->target, JobTarget::kAtlas);  // .obj
  ASSERT_TRUE(job->proxy);
  const ProxyParams params = params_of(*job->proxy);
  const SphereParams* s = std::get_if<SphereParams>(&params);
  ASSERT_NE(s, nullptr);
  EXPECT_EQ(s->center, (Vec3{0, 0.1, 0}));
  EXPECT_EQ(s->radius, 2.0);
  EXPECT_EQ(job->atlas.bake.size, 256);
  EXPECT_EQ(job->atlas.bake.samples, 2);
  EXPECT_EQ(job->atlas.uv, UvLayout::kAuto);
  EXPECT_EQ(job->shading.filter, VertexFilter::kEwa);
  EXPECT_EQ(job->shading.occluded, OccludedMode::kColor);
  EXPECT_EQ(job->shading.occluded_color, (Rgba{1, 0, 0, 1}));
  EXPECT_TRUE(job->shading.linear);
  EXPECT_EQ(job->threads, 3);
  // The atlas's lookup is bilinear unless ewa.
  Expected<Job> plain = job_from_settings(bunny({{"proxy", "sphere"}}, "o.obj"));
  ASSERT_TRUE(plain) << plain.error().message;
  EXPECT_EQ(plain->shading.filter, VertexFilter::kBilinear);
  EXPECT_EQ(plain->atlas.bake.samples, 4);
  EXPECT_EQ(plain->atlas.bake.size, 2048);
}

TEST(JobFromSettings, PhotosAndLayersJobs) {
  Expected<Job> photos = job_from_settings(std::vector<JobSetting>{{"mesh", "m.ply"},
                                                                   {"cameras", "sparse/0"},
                                                                   {"images", "photos"},
                                                                   {"blend", "best"},
                                                                   {"strict_photos", "true"},
                                                                   {"output", "o.obj"},
                                                                   {"samples", "2"}});
  ASSERT_TRUE(photos) << photos.error().message;
  EXPECT_EQ(photos->cameras, fs::path("sparse/0"));
  EXPECT_EQ(photos->images, fs::path("photos"));
  EXPECT_EQ(photos->photo_options.blend, PhotoBlend::kBest);
  EXPECT_EQ(photos->photo_options.exposure, ExposureMode::kGain);
  EXPECT_TRUE(photos->photo_options.strict_photos);
  EXPECT_EQ(photos->atlas.bake.samples, 2);

  Expected<Job> layers = job_from_settings(std::vector<JobSetting>{
      {"mesh", "m.ply"}, {"layers", "l.json"}, {"output", "o.glb"}, {"occluded", "0,0,1,0.5"}});
  ASSERT_TRUE(layers) << layers.error().message;
  EXPECT_EQ(layers->layers, fs::path("l.json"));
  EXPECT_EQ(layers->target, JobTarget::kAtlas);
  EXPECT_EQ(layers->atlas.bake.size, 0);  // not given: the base texture's size, else 2048
  EXPECT_EQ(layers->layers_options.occluded, OccludedMode::kColor);
  EXPECT_EQ(layers->layers_options.occluded_color, (Rgba{0, 0, 1, 0.5f}));
}

TEST(JobOptionDefault, TheTablesDefaultsAsValuesPerTarget) {
  // SPEC sections 4, 5 and 9: the flags' documented defaults.
  const auto d = [](const char* key, JobTarget t) {
    return job_option_default(*find_job_option(key), t);
  };
  EXPECT_EQ(d("samples", JobTarget::kVertex), "16");
  EXPECT_EQ(d("samples", JobTarget::kAtlas), "4");
  EXPECT_EQ(d("filter", JobTarget::kVertex), "area");
  EXPECT_EQ(d("filter", JobTarget::kAtlas), "bilinear");
  EXPECT_EQ(d("size", JobTarget::kAtlas), "2048");
  EXPECT_EQ(d("cache_mb", JobTarget::kVertex), "1024");
  EXPECT_EQ(d("occluded", JobTarget::kAtlas), "fill");
  EXPECT_EQ(d("blend", JobTarget::kVertex), "soft");
  EXPECT_EQ(d("linear", JobTarget::kVertex), "false");
  // In words: worked out by the job.
  for (const char* key : {"target", "padding", "threads", "images", "center", "mesh", "proxy"}) {
    EXPECT_EQ(d(key, JobTarget::kVertex), "") << key;
    EXPECT_EQ(d(key, JobTarget::kAtlas), "") << key;
  }
}

TEST(JobOptionDefault, EveryDefaultIsAValueOrKnownWords) {
  // A default_text that is meant as a value but does not parse (a typo)
  // would silently become words: only these options' defaults are words.
  std::set<std::string> words = {"target", "padding", "threads", "images"};
  for (const GeometryParam& p : geometry_params()) words.insert(std::string(p.key));
  for (const JobOption& o : job_options()) {
    if (o.default_text.empty()) continue;
    const bool value = !job_option_default(o, JobTarget::kVertex).empty();
    EXPECT_EQ(value, !job_option_default(o, JobTarget::kAtlas).empty()) << o.key;
    EXPECT_NE(value, words.count(std::string(o.key)) == 1) << o.key << ": " << o.default_text;
  }
}

TEST(JobFromSettings, AnOptionNotGivenTakesTheTablesDefaultForTheTarget) {
  // Jobs with nothing but their inputs hold the table's defaults for their
  // target (SPEC sections 4, 5 and 9), for the photos' and the atlas's
  // options that had no test of their default.
  Expected<Job> photos = job_from_settings(
      std::vector<JobSetting>{{"mesh", "m.ply"}, {"cameras", "sparse/0"}, {"output", "o.obj"}});
  ASSERT_TRUE(photos) << photos.error().message;
  EXPECT_EQ(photos->atlas.bake.samples, 4);
  EXPECT_EQ(photos->atlas.bake.size, 2048);
  EXPECT_EQ(photos->atlas.uv, UvLayout::kAuto);
  EXPECT_EQ(photos->photo_options.blend, PhotoBlend::kSoft);
  EXPECT_EQ(photos->photo_options.exposure, ExposureMode::kGain);
  EXPECT_EQ(photos->photo_options.color_space, TextureColorSpace::kAuto);
  EXPECT_EQ(photos->photo_options.occluded, OccludedMode::kFill);
  EXPECT_EQ(photos->cache_mb, kDefaultCacheMb);
  EXPECT_EQ(photos->write.format, AtlasFormat::kPng8);
  Expected<Job> atlas = job_from_settings(bunny({{"proxy", "plane"}}, "o.glb"));
  ASSERT_TRUE(atlas) << atlas.error().message;
  EXPECT_EQ(atlas->shading.filter, VertexFilter::kBilinear);  // the atlas's default
  EXPECT_EQ(atlas->shading.plane_wrap, WrapMode::kClamp);
  EXPECT_EQ(atlas->shading.outside, OutsideMode::kClamp);
  EXPECT_EQ(atlas->atlas.bake.samples, 4);
  EXPECT_EQ(atlas->atlas.bake.padding, kPaddingDefault);
  // --wrap's default is no --wrap: a sphere without it is no error.
  EXPECT_TRUE(job_from_settings(bunny({{"proxy", "sphere"}}, "o.ply")));
}

// Each bad set of settings and the start of its message (the command line's).
TEST(JobFromSettings, RefusalsNameTheFlagAsTheCommandLineDoes) {
  struct Case {
    std::vector<JobSetting> more;
    std::string output, message;
  };
  const std::vector<Case> cases = {
      {{{"proxy", "sphere"}, {"size", "64"}}, "o.ply", "--size applies to --target atlas only"},
      {{{"proxy", "sphere"}, {"ascii", "true"}},
       "o.obj",
       "--ascii applies to --target vertex only"},
      {{{"proxy", "sphere"}, {"filter", "area"}},
       "o.obj",
       "--filter area applies to --target vertex only"},
      {{{"proxy", "sphere"}, {"blend", "best"}}, "o.ply", "--blend applies to --cameras only"},
      {{{"proxy", "sphere"}, {"strict_photos", "true"}},
       "o.ply",
       "--strict-photos applies to --cameras and --layers only"},
      {{{"proxy", "sphere"}, {"samples", "0"}},
       "o.ply",
       "--samples 0 is out of range (1 .. 65536)"},
      {{{"proxy", "sphere"}, {"samples", "300"}}, "o.obj", "--samples"},
      {{{"proxy", "sphere"}, {"samples", "x"}}, "o.ply", "--samples: 'x' is not an integer"},
      {{{"proxy", "sphere"}, {"center", "1,2"}}, "o.ply", "--center: expected x,y,z"},
      {{{"proxy", "cube"}}, "o.ply", "--proxy: unknown proxy kind 'cube'"},
      {{{"proxy", "sphere"}, {"filter", "box"}}, "o.ply", "--filter: unknown value 'box'"},
      {{{"proxy", "sphere"}, {"wrap", "repeat"}}, "o.ply", "--wrap applies to the plane proxy"},
      {{{"proxy", "sphere"}, {"apex", "0,0,0"}},
       "o.ply",
       "--apex does not apply to --proxy sphere"},
      {{{"proxy", "sphere"}, {"threads", "0"}}, "o.ply", "--threads 0 is out of range (1 .. 4096)"},
      {{{"proxy", "sphere"}, {"linear", "yes"}}, "o.ply", "--linear: 'yes' is not true or false"},
      {{{"proxy", "sphere"}, {"radius", "1"}, {"radius", "2"}}, "o.ply", "--radius is given twice"},
      {{{"proxy", "sphere"}, {"colour", "1"}}, "o.ply", "key 'colour' is not an option"},
      {{{"proxy", "sphere"}, {"proxy-file", "p.json"}}, "o.ply", "(did you mean 'proxy_file'?)"},
      {{}, "o.ply", "missing --proxy KIND or --proxy-file FILE"},
      {{{"proxy", "sphere"}}, "o.stl", "o.stl"},
      {{{"proxy", "sphere"}, {"report", ""}}, "o.ply", "--report: an empty path"},
  };
  for (const Case& c : cases) {
    Expected<Job> job = job_from_settings(bunny(c.more, c.output));
    ASSERT_FALSE(job) << c.message;
    EXPECT_EQ(exit_code(job.error()), 2) << job.error().message;
    EXPECT_NE(job.error().message.find(c.message), std::string::npos)
        << "expected '" << c.message << "' in '" << job.error().message << "'";
  }
  // Options of the other bakes, named with the bake's reason.
  const std::vector<std::pair<std::vector<JobSetting>, std::string>> others = {
      {{{"cameras", "c.json"}, {"texture", "t.png"}}, "--texture does not apply to --cameras"},
      {{{"cameras", "c.json"}, {"cache_mb", "8"}},
       "--cache-mb does not apply to --cameras (photos are read whole"},
      {{{"cameras", "c.json"}, {"samples", "8"}},
       "--samples applies to --target atlas only with --cameras"},
      {{{"cameras", "c.json"}, {"center", "0,0,0"}}, "--center does not apply to --cameras"},
      {{{"layers", "l.json"}, {"texture", "t.png"}}, "--texture does not apply to --layers"},
      {{{"layers", "l.json"}, {"cameras", "c.json"}}, "--cameras does not apply to --layers"},
      {{{"layers", "l.json"}, {"size", "64"}}, "--size applies to --target atlas only"},
  };
  for (const auto& [more, message] : others) {
    std::vector<JobSetting> s = {{"mesh", "m.ply"}, {"output", "o.ply"}};
    s.insert(s.end(), more.begin(), more.end());
    Expected<Job> job = job_from_settings(s);
    ASSERT_FALSE(job) << message;
    EXPECT_NE(job.error().message.find(message), std::string::npos)
        << "expected '" << message << "' in '" << job.error().message << "'";
  }
  // The first bad value reported is the table's first, whatever the order given.
  Expected<Job> two = job_from_settings(bunny({{"samples", "0"}, {"proxy", "cube"}}, "o.ply"));
  ASSERT_FALSE(two);
  EXPECT_NE(two.error().message.find("--proxy"), std::string::npos) << two.error().message;
}

TEST(JobSettingsFromJson, ValuesBecomeTheCommandLinesText) {
  Expected<std::vector<JobSetting>> s = job_settings_from_json(
      R"({"mesh": "m.ply", "center": [0, 1.5, -2], "radius": 2,
          "corners": [[0,0,0],[1,0,0],[1,1,0],[0,1,0]], "linear": true, "ascii": false,
          "samples": 8})");
  ASSERT_TRUE(s) << s.error().message;
  const std::vector<std::pair<std::string, std::string>> expected = {
      {"mesh", "m.ply"},  {"center", "0,1.5,-2"},
      {"radius", "2"},    {"corners", "0,0,0;1,0,0;1,1,0;0,1,0"},
      {"linear", "true"}, {"ascii", "false"},
      {"samples", "8"}};
  ASSERT_EQ(s->size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ((*s)[i].key, expected[i].first);
    EXPECT_EQ((*s)[i].value, expected[i].second);
  }
  EXPECT_FALSE(job_settings_from_json(R"({"linear": 1})"));               // a flag takes true/false
  EXPECT_FALSE(job_settings_from_json(R"({"samples": true})"));           // not a flag
  EXPECT_FALSE(job_settings_from_json(R"({"center": {"x": 1}})"));        // not a value
  EXPECT_FALSE(job_settings_from_json(R"({"quiet": true})"));             // the batch's
  EXPECT_FALSE(job_settings_from_json(R"({"radius": 1e999})"));           // not finite
  EXPECT_FALSE(job_settings_from_json(R"({"radius": 1, "radius": 2})"));  // twice
}

class BatchRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("texbake_batch_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A small proxy bake to `out`, as a batch line.
  std::string line(const fs::path& out, const std::string& more = "") const {
    return R"({"mesh": ")" + (kData / "bunny00.off").string() + R"(", "texture": ")" +
           (kData / "earth.jpg").string() +
           R"(", "proxy": "sphere", "up": "y", "filter": "bilinear", "output": ")" + out.string() +
           "\"" + more + "}";
  }

  fs::path dir_;
};

TEST_F(BatchRun, EachJobIsRecordedAsItEndsAndAFailureIsItsOwn) {
  const fs::path results = dir_ / "r.jsonl";
  const std::vector<BatchJob> jobs = {{1, line(dir_ / "a.ply")},
                                      {2, line(dir_ / "b.ply", R"(, "samples": 0)")},
                                      {4, line(dir_ / "c.ply", R"(, "threads": 1)")}};
  BatchOptions options;
  options.results = results;
  options.threads = 2;
  std::vector<std::size_t> ended;
  options.on_job_end = [&](const BatchJobResult& r) {
    ended.push_back(r.line);
    // Appended and flushed before the next job starts.
    EXPECT_EQ(lines_of(results).size(), ended.size());
  };
  const BatchResult batch = run_batch(jobs, options);
  ASSERT_FALSE(batch.error);
  EXPECT_EQ(ended, (std::vector<std::size_t>{1, 2, 4}));
  EXPECT_EQ(batch.ok, 2u);
  EXPECT_EQ(batch.failed, 1u);
  EXPECT_EQ(batch.not_run, 0u);
  ASSERT_EQ(batch.jobs.size(), 3u);
  EXPECT_EQ(batch.jobs[1].status, "failed");
  EXPECT_EQ(batch.jobs[1].result.exit_code, 2);
  EXPECT_NE(batch.jobs[1].result.error->message.find("--samples 0 is out of range"),
            std::string::npos);
  EXPECT_FALSE(fs::exists(dir_ / "b.ply"));
  // The same job run alone writes the same bytes.
  Expected<std::vector<JobSetting>> settings = job_settings_from_json(line(dir_ / "alone.ply"));
  ASSERT_TRUE(settings);
  Expected<Job> alone = job_from_settings(*settings);
  ASSERT_TRUE(alone);
  ASSERT_TRUE(run_job(*alone).ok());
  EXPECT_EQ(bytes(dir_ / "a.ply"), bytes(dir_ / "alone.ply"));
  // The results file: one line per job, as it ended.
  const std::vector<std::string> lines = lines_of(results);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0], batch.jobs[0].json);
  EXPECT_NE(lines[0].find(R"("line":1,"status":"ok","exit":0,"error":null)"), std::string::npos)
      << lines[0];
  EXPECT_NE(lines[1].find(R"("line":2,"status":"failed","exit":2)"), std::string::npos) << lines[1];
  EXPECT_NE(lines[2].find(R"("line":4,"status":"ok")"), std::string::npos) << lines[2];

  // fail_fast stops at the failure; skip_existing skips what is up to date.
  options.fail_fast = true;
  options.on_job_end = nullptr;
  const BatchResult fast = run_batch(jobs, options);
  EXPECT_EQ(fast.jobs.size(), 2u);
  EXPECT_EQ(fast.not_run, 1u);
  options.fail_fast = false;
  options.skip_existing = true;
  const BatchResult again = run_batch(jobs, options);
  EXPECT_EQ(again.skipped, 2u);
  EXPECT_EQ(again.jobs[0].status, "skipped");
}

TEST_F(BatchRun, JobsShareTheMeshAndTextureTheyReadAndWriteTheSameBytes) {
  // Four jobs on one mesh and one texture: a vertex bake, the same with
  // another filter (the same files), an atlas (which consumes a copy of the
  // shared mesh) and a vertex bake with another texture colour space (the
  // texture read again: other read options). Each writes the bytes of the
  // same job run alone, without the cache.
  const std::vector<std::string> more = {"", R"(, "filter": "area")",
                                         R"(, "size": 64, "samples": 1)",
                                         R"(, "texture_colorspace": "linear")"};
  const std::vector<fs::path> outputs = {dir_ / "a.ply", dir_ / "b.ply", dir_ / "c.obj",
                                         dir_ / "d.ply"};
  std::vector<BatchJob> jobs;
  for (std::size_t i = 0; i < more.size(); ++i) {
    std::string l = line(outputs[i], more[i]);
    if (i == 1) l.replace(l.find(R"("filter": "bilinear", )"), 22, "");  // one filter key
    jobs.push_back({i + 1, l});
  }
  BatchOptions options;
  options.cache = std::make_shared<JobCache>();
  const BatchResult batch = run_batch(jobs, options);
  ASSERT_FALSE(batch.error);
  ASSERT_EQ(batch.ok, 4u) << (batch.failed ? batch.jobs[0].json : "");
  const JobCache::Counts counts = options.cache->counts();
  EXPECT_EQ(counts.mesh_reads, 1u);
  EXPECT_EQ(counts.mesh_hits, 3u);
  EXPECT_EQ(counts.image_reads, 2u);  // the fourth job's colour space
  EXPECT_EQ(counts.image_hits, 2u);
  // The first two vertex bakes test visibility on one scene, built by the
  // first; the atlas lets it go, so the last builds it again.
  EXPECT_EQ(counts.scene_builds, 2u);
  EXPECT_EQ(counts.scene_hits, 1u);
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    Expected<std::vector<JobSetting>> settings = job_settings_from_json(jobs[i].json);
    ASSERT_TRUE(settings);
    Expected<Job> alone = job_from_settings(*settings);
    ASSERT_TRUE(alone);
    const fs::path moved = dir_ / ("alone_" + outputs[i].filename().string());
    alone->output = moved;
    ASSERT_TRUE(run_job(*alone).ok()) << i;
    if (outputs[i].extension() == ".obj") {
      // The atlas image (the .obj and .mtl name their own files).
      fs::path png = outputs[i], alone_png = moved;
      EXPECT_EQ(bytes(png.replace_extension(".png")), bytes(alone_png.replace_extension(".png")));
    } else {
      EXPECT_EQ(bytes(outputs[i]), bytes(moved)) << i;
    }
  }
}

TEST_F(BatchRun, ACachedFileChangedOnDiskIsReadAgain) {
  const fs::path mesh = dir_ / "m.off";
  fs::copy_file(kData / "bunny00.off", mesh);
  JobCache cache;
  Expected<std::shared_ptr<const LoadedMesh>> first = cache.mesh(mesh);
  ASSERT_TRUE(first);
  Expected<std::shared_ptr<const LoadedMesh>> again = cache.mesh(mesh);
  ASSERT_TRUE(again);
  EXPECT_EQ(first->get(), again->get());  // the same object
  // The held mesh's scene: built once, then the same scene.
  bool built = false;
  Expected<std::shared_ptr<const EmbreeScene>> scene = cache.scene(*first, &built);
  ASSERT_TRUE(scene);
  ASSERT_NE(scene->get(), nullptr);
  EXPECT_TRUE(built);
  Expected<std::shared_ptr<const EmbreeScene>> scene_again = cache.scene(*first, &built);
  ASSERT_TRUE(scene_again);
  EXPECT_EQ(scene_again->get(), scene->get());
  EXPECT_FALSE(built);
  // Another mesh at the same path (a tetrahedron, 4 vertices), written later.
  std::ofstream(mesh) << "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                         "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
  fs::last_write_time(mesh, fs::last_write_time(mesh) + std::chrono::seconds(2));
  Expected<std::shared_ptr<const LoadedMesh>> changed = cache.mesh(mesh);
  ASSERT_TRUE(changed);
  EXPECT_EQ((*changed)->mesh.positions.size(), 4u);
  EXPECT_EQ(cache.counts().mesh_reads, 2u);
  EXPECT_EQ(cache.counts().mesh_hits, 1u);
  // The old mesh is no longer held: no scene for it (the caller builds its own).
  Expected<std::shared_ptr<const EmbreeScene>> stale = cache.scene(*first);
  ASSERT_TRUE(stale);
  EXPECT_EQ(stale->get(), nullptr);
  EXPECT_EQ(cache.counts().scene_builds, 1u);
  EXPECT_EQ(cache.counts().scene_hits, 1u);
  // A file that cannot be read is the reader's error, and not cached.
  EXPECT_FALSE(cache.mesh(dir_ / "missing.off"));
  EXPECT_FALSE(cache.image(dir_ / "missing.png", {}));
}

TEST_F(BatchRun, NoJobMayWriteTheManifestOrTheResults) {
  const fs::path manifest = dir_ / "jobs.jsonl";
  std::ofstream(manifest) << "{}\n";
  const fs::path results = dir_ / "r.jsonl";
  const std::vector<BatchJob> jobs = {{1, line(manifest)}, {2, line(results)}};
  BatchOptions options;
  options.manifest = manifest;
  options.results = results;
  const BatchResult batch = run_batch(jobs, options);
  ASSERT_FALSE(batch.error);
  ASSERT_EQ(batch.jobs.size(), 2u);
  for (const BatchJobResult& r : batch.jobs) {
    EXPECT_EQ(r.status, "failed");
    EXPECT_EQ(r.result.exit_code, 2);
  }
  EXPECT_EQ(bytes(manifest), "{}\n");  // untouched
  // The manifest may not be the results file either: the batch's own error.
  options.results = manifest;
  const BatchResult same = run_batch(jobs, options);
  ASSERT_TRUE(same.error);
  EXPECT_EQ(exit_code(*same.error), 2);
  EXPECT_EQ(bytes(manifest), "{}\n");
}

}  // namespace
}  // namespace texbake
