// Images in and out through OpenImageIO (SPEC sections 1 and 7). Only
// image_io.cpp includes OIIO.
//
// Reading: every format and layout OIIO reads (PNG, JPEG, TIFF, EXR, HDR, ...;
// 8/16-bit integer, half, float; 1-4 channels) becomes one owning float RGBA
// image, top row first:
//   1 channel: gray -> (g, g, g, 1)        2 channels: gray + alpha -> (g, g, g, a)
//   3 channels: (r, g, b, 1)               4 channels: (r, g, b, a)
//   more: the first three as RGB, alpha from the file's alpha channel or 1.
// Integer formats are scaled to [0, 1] (uint8 / 255, uint16 / 65535); float
// formats keep their values. No colour-space conversion happens on reading.
// NaN and infinite values (float formats) are read as 0 and counted in
// Image::nonfinite_values. Pixels are decoded in bands of rows (tile rows
// for tiled files) and the result is allocated after the first band has
// decoded, so a small file with a lying header fails before any large
// allocation; running out of memory is an error naming the file.
// Errors (file named): missing, not a regular file (a folder, a FIFO, a
// device), unreadable, not an image, truncated or 0-pixel images.
//
// Writing goes through write_atomically (temporary name keeps the real
// extension last, from which OIIO picks the format): .png as 8-bit (default)
// or 16-bit, .exr as float; other extensions OIIO writes are accepted with
// 8-bit data (16-bit / float where the format allows and requested). Values
// are clamped to [0, 1] and rounded to nearest for integer outputs. Alpha is
// written only when some pixel is not opaque.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "mapping/error.h"
#include "mapping/image_view.h"

namespace texbake {

class AtomicFileSet;

// Owning float RGBA image; view() is valid while the Image lives unchanged.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // width * height * 4, top row first
  // read_image: NaN or infinite values in the file, read as 0 (a float
  // texture's holes must not poison interpolation); callers warn about them.
  std::size_t nonfinite_values = 0;

  ImageView view() const { return {width, height, pixels.data()}; }
};

Expected<Image> read_image(const std::filesystem::path& path);

// Size limits of read_image, checked on the file's header before any pixel
// is decoded (a lying header must not make texbake allocate terabytes): at
// most kMaxImagePixels pixels (16384 x 16384) and kMaxImageValues decoded
// values (16384 x 16384 x 4 channels: 4 GiB of floats, so a many-channel
// image must be smaller). read_image holds the decoded values and the RGBA
// result at once: at most 8 GiB for the largest image accepted. Above the
// limits: kParse naming the size (read_image prefixes the file name).
inline constexpr long long kMaxImagePixels = 1ll << 28;
inline constexpr long long kMaxImageValues = 1ll << 30;
Status check_image_size(long long width, long long height, int channels);

// The largest side of a square texture atlas texbake bakes or lays out
// (SPEC section 4 / issue #4): the largest square image read_image reads back.
inline constexpr int kMaxAtlasSize = 16384;
static_assert(static_cast<long long>(kMaxAtlasSize) * kMaxAtlasSize == kMaxImagePixels);

enum class ImageBitDepth {
  k8,      // PNG default
  k16,     // 16-bit PNG / TIFF
  kFloat,  // EXR (always float, whatever is requested)
};

// zlib level of OIIO's PNG writer when not set ("png:compressionLevel").
inline constexpr int kPngCompressionDefault = 6;

struct ImageWriteOptions {
  ImageBitDepth bit_depth = ImageBitDepth::k8;
  // PNG only: zlib/deflate level 0 (fastest, largest) .. 9 (slowest,
  // smallest); lossless at every level.
  int png_compression = kPngCompressionDefault;
  // write_image only: stage the file into this set (mesh_io/atomic_file.h;
  // the caller commits it) instead of writing it at once.
  AtomicFileSet* file_set = nullptr;
};

// Precondition: image has at least 1x1 pixel.
Status write_image(const std::filesystem::path& path, const ImageView& image,
                   const ImageWriteOptions& options = {});

// The bytes of the file write_image would write for a file named
// "image<extension>" (e.g. ".png"), encoded in memory (OIIO's IOProxy), for
// containers that embed images (GLB). Formats whose OIIO writer cannot write
// to memory: kUnsupported. Precondition: image has at least 1x1 pixel.
Expected<std::vector<unsigned char>> encode_image(const ImageView& image,
                                                  const std::string& extension,
                                                  const ImageWriteOptions& options = {});

}  // namespace texbake
