#include "bake/photo/photo_view.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <optional>

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

// An image of the camera's size, or of its aspect at another size (then
// `scaled`).
bool fits_camera(const CameraProjector& camera, int width, int height, bool& scaled) {
  const int w = camera.spec().width, h = camera.spec().height;
  scaled = false;
  if (width == w && height == h) return true;
  const long long cross = static_cast<long long>(width) * h - static_cast<long long>(height) * w;
  scaled = width > 0 && height > 0 && std::llabs(cross) < std::max(w, h);
  return scaled;
}

// A photo of the camera's size, or of its aspect at another size (then
// `scaled`); else an error naming both sizes.
Status check_photo_size(const Photo& photo, const PhotoImage& image, bool& scaled) {
  const int w = photo.camera.spec().width, h = photo.camera.spec().height;
  if (fits_camera(photo.camera, image.width, image.height, scaled)) return ok_status();
  return make_error(ErrorCode::kParse, photo.path.string() + ": the photo of " + photo.name +
                                           " is " + std::to_string(image.width) + " x " +
                                           std::to_string(image.height) + ", its camera " +
                                           std::to_string(w) + " x " + std::to_string(h) +
                                           " (neither that size nor that aspect)");
}

// Multiplies the photo's alpha (clamped to [0, 1]) by its mask file's,
// records stats.masked and masked_share.
Status apply_mask(const Photo& photo, PhotoImage& image, PhotoCameraStats& stats) {
  const std::size_t n = static_cast<std::size_t>(image.width) * image.height;
  std::optional<Image> mask;
  if (!photo.mask.empty()) {
    Expected<Image> read = read_mask(photo);
    if (!read) return read.error();
    if (read->width != image.width || read->height != image.height) {
      return make_error(ErrorCode::kParse,
                        "the mask of camera " + photo.name + ": " + photo.mask.string() + " is " +
                            std::to_string(read->width) + " x " + std::to_string(read->height) +
                            ", its photo " + photo.path.string() + " " +
                            std::to_string(image.width) + " x " + std::to_string(image.height) +
                            " (a mask must have its photo's size)");
    }
    mask = std::move(read).value();
  }
  std::vector<std::array<std::size_t, 2>> counts(block_count(n, 1 << 16), {0, 0});
  parallel_for_blocks(n, 1 << 16, [&](std::size_t block, std::size_t b, std::size_t e) {
    std::size_t below = 0, zero = 0;
    for (std::size_t i = b; i < e; ++i) {
      float& a = image.pixels[4 * i + 3];
      a = a >= 1 ? 1.f : a > 0 ? a : 0.f;  // NaN: 0
      if (mask) a *= mask->pixels[4 * i + 3];
      below += a < 1;
      zero += a == 0;
    }
    counts[block] = {below, zero};
  });
  std::size_t below = 0, zero = 0;
  for (const auto& c : counts) below += c[0], zero += c[1];
  stats.masked = below > 0;
  stats.masked_share = n ? static_cast<double>(zero) / static_cast<double>(n) : 0;
  return ok_status();
}

}  // namespace

Status check_mask_size(const Photo& photo, const PhotoImage& mask, bool& scaled) {
  if (fits_camera(photo.camera, mask.width, mask.height, scaled)) return ok_status();
  return make_error(ErrorCode::kParse,
                    "the mask of camera " + photo.name + ": " + photo.mask.string() + " is " +
                        std::to_string(mask.width) + " x " + std::to_string(mask.height) +
                        ", its camera " + std::to_string(photo.camera.spec().width) + " x " +
                        std::to_string(photo.camera.spec().height) +
                        " (neither that size nor that aspect)");
}

Expected<Image> read_mask(const Photo& photo) {
  Expected<Image> mask = read_image(photo.mask);
  if (!mask) {
    return make_error(mask.error().code,
                      "the mask of camera " + photo.name + ": " + mask.error().message);
  }
  const std::size_t n = static_cast<std::size_t>(mask->width) * mask->height;
  parallel_for_chunks(n, 1 << 16, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const float* p = &mask->pixels[4 * i];
      mask->pixels[4 * i + 3] = p[0] > 0 || p[1] > 0 || p[2] > 0 ? 1.f : 0.f;
    }
  });
  return mask;
}

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

namespace {

// prefetching_reader's state: the one read ahead, if any.
struct Prefetch {
  PhotoReader read;
  const std::vector<Photo>* photos = nullptr;
  BackgroundTask task;
  std::size_t ahead = 0;  // the index being read in the background (valid when `started`)
  bool started = false;
  std::optional<Expected<PhotoImage>> image;

  // A read still running writes `image`: wait for it before any member goes
  // (a pass that stops early, on an error, leaves one running).
  ~Prefetch() { task.wait(); }

  Expected<PhotoImage> operator()(const Photo& photo) {
    const std::vector<Photo>& list = *photos;
    const std::size_t i = static_cast<std::size_t>(&photo - list.data());
    const bool in_list = &photo >= list.data() && i < list.size();
    std::optional<Expected<PhotoImage>> got;
    if (started) {
      task.wait();
      started = false;
      if (in_list && ahead == i) got = std::move(image);
      image.reset();
    }
    if (!got) got = read(photo);
    if (in_list && i + 1 < list.size()) {
      ahead = i + 1;
      started = true;
      task.run([this, next = &list[i + 1]] { image = read(*next); });
    }
    return std::move(*got);
  }
};

}  // namespace

PhotoReader prefetching_reader(const PhotoReader& read, const std::vector<Photo>& photos) {
  auto state = std::make_shared<Prefetch>();
  state->read = read;
  state->photos = &photos;
  return [state](const Photo& photo) { return (*state)(photo); };
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
  if (Status s = apply_mask(photo, *image, stats); !s) return s.error();
  stats.photo_width = image->width, stats.photo_height = image->height;
  const CameraProjector& camera = photo.camera;
  if (stats.scaled) {
    warnings.push_back(photo.name + ": the photo is " + std::to_string(image->width) + " x " +
                       std::to_string(image->height) + ", its camera " +
                       std::to_string(camera.spec().width) + " x " +
                       std::to_string(camera.spec().height) + "; sampled at the camera's (u, v)");
  }
  const bool srgb = image->color_space == ColorSpace::kSrgb;
  if (srgb || stats.masked) {
    parallel_for_chunks(image->pixels.size() / 4, 1 << 16, [&](std::size_t b, std::size_t e) {
      for (std::size_t i = b; i < e; ++i) {
        float* px = &image->pixels[4 * i];
        for (int ch = 0; ch < 3; ++ch) {
          if (srgb) px[ch] = srgb_to_linear(px[ch]);
          if (stats.masked) px[ch] *= px[3];  // premultiplied, in linear light
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
