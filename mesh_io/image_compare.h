// Numerical comparison of two images (texbake compare, SPEC section 5),
// done with OpenImageIO's ImageBufAlgo (compare, computePixelStats, absdiff,
// channel ops) rather than hand-written pixel loops.
//
// Definitions:
//  - Values are the images' stored values scaled to [0, 1] (8-bit 255 -> 1);
//    alpha is read unassociated (no premultiplication), so what is compared
//    is exactly what the files hold.
//  - Channels compared: the first min(channels of A, channels of B) channels
//    (an RGBA render against an RGBA render compares R, G, B and A).
//  - RMS = sqrt(mean over compared pixels and channels of (A - B)^2);
//    PSNR = 20 log10(1 / RMS) dB (peak value 1), +infinity when RMS is 0.
//  - Max difference: the largest |A - B| over compared pixels and channels,
//    with the first pixel (row-major) and channel where it occurs.
//  - Background (mask_background): a pixel is background when it is
//    background in both images, and then takes no part in any figure. With an
//    alpha channel in both images, background means alpha == 0 (texbake
//    render writes alpha 0 exactly where the mesh covers no sample). Without,
//    it means every colour channel is within half an 8-bit step (0.5 / 255) of
//    `background` (texbake render's default background unless given).
#pragma once

#include <cstddef>
#include <filesystem>

#include "mapping/error.h"
#include "mapping/image_view.h"

namespace texbake {

struct CompareOptions {
  bool mask_background = false;
  Rgba background{0.3f, 0.3f, 0.35f, 0.0f};  // RGB used only for images without alpha
};

struct CompareResult {
  int width = 0, height = 0;
  int channels = 0;                 // channels compared
  std::size_t compared_pixels = 0;  // pixels not masked as background
  double rms = 0;
  double psnr = 0;  // dB; +infinity for identical images
  double max_difference = 0;
  int max_x = 0, max_y = 0, max_channel = 0;  // where max_difference occurs
};

// Reads both files (any format OpenImageIO reads) and compares them.
// Errors: kIo for a missing or unreadable file, kParse for a size mismatch;
// messages name the file(s).
Expected<CompareResult> compare_image_files(const std::filesystem::path& a,
                                            const std::filesystem::path& b,
                                            const CompareOptions& options);

// The same comparison on two RGBA float views (all four channels).
// Error kParse for a size mismatch.
Expected<CompareResult> compare_images(const ImageView& a, const ImageView& b,
                                       const CompareOptions& options);

}  // namespace texbake
