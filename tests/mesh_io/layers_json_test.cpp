// The layers file (SPEC section 10, mesh_io/layers_json.h): every key, its
// defaults, paths relative to the file, and errors naming the file and key.
#include "mesh_io/layers_json.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

namespace texbake {
namespace {

namespace fs = std::filesystem;

const char* kSphere =
    R"("proxy":{"kind":"sphere","center":[0,0,0],"radius":1,"pole":[0,0,1],"equator":[1,0,0]})";

TEST(LayersJson, EveryKeyAndTheDefaults) {
  const std::string text = std::string(R"({"base":[0.5,0.25,1,1],"layers":[{)") + kSphere +
                           R"(,"texture":"a.png"},{)" + kSphere +
                           R"(,"texture":"/abs/b.png","mask":"m/b.png","opacity":0.5,)"
                           R"("mode":"multiply","angle_fade":[60,80],"visibility":"all",)"
                           R"("outside":[0,1,0,0.5]},{)" +
                           kSphere + R"(,"texture":"c.png","outside":"clamp","mode":"replace"}]})";
  Expected<LayersSpec> spec = layers_from_json(text, "/data/set", "L.json");
  ASSERT_TRUE(spec) << spec.error().message;
  EXPECT_EQ(spec->base, LayerBase::kColor);
  EXPECT_FLOAT_EQ(spec->base_color[1], 0.25f);
  ASSERT_EQ(spec->layers.size(), 3u);
  const LayerSpec& a = spec->layers[0];
  ASSERT_TRUE(a.projector);
  EXPECT_TRUE(std::holds_alternative<Proxy>(*a.projector));
  EXPECT_EQ(a.texture, fs::path("/data/set/a.png"));
  EXPECT_TRUE(a.mask.empty());
  EXPECT_EQ(a.opacity, 1.0);
  EXPECT_EQ(a.mode, LayerMode::kOver);
  EXPECT_FALSE(a.angle_fade);
  EXPECT_EQ(a.visibility, LayerVisibility::kFirst);
  EXPECT_EQ(a.outside, LayerOutside::kTransparent);
  const LayerSpec& b = spec->layers[1];
  EXPECT_EQ(b.texture, fs::path("/abs/b.png"));
  EXPECT_EQ(b.mask, fs::path("/data/set/m/b.png"));
  EXPECT_EQ(b.opacity, 0.5);
  EXPECT_EQ(b.mode, LayerMode::kMultiply);
  ASSERT_TRUE(b.angle_fade);
  EXPECT_EQ((*b.angle_fade)[1], 80.0);
  EXPECT_EQ(b.visibility, LayerVisibility::kAll);
  EXPECT_EQ(b.outside, LayerOutside::kColor);
  EXPECT_FLOAT_EQ(b.outside_color[3], 0.5f);
  EXPECT_EQ(spec->layers[2].outside, LayerOutside::kClamp);
  EXPECT_EQ(spec->layers[2].mode, LayerMode::kReplace);

  spec = layers_from_json(std::string(R"({"layers":[{)") + kSphere + R"(,"texture":"a.png"}]})",
                          "/d", "L.json");
  ASSERT_TRUE(spec);
  EXPECT_EQ(spec->base, LayerBase::kNone);
  spec = layers_from_json(
      std::string(R"({"base":"mesh","layers":[{)") + kSphere + R"(,"texture":"a.png"}]})", "/d");
  ASSERT_TRUE(spec);
  EXPECT_EQ(spec->base, LayerBase::kMesh);
}

TEST(LayersJson, CamerasProxyFilesAndInlineCameras) {
  const fs::path dir =
      fs::temp_directory_path() /
      ("texbake_layers_json_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::create_directories(dir);
  std::ofstream(dir / "cam.json")
      << R"({"kind":"camera","model":"PINHOLE","width":64,"height":48,"params":[50,50,32,24],)"
         R"("pose":{"q_wxyz":[1,0,0,0],"t":[0,0,5]}})";
  std::ofstream(dir / "L.json") << R"({"layers":[{"proxy_file":"cam.json","texture":"photo.png"},)"
                                   R"({"cameras":"sparse/0","images":"photos","masks":"masks"}]})";
  Expected<LayersSpec> spec = read_layers_file(dir / "L.json");
  ASSERT_TRUE(spec) << spec.error().message;
  ASSERT_TRUE(spec->layers[0].projector);
  EXPECT_TRUE(std::holds_alternative<CameraProjector>(*spec->layers[0].projector));
  EXPECT_EQ(spec->layers[0].texture, dir / "photo.png");
  EXPECT_FALSE(spec->layers[1].projector);
  EXPECT_EQ(spec->layers[1].cameras, dir / "sparse/0");
  EXPECT_EQ(spec->layers[1].images, dir / "photos");
  EXPECT_EQ(spec->layers[1].masks, dir / "masks");
  EXPECT_TRUE(spec->layers[0].masks.empty());
  fs::remove_all(dir);
}

TEST(LayersJson, ErrorsNameTheFileAndTheKey) {
  const std::string s = kSphere;
  struct Case {
    std::string text, want;
  };
  const Case cases[] = {
      {R"({"layers":[]})", "L.json: key 'layers' must be a non-empty array"},
      {R"({"base":"nothing","layers":[{)" + s + R"(,"texture":"a"}]})", "L.json: base: must be"},
      {R"({"extra":1,"layers":[{)" + s + R"(,"texture":"a"}]})", "L.json: unknown key 'extra'"},
      {R"({"layers":[{)" + s + R"(,"texture":"a","colour":1}]})",
       "L.json: layers[0]: unknown key 'colour'"},
      {R"({"layers":[{"texture":"a"}]})", "L.json: layers[0]: needs a projector"},
      {R"({"layers":[{)" + s + R"(,"proxy_file":"p.json","texture":"a"}]})",
       "layers[0]: has more than one projector"},
      {R"({"layers":[{)" + s + R"(}]})", "L.json: layers[0]: missing key 'texture'"},
      {R"({"layers":[{)" + s + R"(,"texture":"a","opacity":1.5}]})",
       "L.json: layers[0].opacity: must be a number in [0, 1]"},
      {R"({"layers":[{)" + s + R"(,"texture":"a","mode":"screen"}]})",
       "L.json: layers[0].mode: must be one of \"over\", \"multiply\", \"add\", \"replace\""},
      {R"({"layers":[{)" + s + R"(,"texture":"a","angle_fade":[80,60]}]})",
       "layers[0].angle_fade: must satisfy 0 <= a0 < a1 <= 90"},
      {R"({"layers":[{)" + s + R"(,"texture":"a","visibility":true}]})",
       "layers[0].visibility: must be one of"},
      {R"({"layers":[{)" + s + R"(,"texture":"a","outside":[1,0,0]}]})",
       "layers[0].outside: must be a colour [r, g, b, a]"},
      {R"({"layers":[{)" + s + R"(,"texture":"a","images":"x"}]})",
       "layers[0].images: applies to a cameras layer only"},
      {R"({"layers":[{)" + s + R"(,"texture":"a","masks":"x"}]})",
       "layers[0].masks: applies to a cameras layer only (a proxy layer takes \"mask\")"},
      {R"({"layers":[{"cameras":"m","texture":"a"}]})",
       "layers[0].texture: does not apply to a cameras layer"},
      {R"({"layers":[{"cameras":"m","mask":"k.png"}]})",
       "L.json: layers[0].mask: does not apply to a cameras layer"},
      {R"({"layers":[{"cameras":"m","outside":"clamp"}]})",
       "L.json: layers[0].outside: a cameras layer is transparent where no photo sees"},
      {R"({"layers":[{"cameras":"m","outside":[1,0,0,1]}]})",
       "L.json: layers[0].outside: a cameras layer is transparent"},
      {R"({"layers":[{"cameras":"m","visibility":"all"}]})",
       "L.json: layers[0].visibility: a cameras layer always tests"},
      {R"({"layers":[{"proxy":{"kind":"sphere","radius":-1},"texture":"a"}]})",
       "L.json: layers[0].proxy"},
      {R"({"layers":[{"proxy_file":"/nonexistent/p.json","texture":"a"}]})", "/nonexistent/p.json"},
      {R"({"layers":[{)" + s + R"(,"texture":""}]})",
       "layers[0].texture: must be a non-empty path"},
  };
  for (const Case& c : cases) {
    Expected<LayersSpec> spec = layers_from_json(c.text, "/d", "L.json");
    ASSERT_FALSE(spec) << c.text;
    EXPECT_NE(spec.error().message.find(c.want), std::string::npos)
        << spec.error().message << "\n  wanted: " << c.want;
  }
}

TEST(LayersJson, DeepInlineProxiesAndHugeNumbersAreErrorsOfTheFile) {
  // An inline proxy nested 90,000 deep crashed (its value was printed back
  // to text for the proxy reader); now the file's parse stops at level 129:
  // root, "layers", the layer, "proxy" and 125 arrays of "center". Line 2
  // starts with `{"proxy":{"kind":"sphere","center":` (35 characters).
  const std::string deep =
      "{\"layers\":[\n{\"proxy\":{\"kind\":\"sphere\",\"center\":" + std::string(90000, '[');
  Expected<LayersSpec> spec = layers_from_json(deep, "/d", "L.json");
  ASSERT_FALSE(spec);
  EXPECT_EQ(spec.error().code, ErrorCode::kParse);
  EXPECT_EQ(spec.error().message,
            "L.json: key 'layers.proxy.center' nests deeper than 128 levels (line 2, column 160)");
  spec = layers_from_json(
      R"({"layers":[{)" + std::string(kSphere) + R"(,"texture":"a","opacity":1e999}]})", "/d",
      "L.json");
  ASSERT_FALSE(spec);
  EXPECT_EQ(
      spec.error().message.rfind(
          "L.json: key 'layers.opacity' holds a number that is not finite (1e999 at line 1", 0),
      0u)
      << spec.error().message;
}

}  // namespace
}  // namespace texbake
