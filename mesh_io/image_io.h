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
// formats keep their values. No colour-space conversion happens on reading:
// the values stay as stored and Image::color_space says how they are encoded
// (issue #11), as OpenImageIO 2.4 reports it in "oiio:ColorSpace":
//   - "linear", "Linear", "lin_srgb", "scene_linear", any name containing
//     "linear", or a gamma of 1 ("GammaX" names with oiio:Gamma 1, e.g. a PNG
//     with gAMA 1.0): ColorSpace::kLinear;
//   - a name starting with "sRGB" (any case), or a gamma of 1.8 .. 2.6
//     (a PNG with gAMA 1/2.2, a pure power curve read as the sRGB curve it
//     approximates): ColorSpace::kSrgb;
//   - no attribute (OIIO 2.4 gives none for TIFF without Exif colour space),
//     or a name that is neither (e.g. "AdobeRGB", "ACEScg", other gammas): by
//     the file's data type, float and half linear, 8/16-bit integer sRGB;
//     such a name is kept in Image::unrecognised_color_space for a warning.
// OIIO 2.4 reports "sRGB" for JPEG, for PNG without colour chunks and with an
// sRGB chunk, "Linear" for every EXR (its EXR writer keeps no other name)
// and "linear" for HDR; TIFF has the attribute only when tagged sRGB (Exif).
// ImageReadOptions overrides the detection (--texture-colorspace).
// NaN and infinite values (float formats) are read as 0 and counted in
// Image::nonfinite_values. Pixels are decoded in bands of rows (tile rows
// for tiled files) and the result is allocated after the first band has
// decoded, so a small file with a lying header fails before any large
// allocation; running out of memory is an error naming the file.
// Errors (file named): missing, not a regular file (a folder, a FIFO, a
// device), unreadable, not an image, truncated or 0-pixel images.
//
// Large images (issue #16, SPEC section 13): with a memory budget
// (ImageReadOptions::cache_mb, --cache-mb) an image whose float RGBA copies
// would not fit in it, or that is past the size limits of a whole decode,
// is not decoded: read_image checks its header (a PNG or JPEG too small for
// its size is refused as above), reads its first and last texel (a
// truncated file or a lying size fails here) and returns an Image with
// `tiles` set and no `pixels`, whose texels are read on demand through an
// OpenImageIO ImageCache (tiles of the file, or 64 x 64 tiles of an untiled
// one) holding at most the budget less the per-thread tile caches
// (mapping/tiled_image.h). The values are those the whole decode gives, bit
// for bit. A read that fails later (damage past the first and last tile)
// gives zeros and sets the source's error (TileSource::failed), which the
// bakes report as the file's error. nonfinite_values is not counted for a
// cached image (it is not read whole); its NaN are still read as 0.
//
// Writing goes through write_atomically (temporary name keeps the real
// extension last, from which OIIO picks the format): .png as 8-bit (default)
// or 16-bit, .exr as float; other extensions OIIO writes are accepted with
// 8-bit data (16-bit / float where the format allows and requested). Values
// are clamped to [0, 1] and rounded to nearest for integer outputs. Alpha is
// written only when some pixel is not opaque. Colour spaces: see
// ImageWriteOptions::encode_for_format and tag_color_space.
#pragma once

#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/tiled_image.h"

namespace texbake {

class AtomicFileSet;

// Owning float RGBA image; view() is valid while the Image lives unchanged.
// Either decoded (`pixels`) or, past a memory budget, cached (`tiles`, no
// `pixels`; see above): code that needs `pixels` reads without a budget.
struct Image {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;  // width * height * 4, top row first; empty when `tiles`
  // The texels read on demand (read_image with a budget); shared, so a
  // copy of the Image reads the same cache.
  std::shared_ptr<const TileSource> tiles;
  // read_image: NaN or infinite values in the file, read as 0 (a float
  // texture's holes must not poison interpolation); callers warn about them.
  std::size_t nonfinite_values = 0;
  // The encoding of the values (read_image: detected or overridden, see above).
  ColorSpace color_space = ColorSpace::kSrgb;
  // read_image: the file's oiio:ColorSpace when it names neither sRGB nor
  // linear light and the data type decided (empty otherwise, and always
  // with an override); callers warn about it.
  std::string unrecognised_color_space;
  // read_image: whether the file has an alpha channel (a grey + alpha or an
  // RGBA file, or OpenImageIO's alpha channel); alpha is 1 everywhere when not.
  bool has_alpha = false;
  // read_image of a MIP-mapped file (several MIP levels, as maketx writes
  // them: each level max(1, floor(previous / 2)) a side, down to 1 x 1):
  // levels 1 .., read as level 0 is (in memory or through the same cache),
  // in its encoding. Null for a plain image, or when the file's levels are
  // not that chain (they are then not used). Shared and immutable, so a
  // copy of the Image views the same levels.
  struct MipLevels {
    std::vector<Image> levels;     // levels 1 ..
    std::vector<ImageView> views;  // their views, in the same order
  };
  std::shared_ptr<const MipLevels> mip;

