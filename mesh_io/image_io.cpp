// OpenImageIO <-> Image. The only file that includes OIIO.
#include "mesh_io/image_io.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imagecache.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <thread>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "mapping/sample.h"
#include "mapping/tiled_image.h"
#include "mesh_io/atomic_file.h"
#include "mesh_io/regular_file.h"

namespace texbake {
namespace fs = std::filesystem;

namespace {

// Above the largest ratio of decoded to stored bytes that PNG's deflate
// (1032:1) and baseline JPEG (about 768:1 for a constant colour image) can
// reach.
constexpr long long kMaxCompressionRatio = 1100;

Error image_error(ErrorCode code, const fs::path& path, const std::string& what) {
  return make_error(code, path.string() + ": " + what);
}

// OIIO error text can hold several lines; keep the first, trimmed.
std::string first_line(std::string s) {
  const auto nl = s.find('\n');
  if (nl != std::string::npos) s.resize(nl);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  return s.empty() ? std::string("unknown OpenImageIO error") : s;
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

ColorSpace color_space_from_attributes(const std::string& name, float gamma, bool float_data,
                                       bool* recognised) {
  const ColorSpace by_type = float_data ? ColorSpace::kLinear : ColorSpace::kSrgb;
  if (recognised) *recognised = true;
  if (name.empty()) return by_type;
  const std::string n = lower(name);
  if (n.find("linear") != std::string::npos || n == "lin" || n.rfind("lin_", 0) == 0) {
    return ColorSpace::kLinear;
  }
  if (n.rfind("srgb", 0) == 0) return ColorSpace::kSrgb;
  // OIIO 2.4 names a PNG's or TIFF's gAMA "GammaX.Y" (or "GammaCorrected")
  // with the exponent in oiio:Gamma.
  if (n.rfind("gamma", 0) == 0) {
    if (std::abs(gamma - 1.f) < 0.01f) return ColorSpace::kLinear;
    if (gamma >= 1.8f && gamma <= 2.6f) return ColorSpace::kSrgb;
  }
  if (recognised) *recognised = false;
  return by_type;
}

const char* color_space_name(ColorSpace space) {
  return space == ColorSpace::kLinear ? "Linear" : "sRGB";
}

Status check_image_size(long long width, long long height, int channels) {
  if (width <= 0 || height <= 0 || channels <= 0) {
    return make_error(ErrorCode::kParse,
                      "has " + std::to_string(width) + " x " + std::to_string(height) +
                          " pixels and " + std::to_string(channels) + " channels: no image to use");
  }
  // Compare without overflow: width, height < 2^31 from OIIO's int spec.
  if (width > kMaxImagePixels / height) {
    return make_error(ErrorCode::kParse, std::to_string(width) + " x " + std::to_string(height) +
                                             " pixels is larger than texbake reads (" +
                                             std::to_string(kMaxImagePixels) +
                                             " pixels, e.g. 16384 x 16384)");
  }
  if (width * height > kMaxImageValues / channels) {
    return make_error(ErrorCode::kParse,
                      std::to_string(width) + " x " + std::to_string(height) + " pixels of " +
                          std::to_string(channels) + " channels is more than texbake decodes (" +
                          std::to_string(kMaxImageValues) + " values, 16384 x 16384 x 4)");
  }
  return ok_status();
}

namespace {

// The file's channels (nc values at src) as RGBA at d (SPEC section 1 and
// the header's table); NaN or infinity would poison every interpolation
// that touches the texel (0 x inf is NaN): read as 0. Returns how many.
// The one conversion of both the in-memory and the cached reader, so both
// give the same bits.
inline int to_rgba(const float* src, int nc, int alpha, float* d) {
  if (nc < 3) {
    d[0] = d[1] = d[2] = src[0];
  } else {
    d[0] = src[0];
    d[1] = src[1];
    d[2] = src[2];
  }
  d[3] = alpha >= 0 ? src[alpha] : 1.f;
  int nonfinite = 0;
  for (int k = 0; k < 4; ++k) {
    if (!std::isfinite(d[k])) {
      d[k] = 0.f;
      ++nonfinite;
    }
  }
  return nonfinite;
}

// The channel read as alpha: grey + alpha, RGBA, or OIIO's alpha channel
// past the first three; -1 for none.
int alpha_channel(const OIIO::ImageSpec& spec) {
  const int nc = spec.nchannels;
  return nc == 2 ? 1 : nc == 4 ? 3 : (spec.alpha_channel >= 3 ? spec.alpha_channel : -1);
}

// Image::color_space (and unrecognised_color_space) from the header's
// attributes, or the override.
void set_color_space(const OIIO::ImageSpec& spec, const ImageReadOptions& options, Image& img) {
  if (options.color_space == TextureColorSpace::kAuto) {
    const std::string name = spec.get_string_attribute("oiio:ColorSpace");
    bool recognised = true;
    img.color_space = color_space_from_attributes(name, spec.get_float_attribute("oiio:Gamma", 0.f),
                                                  spec.format.is_floating_point(), &recognised);
    if (!recognised) img.unrecognised_color_space = name;
  } else {
    img.color_space =
        options.color_space == TextureColorSpace::kLinear ? ColorSpace::kLinear : ColorSpace::kSrgb;
  }
}

// The checks on a header before any pixel is decoded or allocated: a 2D
// image, with pixels and channels, within the size limits when it is to be
// decoded whole (`whole`), and no larger than its file can hold.
Status check_header(const OIIO::ImageSpec& spec, const std::string& format, long long stored_bytes,
                    const fs::path& path, bool whole) {
  const long long w = spec.width, h = spec.height;
  if (spec.depth > 1 || spec.deep) {
    return image_error(ErrorCode::kParse, path, "is a volume or deep image: no 2D image to use");
  }
  // An image without pixels is refused either way; the size limits hold
  // for a whole decode only (a cached image is read a tile at a time).
  if (whole || w <= 0 || h <= 0 || spec.nchannels <= 0) {
    if (Status s = check_image_size(w, h, spec.nchannels); !s) {
      return image_error(ErrorCode::kParse, path, s.error().message);
    }
  }
  // PNG (deflate) and JPEG cannot compress by more than about 1032:1 and
  // 768:1 (a constant image): a file that small cannot hold its declared size.
  if (format == "png" || format == "jpeg") {
    const long long raw = w * h * spec.nchannels * static_cast<long long>(spec.format.size());
    if (raw / kMaxCompressionRatio > stored_bytes) {
      return image_error(ErrorCode::kParse, path,
                         "declares " + std::to_string(w) + " x " + std::to_string(h) +
                             " pixels, more than a " + std::to_string(stored_bytes) + "-byte " +
                             format + " file can hold (truncated or lying header)");
    }
  }
  return ok_status();
}

// The sizes of MIP levels 1 .. of the opened image (empty for a plain
// image): used only when they are the chain MipPyramid expects (each side
// max(1, floor(previous / 2)), down to 1 x 1, the channels of level 0), as
// maketx and OpenImageIO's MIP-map writers make them; otherwise the file's
// levels are ignored and the bake reduces level 0 itself.
std::vector<std::pair<int, int>> mip_chain(OIIO::ImageInput& in) {
  std::vector<std::pair<int, int>> sizes;
  const int channels = in.spec().nchannels;
  int w = in.spec().width, h = in.spec().height;
  for (int level = 1; (w > 1 || h > 1) && in.seek_subimage(0, level); ++level) {
    const OIIO::ImageSpec& spec = in.spec();
    w = std::max(1, w / 2);
    h = std::max(1, h / 2);
    if (spec.width != w || spec.height != h || spec.nchannels != channels) {
      sizes.clear();
      break;
    }
    sizes.emplace_back(w, h);
  }
  if (w > 1 || h > 1) sizes.clear();           // the chain stops short of 1 x 1
  (void)in.geterror();                         // a failed seek past the last level is not an error
  if (!in.seek_subimage(0, 0)) sizes.clear();  // read_image then fails on level 0
  return sizes;
}

// Decodes MIP level `miplevel` of the opened image `in` (a file or an
// in-memory proxy of `stored_bytes` bytes); `path` names it in errors.
Expected<Image> decode_image(OIIO::ImageInput* in, const fs::path& path, long long stored_bytes,
                             const ImageReadOptions& options, int miplevel = 0) {
  if (!in->seek_subimage(0, miplevel)) {
    return image_error(
        ErrorCode::kParse, path,
        "cannot read MIP level " + std::to_string(miplevel) + ": " + first_line(in->geterror()));
  }
  const OIIO::ImageSpec spec = in->spec();
  const long long w = spec.width, h = spec.height;
  if (Status s = check_header(spec, in->format_name(), stored_bytes, path, true); !s) {
    return s.error();
  }
  const int nc = spec.nchannels;
  const int alpha = alpha_channel(spec);
  // Decoded in bands of rows (a band is one tile row for tiled files), each
  // converted to RGBA at once: the decoded values of the whole image are
  // never held beside the result. The result is allocated only once the
  // first band has decoded, so a small file whose header claims a huge size
  // fails before texbake allocates for it (issue #12).
  const int band_rows =
      static_cast<int>(std::clamp<long long>(spec.tile_height > 0 ? spec.tile_height : 64, 1, h));
  std::vector<float> band;
  Image img;
  std::size_t nonfinite = 0;
  auto decode_error = [&](const std::string& why) {
    return image_error(ErrorCode::kParse, path, "cannot decode (truncated or corrupt?): " + why);
  };
  try {
    band.resize(static_cast<std::size_t>(w) * band_rows * nc);
    for (long long y0 = 0; y0 < h; y0 += band_rows) {
      const long long y1 = std::min<long long>(h, y0 + band_rows);
      // Reads into float: OIIO scales integer formats to [0, 1] (uint8 / 255,
      // uint16 / 65535) and keeps float values.
      const bool ok =
          spec.tile_width > 0
              ? in->read_tiles(0, miplevel, spec.x, spec.x + static_cast<int>(w),
                               spec.y + static_cast<int>(y0), spec.y + static_cast<int>(y1), spec.z,
                               spec.z + 1, 0, nc, OIIO::TypeDesc::FLOAT, band.data())
              : in->read_scanlines(0, miplevel, spec.y + static_cast<int>(y0),
                                   spec.y + static_cast<int>(y1), spec.z, 0, nc,
                                   OIIO::TypeDesc::FLOAT, band.data());
      // libjpeg and friends report some damage only as a warning-level
      // error that leaves the read true; treat any pending error as failure.
      if (!ok || in->has_error()) return decode_error(first_line(in->geterror()));
      if (y0 == 0) {
        img.width = static_cast<int>(w);
        img.height = static_cast<int>(h);
        img.pixels.resize(static_cast<std::size_t>(w * h) * 4);
        img.has_alpha = alpha >= 0;
      }
      const std::size_t first = static_cast<std::size_t>(y0 * w);
      const std::size_t n = static_cast<std::size_t>((y1 - y0) * w);
      for (std::size_t i = 0; i < n; ++i) {
        nonfinite += to_rgba(&band[i * nc], nc, alpha, &img.pixels[(first + i) * 4]);
      }
    }
  } catch (const std::bad_alloc&) {
    return image_error(ErrorCode::kIo, path,
                       "not enough memory to decode " + std::to_string(w) + " x " +
                           std::to_string(h) + " pixels (" + std::to_string((w * h * 16) >> 20) +
                           " MiB as float RGBA)");
  }
  img.nonfinite_values = nonfinite;
  set_color_space(spec, options, img);
  return img;
}

// Keep the stored values (SPEC section 1): without this OIIO premultiplies
// colour by alpha when it reads PNG, GIF and other unassociated formats.
OIIO::ImageSpec read_config() {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  return config;
}

// The file name extension OIIO picks its reader by for an embedded image:
// from the MIME type, else from the first bytes (PNG, JPEG signatures).
std::string memory_image_extension(const unsigned char* data, std::size_t size,
                                   const std::string& mime_type) {
  const std::string m = lower(mime_type);
  if (m == "image/png") return ".png";
  if (m == "image/jpeg" || m == "image/jpg") return ".jpg";
  if (m == "image/webp") return ".webp";
  if (m == "image/bmp") return ".bmp";
  if (m == "image/gif") return ".gif";
  if (m == "image/tiff") return ".tif";
  static const unsigned char kPng[4] = {0x89, 'P', 'N', 'G'};
  if (size >= 4 && std::equal(kPng, kPng + 4, data)) return ".png";
  if (size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF) return ".jpg";
  return "";
}

// A private OpenImageIO ImageCache holding at most its share of the budget
// (ImageReadOptions::cache_mb) of one file's tiles, in the file's own data
// type (untiled files are read in 64 x 64 tiles, "autotile"); shared by the
// CachedImage of each of the file's MIP levels.
class CacheFile {
 public:
  static constexpr int kAutotile = 64;

  CacheFile(const fs::path& path, float max_memory_mb)
      : cache_(OIIO::ImageCache::create(/*shared=*/false)),
        trim_bytes_(static_cast<double>(max_memory_mb) * (1 << 20) / kTrimsPerCache) {
    cache_->attribute("max_memory_MB", max_memory_mb);
    cache_->attribute("autotile", kAutotile);
    cache_->attribute("unassociatedalpha", 1);  // the stored values, as read_config()
    cache_->attribute("deduplicate", 0);
    handle_ = cache_->get_image_handle(OIIO::ustring(path.string()), perthread());
    if (const OIIO::ImageSpec* s = spec(0)) {
      const bool tiled = s->tile_width > 0 && s->tile_height > 0;
      tile_bytes_ = static_cast<long long>(tiled ? s->tile_width : kAutotile) *
                    (tiled ? s->tile_height : kAutotile) * static_cast<long long>(s->pixel_bytes());
    }
  }
  ~CacheFile() {
    for (auto& [thread, info] : perthread_) cache_->destroy_thread_info(info);
    OIIO::ImageCache::destroy(cache_, /*teardown=*/true);
  }
  CacheFile(const CacheFile&) = delete;
  CacheFile& operator=(const CacheFile&) = delete;

  // Level `miplevel`'s header as the cache sees it (null, with error(),
  // when it cannot open the file or has no such level).
  const OIIO::ImageSpec* spec(int miplevel) const {
    return handle_ ? cache_->imagespec(handle_, perthread(), 0, miplevel) : nullptr;
  }
  std::string error() const { return first_line(cache_->geterror()); }
  bool get_pixels(int miplevel, int x0, int x1, int y0, int y1, int z, int nc,
                  float* values) const {
    const bool ok = handle_ && cache_->get_pixels(handle_, perthread(), 0, miplevel, x0, x1, y0, y1,
                                                  z, z + 1, 0, nc, OIIO::TypeDesc::FLOAT, values);
    release_evicted_tiles();
    return ok;
  }

 private:
  // How often the evicted tiles' memory is handed back: each time the cache
  // has read a tenth of its size anew.
  static constexpr double kTrimsPerCache = 10;

  // The cache frees the tiles it evicts, but glibc's allocator keeps a
  // freed block in the arena of the thread that allocated it (one arena a
  // thread, up to 8 a core), where only that thread's next allocations
  // reuse it; with two threads reading tiles, freed tiles piled up in the
  // worker's arena (a 24 MB heap holding 24 kB in use at the end of a
  // --cache-mb 64 bake), so the image's share of the peak passed the budget
  // (bench/large_images at --cache-mb 512: 43 MB more than with
  // MALLOC_ARENA_MAX=1). malloc_trim hands the free pages of every arena
  // back to the system, so no more than a tenth of the cache's size is
  // freed and still resident; the process's allocator settings (a
  // library's caller's) are left as they are.
  void release_evicted_tiles() const {
#if defined(__GLIBC__)
    int created = 0;
    if (!cache_->getattribute("stat:tiles_created", OIIO::TypeDesc::INT, &created)) return;
    const long long read = static_cast<long long>(created) * tile_bytes_;
    if (read - trimmed_at_.load(std::memory_order_relaxed) < trim_bytes_) return;
    std::unique_lock<std::mutex> lock(trim_mutex_, std::try_to_lock);
    if (!lock || read - trimmed_at_.load(std::memory_order_relaxed) < trim_bytes_) return;
    trimmed_at_.store(read, std::memory_order_relaxed);
    malloc_trim(0);
#endif
  }

  // The calling thread's record of the cache (ImageCache's "Perthread"),
  // made here and destroyed with the cache: the app-managed option of
  // imagecache.h. With OIIO's own (get_perthread_info()) each thread's
  // record is freed when the thread ends, under a static mutex of OIIO's;
  // TBB's workers end during the process's teardown, after OIIO's statics
  // are gone, and crashed the Python interpreter's exit now and then.
  OIIO::ImageCache::Perthread* perthread() const {
    std::lock_guard<std::mutex> lock(perthread_mutex_);
    OIIO::ImageCache::Perthread*& info = perthread_[std::this_thread::get_id()];
    if (!info) info = cache_->create_thread_info();
    return info;
  }

  OIIO::ImageCache* cache_;
  OIIO::ImageCache::ImageHandle* handle_ = nullptr;
  mutable std::mutex perthread_mutex_;
  mutable std::map<std::thread::id, OIIO::ImageCache::Perthread*> perthread_;
  double trim_bytes_;         // the bytes read between two trims
  long long tile_bytes_ = 0;  // one tile of the file, as the cache holds it
  mutable std::mutex trim_mutex_;
  mutable std::atomic<long long> trimmed_at_{0};  // the bytes read at the last trim
};

// The texels of one MIP level of an image past the memory budget, read on
// demand through the file's CacheFile. Every read goes through the same
// conversion as decode_image (ImageCache::get_pixels into float, then
// to_rgba), so both give the same values.
class CachedImage final : public TileSource {
 public:
  CachedImage(std::shared_ptr<const CacheFile> file, const fs::path& path,
              const OIIO::ImageSpec& spec, int miplevel)
      : file_(std::move(file)),
        path_(path),
        miplevel_(miplevel),
        x_(spec.x),
        y_(spec.y),
        z_(spec.z),
        nc_(spec.nchannels),
        alpha_(alpha_channel(spec)) {}

  bool read(int x0, int y0, int w, int h, int stride, bool decode_srgb, bool premultiply,
            float* rgba) const override {
    thread_local std::vector<float> values;
    values.resize(static_cast<std::size_t>(w) * h * nc_);
    if (!file_->get_pixels(miplevel_, x_ + x0, x_ + x0 + w, y_ + y0, y_ + y0 + h, z_, nc_,
                           values.data())) {
      set_error(path_.string() + ": cannot decode (truncated or corrupt?): " + file_->error());
      for (int r = 0; r < h; ++r) {
        std::fill_n(rgba + static_cast<std::size_t>(r) * stride * 4,
                    static_cast<std::size_t>(w) * 4, 0.f);
      }
      return false;
    }
    for (int r = 0; r < h; ++r) {
      for (int c = 0; c < w; ++c) {
        float* d = rgba + (static_cast<std::size_t>(r) * stride + c) * 4;
        to_rgba(&values[(static_cast<std::size_t>(r) * w + c) * nc_], nc_, alpha_, d);
        if (decode_srgb || premultiply) transform_texel(d, decode_srgb, premultiply);
      }
    }
    return true;
  }

 private:
  std::shared_ptr<const CacheFile> file_;
  fs::path path_;
  int miplevel_;
  int x_, y_, z_, nc_, alpha_;
};

// Whether read_image opens the image of header `spec` through the cache:
// a budget is set and the float RGBA copies the caller would hold
// (ImageReadOptions::memory_copies x 16 bytes a pixel) exceed it, or the
// image is past the size limits of a whole decode.
bool goes_through_cache(const OIIO::ImageSpec& spec, const ImageReadOptions& options) {
  if (options.cache_mb == 0 || spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    return false;
  }
  if (!check_image_size(spec.width, spec.height, spec.nchannels)) return true;
  const double bytes = static_cast<double>(spec.width) * spec.height * 16 * options.memory_copies;
  return bytes > static_cast<double>(options.cache_mb) * (1 << 20);
}

// Whether the file's MIP levels are worth reading for an image read as
// `img` (ImageReadOptions::linear_working).
bool wants_levels(const ImageReadOptions& options, const Image& img) {
  return !(options.linear_working && img.color_space == ColorSpace::kSrgb);
}

// Levels 1 .. of `img`'s file, read by read_level(level) (decoded or
// through the cache) into img.mip, in img's encoding. A level whose size is
// not the chain's leaves img without levels; a level that cannot be read is
// the error.
template <class ReadLevel>
Status attach_levels(Image& img, const std::vector<std::pair<int, int>>& sizes,
                     ReadLevel&& read_level) {
  auto mip = std::make_shared<Image::MipLevels>();
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    Expected<Image> level = read_level(static_cast<int>(i) + 1);
    if (!level) return level.error();
    if (level->width != sizes[i].first || level->height != sizes[i].second) return ok_status();
    level->color_space = img.color_space;
    mip->levels.push_back(std::move(*level));
  }
  for (const Image& level : mip->levels) mip->views.push_back(level.view());
  img.mip = std::move(mip);
  return ok_status();
}

Expected<Image> open_cached(const fs::path& path, const OIIO::ImageSpec& header,
                            const std::string& format, long long stored_bytes,
                            const ImageReadOptions& options,
                            const std::vector<std::pair<int, int>>& mip_sizes) {
  if (Status s = check_header(header, format, stored_bytes, path, /*whole=*/false); !s) {
    return s.error();
  }
  // The budget, less what every thread's decoded-tile cache holds
  // (mapping/tiled_image.h), less a tenth for what the ImageCache holds
  // besides its tiles and for the heap's slack as tiles come and go (so
  // the peak measured by bench/large_images stays within the budget); at
  // least a quarter of it for the file's tiles. One cache for all the
  // file's MIP levels.
  const double budget = static_cast<double>(options.cache_mb);
  const double threads = std::max(1u, std::thread::hardware_concurrency());
  const double tile_caches =
      threads * static_cast<double>(tile_cache_bytes_per_thread()) / (1 << 20);
  auto file = std::make_shared<const CacheFile>(
      path, static_cast<float>(std::max(budget / 4, 0.9 * (budget - tile_caches))));
  // Level `miplevel`, with its first and last texel read: a file whose
  // header claims more than it holds (truncated, or a lying size) fails
  // here, before the bake; damage in between is reported by the bake when
  // it reads there (TileSource::failed).
  auto open_level = [&](int miplevel) -> Expected<Image> {
    const OIIO::ImageSpec* spec = file->spec(miplevel);
    if (!spec) {
      return image_error(ErrorCode::kParse, path, "cannot read as an image: " + file->error());
    }
    auto cached = std::make_shared<CachedImage>(file, path, *spec, miplevel);
    Image img;
    img.width = spec->width;
    img.height = spec->height;
    img.has_alpha = alpha_channel(*spec) >= 0;
    set_color_space(*spec, options, img);
    float probe[4];
    if (!cached->read(0, 0, 1, 1, 1, false, false, probe) ||
        !cached->read(img.width - 1, img.height - 1, 1, 1, 1, false, false, probe)) {
      return make_error(ErrorCode::kParse, cached->error());
    }
    img.tiles = std::move(cached);
    return img;
  };
  Expected<Image> img = open_level(0);
  if (!img || mip_sizes.empty() || !wants_levels(options, *img)) return img;
  // The cache's view of the file is checked against the reader's chain.
  if (Status s = attach_levels(*img, mip_sizes, open_level); !s) return s.error();
  return img;
}

}  // namespace

Expected<Image> read_image(const fs::path& path, const ImageReadOptions& options) {
  // Before OIIO opens it: a FIFO would block, a device never end.
  if (Status s = check_regular_file(path, "an image"); !s) return s.error();
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (size == 0) return image_error(ErrorCode::kParse, path, "the file is empty (0 bytes)");
  const OIIO::ImageSpec config = read_config();
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) {
    return image_error(ErrorCode::kParse, path,
                       "cannot read as an image: " + first_line(OIIO::geterror()));
  }
  // A size that could not be read takes no part in the compression check.
  const long long stored =
      ec ? std::numeric_limits<long long>::max() : static_cast<long long>(size);
  const std::vector<std::pair<int, int>> mip_sizes =
      options.mip_levels ? mip_chain(*in) : std::vector<std::pair<int, int>>{};
  if (in->current_subimage() != 0 || in->current_miplevel() != 0) {
    return image_error(ErrorCode::kParse, path,
                       "cannot read as an image: " + first_line(in->geterror()));
  }
  if (goes_through_cache(in->spec(), options)) {
    const OIIO::ImageSpec spec = in->spec();
    const std::string format = in->format_name();
    in.reset();
    return open_cached(path, spec, format, stored, options, mip_sizes);
  }
  Expected<Image> img = decode_image(in.get(), path, stored, options);
  if (!img || mip_sizes.empty() || !wants_levels(options, *img)) return img;
  // A MIP-mapped file: its levels are decoded too, as level 0 is (their
  // non-finite values are not counted: the warning is about the image).
  if (Status s = attach_levels(
          *img, mip_sizes,
          [&](int level) { return decode_image(in.get(), path, stored, options, level); });
      !s) {
    return s.error();
  }
  return img;
}

Expected<Image> read_image_from_memory(std::span<const unsigned char> bytes,
                                       const std::string& mime_type, const std::string& name,
                                       const ImageReadOptions& options) {
  if (bytes.empty()) return image_error(ErrorCode::kParse, name, "the image is empty (0 bytes)");
  const std::string ext = memory_image_extension(bytes.data(), bytes.size(), mime_type);
  if (ext.empty()) {
    return image_error(ErrorCode::kParse, name,
                       "cannot read as an image: unknown format" +
                           (mime_type.empty() ? std::string() : " '" + mime_type + "'"));
  }
  // OIIO 2.4: an ImageInput reads from a Filesystem::IOMemReader instead of
  // a file; the name's extension picks the format. The proxy outlives `in`
  // (declared first, destroyed last).
  OIIO::Filesystem::IOMemReader proxy(const_cast<unsigned char*>(bytes.data()), bytes.size());
  OIIO::ImageSpec config = read_config();
  // OIIO 2.4's readers take the proxy from the configuration hint
  // "oiio:ioproxy" when a config is given (the open() argument alone is
  // replaced by the config's, i.e. none).
  OIIO::Filesystem::IOProxy* proxy_ptr = &proxy;
  config.attribute("oiio:ioproxy", OIIO::TypeDesc::PTR, &proxy_ptr);
  auto in = OIIO::ImageInput::open("embedded" + ext, &config, &proxy);
  if (!in) {
    return image_error(ErrorCode::kParse, name,
                       "cannot read as an image: " + first_line(OIIO::geterror()));
  }
  return decode_image(in.get(), name, static_cast<long long>(bytes.size()), options);
}

namespace {

// How the values change on their way into the file (ImageWriteOptions::encode_for_format).
enum class Transfer { kNone, kToLinear, kToSrgb };

inline float transfer(float c, Transfer t) {
  return t == Transfer::kToLinear ? srgb_to_linear(c)
         : t == Transfer::kToSrgb ? linear_to_srgb(c)
                                  : c;
}

// Pixel i's channel k as written (R, G, B through `t`; alpha never).
inline float file_value(const ImageView& image, std::size_t i, int k, Transfer t) {
  const float c = image.data[i * 4 + k];
  return k < 3 ? transfer(c, t) : c;
}

template <class T>
std::vector<T> quantize(const ImageView& image, int channels, float max, Transfer t) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  std::vector<T> out(n * channels);
  for (std::size_t i = 0; i < n; ++i) {
    for (int k = 0; k < channels; ++k) {
      const float c = file_value(image, i, k, t);
      // Clamp, then round to nearest (NaN -> 0).
      const float q = !(c > 0.f) ? 0.f : (c >= 1.f ? max : std::round(c * max));
      out[i * channels + k] = static_cast<T>(q);
    }
  }
  return out;
}

}  // namespace

