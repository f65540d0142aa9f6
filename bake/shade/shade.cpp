// The shading rule's per-job set-up (the per-sample part is inline in shade.h).
#include "bake/shade/shade.h"

#include <cstddef>
#include <variant>

#include "bake/util/parallel.h"
#include "mapping/tiled_image.h"

namespace texbake {

WorkingImage working_image(const ImageView& image, bool linear) {
  WorkingImage out;
  out.view = image;
  if (!linear || image.color_space == ColorSpace::kLinear) return out;
  out.view.color_space = ColorSpace::kLinear;
  // The file's MIP levels (ImageView::mip_levels) average the stored
  // sRGB values, not linear light: the pyramid is built from this view.
  out.view.mip_levels = nullptr;
  out.view.mip_level_count = 0;
  if (!image.data) {
    // A tiled image is linearised as its tiles are loaded (the same
    // transform_texel on the same values: the same bits as the copy).
    out.view.decode_srgb = true;
    return out;
  }
  const std::size_t pixels = static_cast<std::size_t>(image.width) * image.height;
  out.pixels.assign(image.data, image.data + pixels * 4);
  float* data = out.pixels.data();
  parallel_for_chunks(pixels, 16384, [data](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) transform_texel(&data[4 * i], true, false);
  });
  out.view.data = data;
  return out;
}

void pyramid_rows(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body) {
  parallel_for_chunks(count, 16, body);
}

namespace {

ShadeRule rule_with_wraps(const ImageView& image, WrapMode u, WrapMode v,
                          const VertexBakeOptions& options) {
  ShadeRule rule;
  rule.image = image;
  rule.linear = image.color_space == ColorSpace::kLinear;
  rule.wrap_u = u;
  rule.wrap_v = v;
  rule.outside_constant = options.outside == OutsideMode::kColor;
  rule.outside_color = rule.working(options.outside_color);
  rule.occluded = options.occluded;
  rule.occluded_color = rule.working(options.occluded_color);
  return rule;
}

}  // namespace

ShadeRule make_shade_rule(const ImageView& image, const Proxy& proxy,
                          const VertexBakeOptions& options) {
  ShadeRule rule = rule_with_wraps(image, wrap_u(proxy), wrap_v(proxy), options);
  if (std::holds_alternative<Plane>(proxy) && options.plane_wrap == WrapMode::kRepeat) {
    rule.wrap_u = rule.wrap_v = WrapMode::kRepeat;
    rule.has_outside = false;
  }
  return rule;
}

ShadeRule make_camera_shade_rule(const ImageView& image, const VertexBakeOptions& options) {
  return rule_with_wraps(image, WrapMode::kClamp, WrapMode::kClamp, options);
}

}  // namespace texbake
