#include "mesh_io/image_compare.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>
#include <vector>

namespace texbake {
namespace {

using OIIO::ImageBuf;
namespace IBA = OIIO::ImageBufAlgo;

// Any positive value times this is >= 1 (the smallest 8-bit/16-bit step and
// float denormals aside), so clamp(x * kStep, 0, 1) turns "x > 0" into a 0/1
// mask with ImageBufAlgo operations.
constexpr float kStep = 1e30f;
constexpr float kBackgroundTolerance = 0.5f / 255.0f;

// Reads a whole image as float, alpha unassociated, bypassing OIIO's
// ImageCache (which could serve a stale copy of a file rewritten in place).
Expected<ImageBuf> read_float(const std::filesystem::path& path) {
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  auto in = OIIO::ImageInput::open(path.string(), &config);
  if (!in) {
    std::string why = OIIO::geterror();
    return make_error(ErrorCode::kIo, "cannot read image '" + path.string() +
                                          "': " + (why.empty() ? "unknown error" : why));
  }
  OIIO::ImageSpec spec = in->spec();
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0) {
    return make_error(ErrorCode::kParse, "image '" + path.string() + "' has no pixels");
  }
  spec.set_format(OIIO::TypeDesc::FLOAT);
  ImageBuf buf(spec);
  if (!in->read_image(0, 0, 0, spec.nchannels, OIIO::TypeDesc::FLOAT, buf.localpixels())) {
    return make_error(ErrorCode::kIo,
                      "cannot read image '" + path.string() + "': " + in->geterror());
  }
  return buf;
}

// 1-channel 0/1 image: 1 where `img` is not background (see the header).
ImageBuf foreground(const ImageBuf& img, bool use_alpha, int alpha_channel, const Rgba& bg) {
  if (use_alpha) {
    ImageBuf alpha = IBA::channels(img, 1, {alpha_channel});
    return IBA::clamp(IBA::mul(alpha, kStep), {0.0f}, {1.0f});
  }
  const int colour = std::min(img.nchannels(), 3);
  std::vector<int> order(colour);
  std::iota(order.begin(), order.end(), 0);
  ImageBuf rgb = IBA::channels(img, colour, order);
  ImageBuf dist = IBA::maxchan(IBA::absdiff(rgb, OIIO::cspan<float>(bg.data(), colour)));
  return IBA::clamp(IBA::mul(IBA::sub(dist, kBackgroundTolerance), kStep), {0.0f}, {1.0f});
}

Expected<CompareResult> compare_bufs(const ImageBuf& a, const ImageBuf& b,
                                     const CompareOptions& options, const std::string& names) {
  const OIIO::ImageSpec& sa = a.spec();
  const OIIO::ImageSpec& sb = b.spec();
  if (sa.width != sb.width || sa.height != sb.height) {
    return make_error(ErrorCode::kParse,
                      "image sizes differ: " + names + " are " + std::to_string(sa.width) + "x" +
                          std::to_string(sa.height) + " and " + std::to_string(sb.width) + "x" +
                          std::to_string(sb.height));
  }
  CompareResult r;
  r.width = sa.width;
  r.height = sa.height;
  r.channels = std::min(sa.nchannels, sb.nchannels);
  const std::size_t pixels = static_cast<std::size_t>(r.width) * r.height;

  std::vector<int> order(r.channels);
  std::iota(order.begin(), order.end(), 0);
  ImageBuf ca = IBA::channels(a, r.channels, order);
  ImageBuf cb = IBA::channels(b, r.channels, order);

  r.compared_pixels = pixels;
  if (options.mask_background) {
    const bool use_alpha = sa.alpha_channel >= 0 && sb.alpha_channel >= 0;
    ImageBuf mask = IBA::max(foreground(a, use_alpha, sa.alpha_channel, options.background),
                             foreground(b, use_alpha, sb.alpha_channel, options.background));
    const IBA::PixelStats stats = IBA::computePixelStats(mask);
    if (mask.has_error() || stats.sum.empty()) {
      return make_error(ErrorCode::kInternal, "masking " + names + " failed: " + mask.geterror());
    }
    r.compared_pixels = static_cast<std::size_t>(std::llround(stats.sum[0]));
    // Zero both images on the background: it then adds nothing to the error
    // sums, and the RMS is rescaled to the foreground pixel count below.
    ImageBuf mask_n = IBA::channels(mask, r.channels, std::vector<int>(r.channels, 0));
    ca = IBA::mul(ca, mask_n);
    cb = IBA::mul(cb, mask_n);
  }

  // Thresholds at the float maximum: OIIO sets CompareResults::error when any
  // value exceeds the fail threshold; texbake only wants the statistics.
  const float no_threshold = std::numeric_limits<float>::max();
  const IBA::CompareResults cr = IBA::compare(ca, cb, no_threshold, no_threshold);
  if (cr.error || ca.has_error() || cb.has_error()) {
    return make_error(ErrorCode::kInternal,
                      "comparing " + names + " failed: " + ca.geterror() + cb.geterror());
  }
  // OIIO's rms_error averages over every pixel of the ROI and every channel.
  r.rms = r.compared_pixels == 0
              ? 0.0
              : cr.rms_error * std::sqrt(static_cast<double>(pixels) / r.compared_pixels);
  r.psnr = r.rms > 0 ? 20.0 * std::log10(1.0 / r.rms) : std::numeric_limits<double>::infinity();
  r.max_difference = cr.maxerror;
  r.max_x = cr.maxx;
  r.max_y = cr.maxy;
  r.max_channel = cr.maxc;
  return r;
}

}  // namespace

Expected<CompareResult> compare_image_files(const std::filesystem::path& a,
                                            const std::filesystem::path& b,
                                            const CompareOptions& options) {
  auto ia = read_float(a);
  if (!ia) return ia.error();
  auto ib = read_float(b);
  if (!ib) return ib.error();
  std::string names = "'";
  names += a.string();
  names += "' and '";
  names += b.string();
  names += "'";
  return compare_bufs(*ia, *ib, options, names);
}

Expected<CompareResult> compare_images(const ImageView& a, const ImageView& b,
                                       const CompareOptions& options) {
  auto wrap = [](const ImageView& v) {
    OIIO::ImageSpec spec(v.width, v.height, 4, OIIO::TypeDesc::FLOAT);
    spec.alpha_channel = 3;
    // ImageBuf wraps the caller's pixels without copying; the algorithms
    // below only read their sources.
    return ImageBuf(spec, const_cast<float*>(v.data));
  };
  if (a.width <= 0 || a.height <= 0 || b.width <= 0 || b.height <= 0) {
    return make_error(ErrorCode::kInvalidArgument, "cannot compare an image of 0 pixels");
  }
  return compare_bufs(wrap(a), wrap(b), options, "the images");
}

}  // namespace texbake