namespace {

// What write_image writes for `ext` (lower case, with the dot).
struct Encoding {
  int channels = 3;
  ImageBitDepth depth = ImageBitDepth::k8;
};

Encoding encoding_for(const ImageView& image, const std::string& ext,
                      const ImageWriteOptions& options) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  bool opaque = true;
  for (std::size_t i = 0; i < n && opaque; ++i) opaque = image.data[i * 4 + 3] >= 1.f;
  Encoding e;
  e.channels = opaque ? 3 : 4;
  e.depth = options.bit_depth;
  if (ext == ".exr" || ext == ".hdr") e.depth = ImageBitDepth::kFloat;
  if ((ext == ".png" || ext == ".jpg" || ext == ".jpeg") && e.depth == ImageBitDepth::kFloat) {
    e.depth = ImageBitDepth::k16;
  }
  if (ext == ".jpg" || ext == ".jpeg") e.depth = ImageBitDepth::k8;
  return e;
}

std::string lower_ext(const fs::path& path) {
  return lower(path.extension().string());
}

// Opens `out` on `name` with the spec for `e` and writes the pixels. `what`
// names the destination in errors.
Status encode_into(OIIO::ImageOutput& out, const std::string& name, const ImageView& image,
                   const Encoding& e, const ImageWriteOptions& options, const std::string& what) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  const int channels = e.channels;
  OIIO::TypeDesc type = e.depth == ImageBitDepth::k8    ? OIIO::TypeDesc::UINT8
                        : e.depth == ImageBitDepth::k16 ? OIIO::TypeDesc::UINT16
                                                        : OIIO::TypeDesc::FLOAT;
  // The file's colour space: the format's own when encoding for it, else the values'.
  const ColorSpace file_space = !options.encode_for_format         ? image.color_space
                                : e.depth == ImageBitDepth::kFloat ? ColorSpace::kLinear
                                                                   : ColorSpace::kSrgb;
  const Transfer t = file_space == image.color_space     ? Transfer::kNone
                     : file_space == ColorSpace::kLinear ? Transfer::kToLinear
                                                         : Transfer::kToSrgb;
  OIIO::ImageSpec spec(image.width, image.height, channels, type);
  if (options.tag_color_space) spec.attribute("oiio:ColorSpace", color_space_name(file_space));
  if (channels == 4) {
    spec.alpha_channel = 3;
    // Our values are unassociated (straight) alpha: stop OIIO dividing by it.
    spec.attribute("oiio:UnassociatedAlpha", 1);
  }
  spec.attribute("png:compressionLevel", std::clamp(options.png_compression, 0, 9));
  if (!out.open(name, spec)) {
    return make_error(ErrorCode::kIo, "cannot write " + what + ": " + first_line(out.geterror()));
  }
  bool ok = false;
  if (e.depth == ImageBitDepth::k8) {
    const auto q = quantize<uint8_t>(image, channels, 255.f, t);
    ok = out.write_image(OIIO::TypeDesc::UINT8, q.data());
  } else if (e.depth == ImageBitDepth::k16) {
    const auto q = quantize<uint16_t>(image, channels, 65535.f, t);
    ok = out.write_image(OIIO::TypeDesc::UINT16, q.data());
  } else {
    std::vector<float> f(n * channels);
    for (std::size_t i = 0; i < n; ++i) {
      for (int k = 0; k < channels; ++k) f[i * channels + k] = file_value(image, i, k, t);
    }
    ok = out.write_image(OIIO::TypeDesc::FLOAT, f.data());
  }
  const bool closed = out.close();
  if (!ok || !closed) {
    return make_error(ErrorCode::kIo, "cannot write " + what + ": " + first_line(out.geterror()));
  }
  return ok_status();
}

}  // namespace

