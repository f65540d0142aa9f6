// A baseline TIFF written byte by byte (TIFF 6.0, little-endian, tiled, RGB
// 8-bit, uncompressed): header, the one IFD, then the tiles, so a test can
// make a file lie about its size or lose a tile without libtiff correcting
// it. Header-only; for the image-cache tests (issue #16).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace texbake::test {

struct TiffLayout {
  int width = 0, height = 0;  // declared in the header
  int tile = 64;              // tile side (a multiple of 16)
  // Tiles whose offset points past the end of the file (their data is left out).
  std::vector<int> missing_tiles;
  bool no_data = false;  // every tile past the end (a lying header)
};

inline std::string le16(uint16_t v) {
  return {char(v & 255), char(v >> 8)};
}
inline std::string le32(uint32_t v) {
  return {char(v & 255), char((v >> 8) & 255), char((v >> 16) & 255), char(v >> 24)};
}

// `rgb(x, y, c)` gives the byte of channel c at (x, y) inside the image.
template <class Rgb>
std::string tiled_tiff(const TiffLayout& t, Rgb rgb) {
  const int tx = (t.width + t.tile - 1) / t.tile, ty = (t.height + t.tile - 1) / t.tile;
  const uint32_t n = static_cast<uint32_t>(tx) * ty;
  const uint32_t tile_bytes = static_cast<uint32_t>(t.tile) * t.tile * 3;
  const int entries = 11;
  const uint32_t ifd = 8, bps = ifd + 2 + entries * 12 + 4, offsets = bps + 6,
                 counts = offsets + 4 * n, data = counts + 4 * n;
  auto entry = [](uint16_t tag, uint16_t type, uint32_t count, uint32_t value) {
    return le16(tag) + le16(type) + le32(count) + le32(value);
  };
  constexpr uint16_t kShort = 3, kLong = 4;
  std::string out = "II" + le16(42) + le32(ifd) + le16(entries);
  out += entry(256, kLong, 1, t.width);
  out += entry(257, kLong, 1, t.height);
  out += entry(258, kShort, 3, bps);
  out += entry(259, kShort, 1, 1);  // no compression
  out += entry(262, kShort, 1, 2);  // RGB
  out += entry(277, kShort, 1, 3);
  out += entry(284, kShort, 1, 1);  // chunky
  out += entry(322, kLong, 1, t.tile);
  out += entry(323, kLong, 1, t.tile);
  out += entry(324, kLong, n, offsets);
  out += entry(325, kLong, n, counts);
  out += le32(0);
  out += le16(8) + le16(8) + le16(8);
  std::vector<bool> missing(n, t.no_data);
  for (int m : t.missing_tiles) missing[static_cast<std::size_t>(m)] = true;
  uint32_t present = 0;
  for (uint32_t i = 0; i < n; ++i) present += missing[i] ? 0 : 1;
  const uint32_t end = data + present * tile_bytes;
  uint32_t next = data;
  for (uint32_t i = 0; i < n; ++i) {
    out += le32(missing[i] ? end + 4096 + i : next);
    if (!missing[i]) next += tile_bytes;
  }
  for (uint32_t i = 0; i < n; ++i) out += le32(tile_bytes);
  for (uint32_t i = 0; i < n; ++i) {
    if (missing[i]) continue;
    const int x0 = static_cast<int>(i % tx) * t.tile, y0 = static_cast<int>(i / tx) * t.tile;
    for (int y = y0; y < y0 + t.tile; ++y) {
      for (int x = x0; x < x0 + t.tile; ++x) {
        for (int c = 0; c < 3; ++c) {
          out += (x < t.width && y < t.height) ? static_cast<char>(rgb(x, y, c)) : '\0';
        }
      }
    }
  }
  return out;
}

}  // namespace texbake::test
