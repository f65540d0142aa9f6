// RunOptions of texbake/texbake.h: the progress callback (fractions per stage,
// never concurrent, cancelling) and the per-call thread count.
#include <gtest/gtest.h>

#include <atomic>
#include <map>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "tests/bake/bunny_earth.h"
#include "texbake/texbake.h"

namespace texbake {
namespace {

// Records every call of a progress callback; cancels (returns false) once
// a fraction of `cancel_stage` reaches `cancel_at`.
struct Recorder {
  std::string cancel_stage = "";
  double cancel_at = 2;  // > 1: never cancels

  std::mutex mutex;
  std::vector<std::pair<std::string, double>> calls;
  std::atomic<int> inside{0};
  bool overlapped = false;
  int calls_after_false = 0;
  bool said_false = false;
  std::vector<std::thread::id> threads;

  ProgressCallback callback() {
    return [this](std::string_view stage, double fraction) {
      if (inside.fetch_add(1) != 0) overlapped = true;
      bool go = true;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (said_false) ++calls_after_false;
        calls.emplace_back(std::string(stage), fraction);
        threads.push_back(std::this_thread::get_id());
        if (stage == cancel_stage && fraction >= cancel_at) {
          said_false = true;
          go = false;
        }
      }
      inside.fetch_sub(1);
      return go;
    };
  }

  // RunOptions of `threads` threads reporting to this recorder.
  RunOptions run(int threads = 0) {
    RunOptions r;
    r.threads = threads;
    r.progress = callback();
    return r;
  }

  // The fractions of each stage, in call order.
  std::map<std::string, std::vector<double>> by_stage() const {
    std::map<std::string, std::vector<double>> out;
    for (const auto& [stage, f] : calls) out[stage].push_back(f);
    return out;
  }
};

// A call cancelled by `r`'s false: kCancelled, and no call after the false.
void expect_cancelled(const Error& error, const Recorder& r) {
  EXPECT_EQ(error.code, ErrorCode::kCancelled) << error.message;
  EXPECT_EQ(category(error), ErrorCategory::kCancelled);
  EXPECT_EQ(r.calls_after_false, 0) << "the callback is not called after it said false";
}

// The bunny's atlas of `size` through the API.
Expected<Atlas> bunny_atlas(int size, const RunOptions& run) {
  const test::BunnyEarth* be = test::bunny_earth();
  if (!be) return make_error(ErrorCode::kIo, "no bunny");
  AtlasOptions options;
  options.bake.size = size;
  return bake_atlas_texture(be->mesh, be->earth.view(), be->proxy, options, run);
}

void expect_well_formed(const Recorder& r, const std::vector<std::string>& stages) {
  EXPECT_FALSE(r.overlapped) << "the callback was called concurrently with itself";
  const auto by_stage = r.by_stage();
  for (const std::string& stage : stages) {
    ASSERT_TRUE(by_stage.count(stage)) << "stage " << stage << " was not reported";
    const std::vector<double>& f = by_stage.at(stage);
    EXPECT_EQ(f.front(), 0.0) << stage;
    EXPECT_EQ(f.back(), 1.0) << stage;
    // At most about every percent: 0, each whole percent once, 1.
    EXPECT_LE(f.size(), 101u) << stage;
    for (std::size_t i = 1; i < f.size(); ++i) {
      EXPECT_GT(f[i], f[i - 1]) << stage << " call " << i;
    }
  }
}

TEST(ApiProgress, VertexBakeReportsBakeThenFillMonotonically) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Recorder rec;
  const RunOptions run = rec.run();
  Expected<VertexColors> baked =
      bake_vertex_colors(be->mesh, be->earth.view(), be->proxy, VertexBakeOptions{}, run);
  ASSERT_TRUE(baked) << baked.error().message;
  expect_well_formed(rec, {"bake", "fill"});
  // The bunny's 37706 vertices in chunks of 1024: more than 10 reports in between.
  EXPECT_GT(rec.by_stage().at("bake").size(), 10u);
  // Stages in order: every "bake" call before the first "fill".
  std::size_t last_bake = 0, first_fill = rec.calls.size();
  for (std::size_t i = 0; i < rec.calls.size(); ++i) {
    if (rec.calls[i].first == "bake") last_bake = i;
    if (rec.calls[i].first == "fill") first_fill = std::min(first_fill, i);
  }
  EXPECT_LT(last_bake, first_fill);
}

TEST(ApiProgress, AtlasBakeReportsLayoutThenSamples) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Recorder rec;
  const RunOptions run = rec.run();
  Expected<Atlas> atlas = bunny_atlas(256, run);
  ASSERT_TRUE(atlas) << atlas.error().message;
  expect_well_formed(rec, {"uv_layout", "sample"});
  EXPECT_EQ(rec.calls.front().first, "uv_layout");
}

TEST(ApiProgress, RenderReportsItsTiles) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Recorder rec;
  const RunOptions run = rec.run();
  Expected<Rendered> r = render_mesh(be->mesh, GreySource{}, test::bunny_view(64, 1), run);
  ASSERT_TRUE(r) << r.error().message;
  expect_well_formed(rec, {"render"});
}

TEST(ApiCancel, FalseAtHalfOfTheBakeCancelsTheVertexBake) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  for (int threads : {1, 2}) {
    Recorder rec{"bake", 0.5};
    Expected<VertexColors> baked =
        bake_vertex_colors(be->mesh, be->earth.view(), be->proxy, {}, rec.run(threads));
    ASSERT_FALSE(baked) << threads << " threads: the bake was not cancelled";
    expect_cancelled(baked.error(), rec);
    EXPECT_EQ(rec.by_stage().count("fill"), 0u) << "the fill must not run after a cancel";
    // It stopped at (about) half: the last fraction heard is below 1.
    EXPECT_LT(rec.calls.back().second, 1.0);
  }
}

