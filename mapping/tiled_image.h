// Texels kept outside memory (issue #16, SPEC section 13): an image larger
// than the memory budget is not decoded whole but read a tile at a time from
// a TileSource (mesh_io's OpenImageIO ImageCache). An ImageView with `tiles`
// set and no `data` reads its texels through ImageView::texel(), which keeps
// a small direct-mapped cache of decoded RGBA float tiles per thread, so the
// per-sample path is an index computation and a tag compare; the source's
// (virtual) read runs once per tile miss, never per sample.
//
// Bit-identity with the in-memory path: a TileSource gives exactly the
// values the in-memory reader would have put in those pixels (the same
// conversion to float RGBA, the same NaN rule), and the linearised working
// image of --linear is the same srgb_to_linear applied as a tile is loaded
// (ImageView::decode_srgb) instead of to a whole copy. So every lookup
// (bilinear, area, EWA) gives the same bits both ways.
//
// Standard C++ only.
#pragma once

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/sample.h"

namespace texbake {

class TileSource {
 public:
  // Side of the square tiles of the per-thread cache, in texels, and of the
  // square window of tiles it holds (direct-mapped: tile (tx, ty) lives in
  // slot (tx mod kCacheWindow, ty mod kCacheWindow)). 32 x 32 tiles in a
  // 16 x 16 window (512 x 512 texels, 4 MiB): a miss converts a quarter of
  // what a 64 x 64 tile would, which made the atlas's sampling through the
  // cache 2 to 3 times faster with the same bytes (bench/large_images).
  static constexpr int kTileSize = 32;
  static constexpr int kCacheWindow = 16;

  TileSource();
  virtual ~TileSource() = default;
  TileSource(const TileSource&) = delete;
  TileSource& operator=(const TileSource&) = delete;

  // Reads the texels [x0, x0 + w) x [y0, y0 + h) (inside the image) as RGBA
  // floats into `rgba`, rows `stride` texels apart, each through
  // transform_texel(texel, decode_srgb, premultiply). False when the file
  // cannot give them (the texels are then 0): the source keeps the first
  // error (failed()). Thread-safe.
  virtual bool read(int x0, int y0, int w, int h, int stride, bool decode_srgb, bool premultiply,
                    float* rgba) const = 0;

  // Whether some read failed, and the first failure's message (naming the file).
  bool failed() const { return failed_.load(std::memory_order_acquire); }
  std::string error() const;

  // Never reused by another source in the same process: keys the per-thread caches.
  std::uint64_t serial() const { return serial_; }

 protected:
  void set_error(const std::string& message) const;

 private:
  std::uint64_t serial_;
  mutable std::atomic<bool> failed_{false};
  mutable std::mutex error_mutex_;
  mutable std::string error_;
};

// The one per-texel transform of a tiled view (ImageView::decode_srgb,
// premultiply), and of the copies it stands for (shade's working image,
// a layer's premultiplied texture), so both give the same bits.
inline void transform_texel(float* rgba, bool decode_srgb, bool premultiply) {
  for (int k = 0; k < 3; ++k) {
    const float c = decode_srgb ? srgb_to_linear(rgba[k]) : rgba[k];
    rgba[k] = premultiply ? c * rgba[3] : c;
  }
}

// The bytes of the per-thread tile cache (each thread that reads a tiled
// image holds one, for as long as the thread lives): counted in the budget.
std::size_t tile_cache_bytes_per_thread();

// Rows [y0, y1) of `image` (in memory or tiled) as RGBA floats into `rgba`
// (width * (y1 - y0) * 4 floats), bypassing the per-thread cache: the bulk
// reads of a pass over the whole image (MIP levels, the image mean).
// False when a tiled source fails (its error() says why).
bool read_rows(const ImageView& image, int y0, int y1, float* rgba);

// After a pass over `image`: kParse with the source's message (naming the
// file) when a tiled image's reads failed, its own or those of its MIP
// levels (ImageView::mip_levels), else ok. In-memory views: ok.
Status check_texels_read(const ImageView& image);

namespace detail {
// ImageView::texel() of a tiled view.
Rgba tiled_texel(const ImageView& image, int x, int y);
}  // namespace detail

}  // namespace texbake