Status write_image(const fs::path& path, const ImageView& image, const ImageWriteOptions& options) {
  if (image.width <= 0 || image.height <= 0 || image.data == nullptr) {
    return make_error(ErrorCode::kInternal, "cannot write " + path.string() + ": empty image");
  }
  const std::string ext = lower_ext(path);
  const Encoding e = encoding_for(image, ext, options);
  return stage_or_write(options.file_set, path, [&](const fs::path& temp) -> Status {
    auto out = OIIO::ImageOutput::create(temp.string());
    if (!out) {
      return make_error(ErrorCode::kUnsupported, "cannot write " + path.string() +
                                                     ": no image format for '" + ext + "' (" +
                                                     first_line(OIIO::geterror()) + ")");
    }
    return encode_into(*out, temp.string(), image, e, options, path.string());
  });
}

Expected<std::vector<unsigned char>> encode_image(const ImageView& image,
                                                  const std::string& extension,
                                                  const ImageWriteOptions& options) {
  const std::string what = "a " + extension + " image in memory";
  if (image.width <= 0 || image.height <= 0 || image.data == nullptr) {
    return make_error(ErrorCode::kInternal, "cannot write " + what + ": empty image");
  }
  const std::string ext = lower_ext(fs::path("image" + extension));
  const Encoding e = encoding_for(image, ext, options);
  const std::string name = "image" + ext;
  auto out = OIIO::ImageOutput::create(name);
  if (!out) {
    return make_error(ErrorCode::kUnsupported, "cannot write " + what + ": no image format (" +
                                                   first_line(OIIO::geterror()) + ")");
  }
  if (!out->supports("ioproxy")) {
    return make_error(ErrorCode::kUnsupported,
                      "cannot write " + what + ": OpenImageIO cannot write it to memory");
  }
  // OIIO 2.4: ImageOutput::set_ioproxy with a Filesystem::IOVecOutput
  // collects the encoded bytes in our vector instead of a file.
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput proxy(bytes);
  if (!out->set_ioproxy(&proxy)) {
    return make_error(ErrorCode::kUnsupported,
                      "cannot write " + what + ": " + first_line(out->geterror()));
  }
  if (Status s = encode_into(*out, name, image, e, options, what); !s) return s.error();
  out.reset();
  if (bytes.empty()) return make_error(ErrorCode::kIo, "cannot write " + what + ": no bytes");
  return bytes;
}

}  // namespace texbake