// The bunny's layers: the Earth through its sphere, one layer.
LayersSpec bunny_layers() {
  LayersSpec spec;
  LayerSpec layer;
  layer.projector = test::bunny_earth()->proxy;
  layer.texture = test::shared_data("earth.jpg");
  spec.layers.push_back(layer);
  return spec;
}

TEST(ApiProgress, LayersVertexBakeReportsLayersBakeThenFill) {
  ASSERT_TRUE(test::bunny_earth());
  Recorder rec;
  Expected<LayerColors> baked =
      bake_vertex_colors_from_layers(test::bunny_earth()->mesh, bunny_layers(), {}, rec.run());
  ASSERT_TRUE(baked) << baked.error().message;
  expect_well_formed(rec, {"layers", "bake", "fill"});
  // The bunny's 37706 vertices in blocks of 4096: reports in between.
  EXPECT_GT(rec.by_stage().at("bake").size(), 5u);
  // In order: the layers read, then every "bake" call, then the fill.
  std::size_t last_layers = 0, first_bake = rec.calls.size(), last_bake = 0,
              first_fill = rec.calls.size();
  for (std::size_t i = 0; i < rec.calls.size(); ++i) {
    const std::string& stage = rec.calls[i].first;
    if (stage == "layers") last_layers = i;
    if (stage == "bake") first_bake = std::min(first_bake, i), last_bake = i;
    if (stage == "fill") first_fill = std::min(first_fill, i);
  }
  EXPECT_LT(last_layers, first_bake);
  EXPECT_LT(last_bake, first_fill);
}

TEST(ApiCancel, FalseAtHalfOfTheBakeCancelsTheLayersVertexBake) {
  ASSERT_TRUE(test::bunny_earth());
  for (int threads : {1, 2}) {
    Recorder rec{"bake", 0.5};
    Expected<LayerColors> baked = bake_vertex_colors_from_layers(
        test::bunny_earth()->mesh, bunny_layers(), {}, rec.run(threads));
    ASSERT_FALSE(baked) << threads << " threads: the layers bake was not cancelled";
    expect_cancelled(baked.error(), rec);
    EXPECT_EQ(rec.by_stage().count("fill"), 0u) << "the fill must not run after a cancel";
    EXPECT_LT(rec.calls.back().second, 1.0);
  }
}

TEST(ApiCancel, FalseAtHalfOfTheSamplesCancelsTheAtlasBake) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Recorder rec{"sample", 0.5};
  Expected<Atlas> atlas = bunny_atlas(256, rec.run());  // 16 bands of 16 rows
  ASSERT_FALSE(atlas) << "the atlas bake was not cancelled";
  expect_cancelled(atlas.error(), rec);
  EXPECT_LT(rec.calls.back().second, 1.0);
}

TEST(ApiCancel, FalseAtTheStartOfTheLayoutCancelsBeforeTheBake) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Recorder rec{"uv_layout", 0};
  Expected<Atlas> atlas = bunny_atlas(64, rec.run());
  ASSERT_FALSE(atlas);
  expect_cancelled(atlas.error(), rec);
  ASSERT_EQ(rec.calls.size(), 1u) << "nothing after the refused start";
}

TEST(ApiCancel, FalseAtTheLastCallStillCancels) {
  // Returning false when the work is done (fraction 1 of the last stage)
  // cancels too: the call never returns a result after a false.
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Recorder rec{"render", 1.0};
  Expected<Rendered> r = render_mesh(be->mesh, GreySource{}, test::bunny_view(32, 1), rec.run());
  ASSERT_FALSE(r);
  expect_cancelled(r.error(), rec);
}

TEST(ApiThreads, ResultsAreIdenticalWithOneAndTwoThreads) {
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  RunOptions one, two;
  one.threads = 1;
  two.threads = 2;

  Expected<VertexColors> v1 = bake_vertex_colors(be->mesh, be->earth.view(), be->proxy, {}, one);
  Expected<VertexColors> v2 = bake_vertex_colors(be->mesh, be->earth.view(), be->proxy, {}, two);
  ASSERT_TRUE(v1 && v2);
  EXPECT_TRUE(v1->colors == v2->colors);
  EXPECT_EQ(v1->stats.counts.occluded, v2->stats.counts.occluded);

  Expected<Atlas> a1 = bunny_atlas(128, one);
  Expected<Atlas> a2 = bunny_atlas(128, two);
  ASSERT_TRUE(a1 && a2);
  EXPECT_TRUE(a1->image.pixels == a2->image.pixels);
  EXPECT_TRUE(a1->mesh.uvs.size() == a2->mesh.uvs.size());

  const RenderOptions ro = test::bunny_view(48, 4);
  const ColorSource source = ProjectionSource{be->proxy, be->earth.view(), std::nullopt};
  Expected<Rendered> r1 = render_mesh(be->mesh, source, ro, one);
  Expected<Rendered> r2 = render_mesh(be->mesh, source, ro, two);
  ASSERT_TRUE(r1 && r2);
  EXPECT_TRUE(r1->image.pixels == r2->image.pixels);
}

TEST(ApiThreads, OneThreadRunsEveryStageOnTheCallingThread) {
  // A one-thread arena has only the caller's slot: every chunk, hence every
  // progress report, runs on the calling thread.
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_TRUE(be);
  Recorder rec;
  ASSERT_TRUE(bake_vertex_colors(be->mesh, be->earth.view(), be->proxy, {}, rec.run(1)));
  ASSERT_FALSE(rec.threads.empty());
  for (std::thread::id id : rec.threads) EXPECT_EQ(id, std::this_thread::get_id());
}

}  // namespace
}  // namespace texbake
