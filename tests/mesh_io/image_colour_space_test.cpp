// image_io and colour spaces (issue #11): what read_image makes of the
// colour space OpenImageIO reports, the override, and write_image's encoding
// for the format and its tag. Files are written and read back straight
// through OpenImageIO (tests/mesh_io/colour_testing.h); expected values come
// from the IEC 61966-2-1 formula written out in the test helpers.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "mesh_io/image_io.h"
#include "tests/mesh_io/colour_testing.h"
#include "tests/mesh_io/test_files.h"

namespace texbake {
namespace {

namespace fs = std::filesystem;
using colour_testing::file_bytes;
using colour_testing::oiio_read;
using colour_testing::png_chunk_types;
using colour_testing::srgb_decode;
using colour_testing::write_constant;

// (128, 64, 255) / 255, sRGB-encoded, and the same colour in linear light:
// ((c + 0.055) / 1.055)^2.4 = 0.2158605, 0.0512695, 1.
const std::vector<double> kSrgb = {128 / 255.0, 64 / 255.0, 1.0};
const std::vector<double> kLinear = {srgb_decode(128 / 255.0), srgb_decode(64 / 255.0), 1.0};

bool has_chunk(const std::vector<std::string>& types, const std::string& t) {
  return std::find(types.begin(), types.end(), t) != types.end();
}

class ImageColourSpace : public ::testing::Test {
 protected:
  void SetUp() override { dir = test::fresh_temp_dir("colour"); }
  void TearDown() override { fs::remove_all(dir); }

  ColorSpace read_space(const fs::path& p, const ImageReadOptions& o = {}) {
    Expected<Image> img = read_image(p, o);
    EXPECT_TRUE(img) << p << ": " << (img ? "" : img.error().message);
    return img ? img->color_space : ColorSpace::kSrgb;
  }