  ImageView view() const {
    ImageView v{width, height, tiles ? nullptr : pixels.data(), color_space};
    v.tiles = tiles.get();
    if (mip) {
      v.mip_levels = mip->views.data();
      v.mip_level_count = static_cast<int>(mip->views.size());
    }
    return v;
  }
};

// How to take a texture's colour space (--texture-colorspace).
enum class TextureColorSpace {
  kAuto,    // as OpenImageIO reports it (the rules above)
  kSrgb,    // the values are sRGB-encoded, whatever the file says
  kLinear,  // the values are linear light, whatever the file says
};

struct ImageReadOptions {
  TextureColorSpace color_space = TextureColorSpace::kAuto;
  // The memory budget in MiB (--cache-mb; SPEC section 13). 0: none, the
  // image is always decoded whole (within kMaxImagePixels). Otherwise an
  // image whose memory_copies float RGBA copies (16 bytes a pixel each)
  // exceed it, or past kMaxImagePixels / kMaxImageValues, is read through
  // the cache (see above). read_image_from_memory ignores it.
  std::size_t cache_mb = 0;
  // How many float RGBA copies of the image the caller would hold in memory
  // (the image, a linear working copy, a MIP pyramid's third, ...).
  double memory_copies = 1;
  // Read a MIP-mapped file's levels above the full size too (Image::mip;
  // for --filter ewa), in memory or through the cache as level 0 is.
  bool mip_levels = false;
  // The caller works in linear light (--linear): the levels of a texture
  // read as sRGB-encoded average encoded values and would not be used
  // (the bake builds linear-light ones), so they are not read.
  bool linear_working = false;
};

// The default budget of --cache-mb.
inline constexpr std::size_t kDefaultCacheMb = 1024;

Expected<Image> read_image(const std::filesystem::path& path, const ImageReadOptions& options = {});

// read_image for an encoded image held in memory (an image embedded in a
// glTF file): the same decoding, limits and colour-space rules, through
// OpenImageIO's in-memory reader (Filesystem::IOMemReader). The format comes
// from `mime_type` (image/png, image/jpeg, image/webp, image/bmp,
// image/gif, image/tiff), else from the bytes' signature (PNG, JPEG).
// `name` stands for the file in errors ("MODEL.glb: image 0"). Errors:
// kParse (empty, unknown format, not decodable, above the size limits).
Expected<Image> read_image_from_memory(std::span<const unsigned char> bytes,
                                       const std::string& mime_type, const std::string& name,
                                       const ImageReadOptions& options = {});

// The colour space the detection rules above give for an "oiio:ColorSpace"
// value `name` ("" when the file has none), its "oiio:Gamma" (0 when none)
// and whether the data type is floating point. `recognised`, when not null,
// is set to false when `name` is non-empty and named neither space (the data
// type decided). Exposed for tests.
ColorSpace color_space_from_attributes(const std::string& name, float gamma, bool float_data,
                                       bool* recognised = nullptr);

// The name texbake tags a file of that colour space with ("oiio:ColorSpace"):
// "sRGB" or "Linear", the names OpenImageIO 2.4 uses and reports (EXR).
const char* color_space_name(ColorSpace space);

// Size limits of read_image, checked on the file's header before any pixel
// is decoded (a lying header must not make texbake allocate terabytes): at
// most kMaxImagePixels pixels (16384 x 16384) and kMaxImageValues decoded
// values (16384 x 16384 x 4 channels: 4 GiB of floats, so a many-channel
// image must be smaller). read_image holds the decoded values and the RGBA
// result at once: at most 8 GiB for the largest image accepted. Above the
// limits: kParse naming the size (read_image prefixes the file name), unless
// a memory budget is set (ImageReadOptions::cache_mb): the image is then
// read through the cache, whatever its size.
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
  // Colour space of the file (issue #11). false: the values are written as
  // given, in the image's color_space (an EXR is read back as linear
  // whatever its tag: OIIO 2.4 keeps none but "Linear"). true: they are first converted from
  // the image's color_space to the format's own, linear light for float data
  // (EXR, HDR, float TIFF) and sRGB-encoded for 8/16-bit data (PNG, JPEG,
  // TIFF), by the sRGB curves of mapping/sample.h on R, G, B (alpha as is).
  bool encode_for_format = false;
  // Tag the file with the colour space its values are in ("oiio:ColorSpace",
  // color_space_name(); OIIO writes a PNG's as gAMA + sRGB + cHRM chunks for
  // "sRGB", gAMA 1.0 for "Linear", an EXR's as a header attribute). false:
  // no tag, for PNGs embedded in a GLB: glTF fixes an image's space by its
  // use and glTF-Validator warns about colour chunks (IMAGE_FEATURES_UNSUPPORTED).
  bool tag_color_space = true;
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
