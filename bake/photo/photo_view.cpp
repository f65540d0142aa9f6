#include "bake/photo/photo_view.h"

#include <algorithm>
#include <cstdlib>

#include "bake/util/parallel.h"
#include "mapping/sample.h"
#include "mesh_io/image_io.h"

namespace texbake::photo_detail {

Expected<PhotoImage> read_photo_file(const Photo& photo) {
  Expected<Image> image = read_image(photo.path);
  if (!image) return image.error();
  return PhotoImage{image->width, image->height, std::move(image->pixels), image->color_space};
}

namespace {

// A photo of the camera's size, or of its aspect at another size (then
// `scaled`); else an error naming both sizes.
Status check_photo_size(const Photo& photo, const PhotoImage& image, bool& scaled) {
  const int w = photo.camera.spec().width, h = photo.camera.spec().height;
  scaled = false;
  if (image.width == w && image.height == h) return ok_status();
  const long long cross =
      static_cast<long long>(image.width) * h - static_cast<long long>(image.height) * w;
  if (image.width > 0 && image.height > 0 && std::llabs(cross) < std::max(w, h)) {
    scaled = true;
    return ok_status();
  }
  return make_error(ErrorCode::kParse, photo.path.string() + ": the photo of " + photo.name +
                                           " is " + std::to_string(image.width) + " x " +
                                           std::to_string(image.height) + ", its camera " +
                                           std::to_string(w) + " x " + std::to_string(h) +
                                           " (neither that size nor that aspect)");
}

}  // namespace

Error unreadable_photo_error(const Photo& photo, const Error& read) {
  return make_error(read.code, "the photo of camera " + photo.name + ": " + read.message);
}

Error no_usable_photo_error(const std::vector<SkippedPhoto>& skipped) {
  const std::string first = skipped.empty() ? std::string() : skipped.front().reason;
  if (skipped.size() == 1) {
    return make_error(ErrorCode::kIo,
                      "no usable photo: the only photo cannot be read (" + first + ")");
  }
  return make_error(ErrorCode::kIo, "no usable photo: all " + std::to_string(skipped.size()) +
                                        " photos cannot be read (the first: " + first + ")");
}

void skip_photo(const Photo& photo, const Error& read, std::vector<SkippedPhoto>& skipped,
                std::vector<std::string>& warnings) {
  skipped.push_back({photo.name, photo.path, read.message});
  warnings.push_back("the photo of camera " + photo.name + " is left out: " + read.message);
}

Expected<PhotoImage> load_photo(const Photo& photo, const PhotoReader& read,
                                PhotoCameraStats& stats, std::vector<std::string>& warnings,
                                bool& unreadable) {
  unreadable = false;
  Expected<PhotoImage> image = read(photo);
  if (!image) {
    unreadable = image.error().code != ErrorCode::kCancelled;
    return image.error();
  }
  if (Status s = check_photo_size(photo, *image, stats.scaled); !s) return s.error();
  stats.photo_width = image->width, stats.photo_height = image->height;
  const CameraProjector& camera = photo.camera;
  if (stats.scaled) {
    warnings.push_back(photo.name + ": the photo is " + std::to_string(image->width) + " x " +
                       std::to_string(image->height) + ", its camera " +
                       std::to_string(camera.spec().width) + " x " +
                       std::to_string(camera.spec().height) + "; sampled at the camera's (u, v)");
  }
  if (image->color_space == ColorSpace::kSrgb) {
    parallel_for_chunks(image->pixels.size() / 4, 1 << 16, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        for (int ch = 0; ch < 3; ++ch) {
          image->pixels[4 * i + ch] = srgb_to_linear(image->pixels[4 * i + ch]);
        }
      }
    });
  }
  return image;
}

double border_weight(Vec2 pixel, int w, int h) {
  const double edge = std::min({pixel.x, w - pixel.x, pixel.y, h - pixel.y});
  return std::clamp(edge / (kBorderFraction * std::min(w, h)), 0.0, 1.0);
}

}  // namespace texbake::photo_detail