  fs::path dir;
};

TEST(ColorSpaceFromAttributes, NamesAndGammasOpenImageIoUses) {
  struct Case {
    const char* name;
    float gamma;
    bool float_data;
    ColorSpace space;
    bool recognised;
  };
  const Case cases[] = {
      {"", 0, false, ColorSpace::kSrgb, true},   // untagged 8/16-bit
      {"", 0, true, ColorSpace::kLinear, true},  // untagged float (TIFF)
      {"sRGB", 0, true, ColorSpace::kSrgb, true},
      {"srgb_texture", 0, false, ColorSpace::kSrgb, true},  // OCIO 2 / OIIO 2.5 names
      {"Linear", 0, false, ColorSpace::kLinear, true},      // EXR; PNG tEXt
      {"linear", 0, false, ColorSpace::kLinear, true},      // HDR; PNG gAMA 1.0
      {"lin_srgb", 0, false, ColorSpace::kLinear, true},
      {"scene_linear", 0, false, ColorSpace::kLinear, true},
      {"Gamma1.0", 1.0f, false, ColorSpace::kLinear, true},
      {"Gamma2.2", 2.2f, true, ColorSpace::kSrgb, true},    // PNG gAMA 1/2.2
      {"Gamma1.5", 1.5f, false, ColorSpace::kSrgb, false},  // neither: by data type
      {"AdobeRGB", 0, true, ColorSpace::kLinear, false},
      {"ACEScg", 0, false, ColorSpace::kSrgb, false},
  };
  for (const Case& c : cases) {
    bool recognised = !c.recognised;
    EXPECT_EQ(color_space_from_attributes(c.name, c.gamma, c.float_data, &recognised), c.space)
        << c.name;
    EXPECT_EQ(recognised, c.recognised) << c.name;
  }
  EXPECT_STREQ(color_space_name(ColorSpace::kSrgb), "sRGB");
  EXPECT_STREQ(color_space_name(ColorSpace::kLinear), "Linear");
}

TEST_F(ImageColourSpace, FloatFilesAreLinearIntegerFilesSrgbTaggedFilesAsTagged) {
  const auto u8 = OIIO::TypeDesc::UINT8, u16 = OIIO::TypeDesc::UINT16;
  const auto half = OIIO::TypeDesc::HALF, f32 = OIIO::TypeDesc::FLOAT;
  ASSERT_TRUE(write_constant(dir / "plain.png", 2, 2, kSrgb, u8));
  ASSERT_TRUE(write_constant(dir / "plain16.png", 2, 2, kSrgb, u16));
  ASSERT_TRUE(write_constant(dir / "photo.jpg", 2, 2, kSrgb, u8));
  ASSERT_TRUE(write_constant(dir / "plain.exr", 2, 2, kLinear, half));
  ASSERT_TRUE(write_constant(dir / "plain.hdr", 2, 2, kLinear, f32));
  ASSERT_TRUE(write_constant(dir / "float.tif", 2, 2, kLinear, f32));
  ASSERT_TRUE(write_constant(dir / "plain16.tif", 2, 2, kSrgb, u16));
  ASSERT_TRUE(write_constant(dir / "linear16.png", 2, 2, kLinear, u16, "Linear"));
  ASSERT_TRUE(write_constant(dir / "srgb.tif", 2, 2, kSrgb, f32, "sRGB"));
  ASSERT_TRUE(write_constant(dir / "srgb.exr", 2, 2, kSrgb, half, "sRGB"));
  EXPECT_EQ(read_space(dir / "plain.png"), ColorSpace::kSrgb);
  EXPECT_EQ(read_space(dir / "plain16.png"), ColorSpace::kSrgb);
  EXPECT_EQ(read_space(dir / "photo.jpg"), ColorSpace::kSrgb);
  EXPECT_EQ(read_space(dir / "plain.exr"), ColorSpace::kLinear);
  EXPECT_EQ(read_space(dir / "plain.hdr"), ColorSpace::kLinear);
  EXPECT_EQ(read_space(dir / "float.tif"), ColorSpace::kLinear);  // no attribute: float
  EXPECT_EQ(read_space(dir / "plain16.tif"), ColorSpace::kSrgb);  // no attribute: integer
  EXPECT_EQ(read_space(dir / "linear16.png"), ColorSpace::kLinear);
  EXPECT_EQ(read_space(dir / "srgb.tif"), ColorSpace::kSrgb);  // float, tagged sRGB
  // OIIO 2.4 reads every EXR as "Linear" (its writer keeps no other name).
  EXPECT_EQ(oiio_read(dir / "srgb.exr").color_space, "Linear");
  EXPECT_EQ(read_space(dir / "srgb.exr"), ColorSpace::kLinear);

  // The tagged linear PNG keeps its stored values: 0.2158605 * 65535 = 14146.4.
  Expected<Image> lin = read_image(dir / "linear16.png");
  ASSERT_TRUE(lin);
  EXPECT_FLOAT_EQ(lin->pixels[0], 14146 / 65535.f);
  EXPECT_EQ(lin->view().color_space, ColorSpace::kLinear);
}

TEST_F(ImageColourSpace, PngGammaChunkAloneDecides) {
  // OIIO writes "Linear" as a gAMA of 1.0 plus a tEXt chunk; without the
  // tEXt, the gAMA chunk alone (OIIO reports "linear", gamma 1) decides.
  ASSERT_TRUE(write_constant(dir / "tagged.png", 2, 2, kLinear, OIIO::TypeDesc::UINT16, "Linear"));
  const std::string tagged = file_bytes(dir / "tagged.png");
  ASSERT_TRUE(has_chunk(png_chunk_types(tagged), "gAMA"));
  const std::string gama_only = colour_testing::png_without(tagged, "tEXt");
  ASSERT_FALSE(has_chunk(png_chunk_types(gama_only), "tEXt"));
  test::write_text(dir / "gama.png", gama_only);
  EXPECT_EQ(oiio_read(dir / "gama.png").color_space, "linear");
  EXPECT_EQ(read_space(dir / "gama.png"), ColorSpace::kLinear);
  // Without the gAMA chunk as well: a plain 16-bit PNG, sRGB.
  test::write_text(dir / "none.png", colour_testing::png_without(gama_only, "gAMA"));
  EXPECT_EQ(read_space(dir / "none.png"), ColorSpace::kSrgb);
}

TEST_F(ImageColourSpace, OverrideWinsAndKeepsTheValues) {
  ASSERT_TRUE(write_constant(dir / "a.png", 2, 2, kSrgb, OIIO::TypeDesc::UINT8));
  ASSERT_TRUE(write_constant(dir / "a.exr", 2, 2, kLinear, OIIO::TypeDesc::FLOAT));
  Expected<Image> png = read_image(dir / "a.png", {TextureColorSpace::kLinear});
  Expected<Image> exr = read_image(dir / "a.exr", {TextureColorSpace::kSrgb});
  ASSERT_TRUE(png && exr);
  EXPECT_EQ(png->color_space, ColorSpace::kLinear);
  EXPECT_EQ(exr->color_space, ColorSpace::kSrgb);
  EXPECT_FLOAT_EQ(png->pixels[0], 128 / 255.f);  // values as stored
  EXPECT_FLOAT_EQ(exr->pixels[0], static_cast<float>(kLinear[0]));
  EXPECT_EQ(read_space(dir / "a.png", {TextureColorSpace::kAuto}), ColorSpace::kSrgb);
  EXPECT_EQ(read_space(dir / "a.exr", {TextureColorSpace::kAuto}), ColorSpace::kLinear);
}

TEST_F(ImageColourSpace, UnrecognisedNameIsReadByDataTypeAndKept) {
  // OIIO keeps a PNG's name in a tEXt chunk.
  ASSERT_TRUE(write_constant(dir / "adobe.png", 1, 1, kSrgb, OIIO::TypeDesc::UINT8, "AdobeRGB"));
  ASSERT_EQ(oiio_read(dir / "adobe.png").color_space, "AdobeRGB");
  Expected<Image> img = read_image(dir / "adobe.png");
  ASSERT_TRUE(img);
  EXPECT_EQ(img->color_space, ColorSpace::kSrgb);  // 8-bit data
  EXPECT_EQ(img->unrecognised_color_space, "AdobeRGB");
  Expected<Image> forced = read_image(dir / "adobe.png", {TextureColorSpace::kLinear});
  ASSERT_TRUE(forced);
  EXPECT_TRUE(forced->unrecognised_color_space.empty());
}

// An sRGB-encoded 2 x 2 image of kSrgb (alpha 1).
Image srgb_image() {
  Image img;
  img.width = img.height = 2;
  for (int i = 0; i < 4; ++i) {
    for (double c : kSrgb) img.pixels.push_back(static_cast<float>(c));
    img.pixels.push_back(1.f);
  }
  return img;
}

TEST_F(ImageColourSpace, EncodeForFormatWritesExrLinearAndPngSrgbTagged) {
  ImageWriteOptions enc;
  enc.encode_for_format = true;
  Image srgb = srgb_image();
  ASSERT_TRUE(write_image(dir / "s.exr", srgb.view(), enc));
  ASSERT_TRUE(write_image(dir / "s.png", srgb.view(), enc));
  const colour_testing::OiioImage exr = oiio_read(dir / "s.exr");
  ASSERT_TRUE(exr.ok);
  EXPECT_EQ(exr.color_space, "Linear");
  ASSERT_EQ(exr.channels, 3);
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(exr.pixel(i)[c], kLinear[c], 1e-6) << i << "," << c;
  }
  const colour_testing::OiioImage png = oiio_read(dir / "s.png");
  ASSERT_TRUE(png.ok);
  EXPECT_EQ(png.color_space, "sRGB");
  EXPECT_FLOAT_EQ(png.pixel(3)[0], 128 / 255.f);
  EXPECT_FLOAT_EQ(png.pixel(3)[1], 64 / 255.f);
  // OIIO stores the tag as PNG's own sRGB chunk (+ gAMA, cHRM).
  EXPECT_TRUE(has_chunk(png_chunk_types(file_bytes(dir / "s.png")), "sRGB"));

