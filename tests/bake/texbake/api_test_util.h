// Small inputs shared by the API tests.
#pragma once

#include <optional>

#include "texbake/texbake.h"

namespace texbake::test {

// A w x h image of one colour.
inline Image constant_image(int w, int h, Rgba c) {
  Image img;
  img.width = w;
  img.height = h;
  img.pixels.resize(static_cast<std::size_t>(w) * h * 4);
  for (std::size_t i = 0; i < img.pixels.size(); ++i) img.pixels[i] = c[i % 4];
  return img;
}

// The unit sphere at the origin, pole +Z.
inline Proxy unit_sphere_proxy() {
  return make_proxy(SphereParams{{0, 0, 0}, 1, {0, 0, 1}, std::nullopt}).value();
}

}  // namespace texbake::test
