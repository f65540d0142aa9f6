// Helpers for the colour-space tests (issue #11), shared by tests/mesh_io and
// tests/cli: the sRGB transfer curves written out from IEC 61966-2-1 in
// double (independent of mapping/sample.h), images written and read straight
// through OpenImageIO (not texbake's image_io), and a PNG chunk lister.
// Header-only; the test binaries glob only *.cpp.
#pragma once

#include <OpenImageIO/imageio.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace texbake::colour_testing {

// IEC 61966-2-1: decode (sRGB-encoded -> linear) and encode.
inline double srgb_decode(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}
inline double srgb_encode(double l) {
  return l <= 0.0031308 ? l * 12.92 : 1.055 * std::pow(l, 1 / 2.4) - 0.055;
}

// A w x h image of one RGB colour written by OpenImageIO in `type` (UINT8,
// UINT16, HALF, FLOAT: integer types take `rgb` in [0, 1] and round), with
// "oiio:ColorSpace" = `color_space` unless empty. False on failure.
inline bool write_constant(const std::filesystem::path& path, int w, int h,
                           const std::vector<double>& rgb, OIIO::TypeDesc type,
                           const std::string& color_space = "") {
  auto out = OIIO::ImageOutput::create(path.string());
  if (!out) return false;
  OIIO::ImageSpec spec(w, h, 3, type);
  if (!color_space.empty()) spec.attribute("oiio:ColorSpace", color_space);
  if (!out->open(path.string(), spec)) return false;
  std::vector<float> pixels;
  for (int i = 0; i < w * h; ++i) {
    for (double c : rgb) pixels.push_back(static_cast<float>(c));
  }
  // OIIO converts float to the file's type (integers: scaled, rounded).
  const bool ok = out->write_image(OIIO::TypeDesc::FLOAT, pixels.data());
  return out->close() && ok;
}

// What OpenImageIO reads from a file: its pixels as float (channels as
// stored), channel count, size and "oiio:ColorSpace".
struct OiioImage {
  int width = 0, height = 0, channels = 0;
  std::vector<float> pixels;
  std::string color_space;
  bool ok = false;
  const float* pixel(int i) const { return pixels.data() + static_cast<std::size_t>(i) * channels; }
};
inline OiioImage oiio_read(const std::filesystem::path& path) {
  OiioImage img;
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) return img;
  const OIIO::ImageSpec& spec = in->spec();
  img.width = spec.width;
  img.height = spec.height;
  img.channels = spec.nchannels;
  img.color_space = spec.get_string_attribute("oiio:ColorSpace");
  img.pixels.resize(static_cast<std::size_t>(spec.width) * spec.height * spec.nchannels);
  img.ok = in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, img.pixels.data());
  in->close();
  return img;
}

// The chunk types of a PNG file's bytes, in order ({} if not a PNG).
inline std::vector<std::string> png_chunk_types(const std::string& bytes) {
  std::vector<std::string> types;
  if (bytes.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)) != 0) return types;
  for (std::size_t at = 8; at + 12 <= bytes.size();) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at);
    const uint32_t length =
        (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
    types.push_back(bytes.substr(at + 4, 4));
    at += 12 + static_cast<std::size_t>(length);
  }
  return types;
}

// The PNG without its chunks of type `drop` (the others keep their bytes
// and CRCs).
inline std::string png_without(const std::string& bytes, const std::string& drop) {
  std::string out = bytes.substr(0, 8);
  for (std::size_t at = 8; at + 12 <= bytes.size();) {
    const auto* p = reinterpret_cast<const unsigned char*>(bytes.data() + at);
    const uint32_t length =
        (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
    if (bytes.substr(at + 4, 4) != drop) out += bytes.substr(at, 12 + length);
    at += 12 + static_cast<std::size_t>(length);
  }
  return out;
}

inline std::string file_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace texbake::colour_testing
