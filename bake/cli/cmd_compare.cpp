// texbake compare A B [--mask-background] [--min-psnr DB]: PSNR and largest
// difference of two images (mesh_io/image_compare.h has the definitions).
// Exit 0 when compared (and --min-psnr, if given, is reached), 1 when an image
// cannot be read, the sizes differ or the PSNR is below --min-psnr, 2 for
// usage errors.
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "bake/cli/commands.h"
#include "texbake/texbake.h"

namespace texbake::cli {
namespace {

struct CompareArgs {
  std::string a, b;
  bool mask_background = false;
  std::optional<double> min_psnr;
  std::vector<float> background;
};

std::string format_db(double db) {
  if (std::isinf(db)) return "inf";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", db);
  return buf;
}

int run_compare(const CompareArgs& args) {
  CompareOptions options;
  options.mask_background = args.mask_background;
  if (!args.background.empty()) {
    for (std::size_t c = 0; c < 3; ++c) options.background[c] = args.background[c];
  }
  if (Status s = validate_options(options); !s) return report_error(s.error());
  auto result = compare_image_files(args.a, args.b, options);
  if (!result) return report_error(result.error());
  const CompareResult& r = *result;
  std::printf("size: %dx%d, %d channel(s) compared\n", r.width, r.height, r.channels);
  std::printf("compared pixels: %zu of %zu%s\n", r.compared_pixels,
              static_cast<std::size_t>(r.width) * r.height,
              args.mask_background ? " (background masked)" : "");
  std::printf("PSNR: %s dB\n", format_db(r.psnr).c_str());
  std::printf("RMS error: %.6g\n", r.rms);
  std::printf("max difference: %.6g at pixel (%d, %d) channel %d\n", r.max_difference, r.max_x,
              r.max_y, r.max_channel);
  if (args.min_psnr && !(r.psnr >= *args.min_psnr)) {
    return report_error(ErrorCode::kIo, "PSNR " + format_db(r.psnr) + " dB is below --min-psnr " +
                                            format_db(*args.min_psnr) + " dB");
  }
  return 0;
}

}  // namespace

RunFunction add_compare_command(CLI::App& app) {
  auto args = std::make_shared<CompareArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compare",
      "PSNR and largest difference of two images (e.g. two renders), by OpenImageIO.\n"
      "PSNR = 20 log10(1 / RMS) over the channels both images have, values in [0, 1].");
  cmd->add_option("A", args->a, "first image")->required();
  cmd->add_option("B", args->b, "second image")->required();
  cmd->add_flag("--mask-background", args->mask_background,
                "ignore pixels that are background in both images: alpha 0 when both have "
                "alpha, else equal to --background (within 0.5/255)");
  cmd->add_option("--min-psnr", args->min_psnr,
                  "fail (exit 1) when the PSNR in dB is below this value");
  cmd->add_option("--background", args->background,
                  "R,G,B background colour in [0, 1] for images without alpha "
                  "(default: texbake render's, 0.3,0.3,0.35)")
      ->delimiter(',')
      ->expected(3);
  return [args] { return run_compare(*args); };
}

}  // namespace texbake::cli