  // A linear image into a PNG: sRGB-encoded on the way.
  Image lin = srgb_image();
  for (int i = 0; i < 4; ++i) {
    for (int c = 0; c < 3; ++c) lin.pixels[i * 4 + c] = static_cast<float>(kLinear[c]);
  }
  lin.color_space = ColorSpace::kLinear;
  ASSERT_TRUE(write_image(dir / "l.png", lin.view(), enc));
  const colour_testing::OiioImage lpng = oiio_read(dir / "l.png");
  ASSERT_TRUE(lpng.ok);
  EXPECT_EQ(lpng.color_space, "sRGB");
  EXPECT_FLOAT_EQ(lpng.pixel(0)[0], 128 / 255.f);
  EXPECT_FLOAT_EQ(lpng.pixel(0)[1], 64 / 255.f);
  EXPECT_FLOAT_EQ(lpng.pixel(0)[2], 1.f);
  // ... and into an EXR as it is.
  ASSERT_TRUE(write_image(dir / "l.exr", lin.view(), enc));
  EXPECT_FLOAT_EQ(oiio_read(dir / "l.exr").pixel(0)[0], static_cast<float>(kLinear[0]));
}

TEST_F(ImageColourSpace, WithoutEncodingValuesAreWrittenAsGivenAndTaggedAsTheyAre) {
  Image srgb = srgb_image();
  ImageWriteOptions f;
  f.bit_depth = ImageBitDepth::kFloat;
  ASSERT_TRUE(write_image(dir / "s.tif", srgb.view(), f));
  const colour_testing::OiioImage tif = oiio_read(dir / "s.tif");
  EXPECT_EQ(tif.color_space, "sRGB");
  EXPECT_FLOAT_EQ(tif.pixel(0)[0], 128 / 255.f);
  EXPECT_EQ(read_space(dir / "s.tif"), ColorSpace::kSrgb);  // read back as written
  // An EXR gets the numbers as given too, but OIIO 2.4 reads any EXR as
  // linear: only encode_for_format makes an sRGB image a correct EXR.
  ASSERT_TRUE(write_image(dir / "s.exr", srgb.view()));
  EXPECT_FLOAT_EQ(oiio_read(dir / "s.exr").pixel(0)[0], 128 / 255.f);
}

TEST_F(ImageColourSpace, UntaggedPngHasNoColourChunks) {
  // For GLB: glTF-Validator warns about gAMA / sRGB / cHRM / iCCP.
  ImageWriteOptions o;
  o.encode_for_format = true;
  o.tag_color_space = false;
  Image srgb = srgb_image();
  Expected<std::vector<unsigned char>> bytes = encode_image(srgb.view(), ".png", o);
  ASSERT_TRUE(bytes);
  const std::vector<std::string> types = png_chunk_types(std::string(bytes->begin(), bytes->end()));
  ASSERT_FALSE(types.empty());
  for (const char* t : {"gAMA", "sRGB", "cHRM", "iCCP", "tEXt"}) {
    EXPECT_FALSE(has_chunk(types, t)) << t;
  }
  o.tag_color_space = true;
  bytes = encode_image(srgb.view(), ".png", o);
  ASSERT_TRUE(bytes);
  EXPECT_TRUE(has_chunk(png_chunk_types(std::string(bytes->begin(), bytes->end())), "sRGB"));
}

}  // namespace
}  // namespace texbake
