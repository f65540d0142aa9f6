// The per-thread tile cache behind ImageView::texel() (mapping/tiled_image.h).
#include "mapping/tiled_image.h"

#include <algorithm>
#include <cstring>
#include <memory>

namespace texbake {

namespace {

constexpr int kTile = TileSource::kTileSize;
constexpr int kTileShift = 5;
static_assert(kTile == 1 << kTileShift);
// Direct-mapped: the kWindow x kWindow tiles around any point are resident
// together, and the up to four tiles of one bilinear lookup never evict each
// other (neighbouring tiles fall in different slots, but for a periodic fold
// from the last column to the first: then at worst one tile is read twice).
constexpr int kWindow = TileSource::kCacheWindow;
constexpr int kWindowShift = 4;
static_assert(kWindow == 1 << kWindowShift);
constexpr int kSlots = kWindow * kWindow;
constexpr std::size_t kTileFloats = static_cast<std::size_t>(kTile) * kTile * 4;

struct Slot {
  std::uint64_t key = 0;  // source serial * 4 + decode_srgb + 2 premultiply; 0: empty
  int tx = -1, ty = -1;
};

struct ThreadTiles {
  Slot slots[kSlots];
  std::unique_ptr<float[]> data;  // kSlots tiles, allocated on first use
};

thread_local ThreadTiles t_tiles;

std::atomic<std::uint64_t> g_next_serial{1};

}  // namespace

TileSource::TileSource() : serial_(g_next_serial.fetch_add(1, std::memory_order_relaxed)) {}

std::string TileSource::error() const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  return error_;
}

void TileSource::set_error(const std::string& message) const {
  std::lock_guard<std::mutex> lock(error_mutex_);
  if (error_.empty()) error_ = message;
  failed_.store(true, std::memory_order_release);
}

std::size_t tile_cache_bytes_per_thread() {
  return kSlots * kTileFloats * sizeof(float);
}

bool read_rows(const ImageView& image, int y0, int y1, float* rgba) {
  if (y1 <= y0) return true;
  if (image.data) {
    std::memcpy(rgba, image.pixel(0, y0),
                static_cast<std::size_t>(image.width) * (y1 - y0) * 4 * sizeof(float));
    return true;
  }
  return image.tiles->read(0, y0, image.width, y1 - y0, image.width, image.decode_srgb,
                           image.premultiply, rgba);
}

Status check_texels_read(const ImageView& image) {
  for (int i = 0; i < image.mip_level_count; ++i) {
    if (Status s = check_texels_read(image.mip_levels[i]); !s) return s;
  }
  if (image.data || !image.tiles || !image.tiles->failed()) return ok_status();
  return make_error(ErrorCode::kParse, image.tiles->error());
}

namespace detail {

std::array<float, 4> tiled_texel(const ImageView& image, int x, int y) {
  ThreadTiles& cache = t_tiles;
  if (!cache.data) cache.data = std::make_unique<float[]>(kSlots * kTileFloats);
  const int tx = x >> kTileShift, ty = y >> kTileShift;
  const int s = (tx & (kWindow - 1)) | ((ty & (kWindow - 1)) << kWindowShift);
  Slot& slot = cache.slots[s];
  float* tile = cache.data.get() + static_cast<std::size_t>(s) * kTileFloats;
  const std::uint64_t key =
      image.tiles->serial() * 4 + (image.decode_srgb ? 1 : 0) + (image.premultiply ? 2 : 0);
  if (slot.key != key || slot.tx != tx || slot.ty != ty) {
    const int x0 = tx << kTileShift, y0 = ty << kTileShift;
    // A failed read leaves zeros and the source's error, which the bake
    // reports after its pass (never a crash mid-pass).
    image.tiles->read(x0, y0, std::min(kTile, image.width - x0), std::min(kTile, image.height - y0),
                      kTile, image.decode_srgb, image.premultiply, tile);
    slot = {key, tx, ty};
  }
  const float* p = tile + ((static_cast<std::size_t>(y & (kTile - 1)) << kTileShift) +
                           static_cast<std::size_t>(x & (kTile - 1))) *
                              4;
  return {p[0], p[1], p[2], p[3]};
}

}  // namespace detail

}  // namespace texbake
