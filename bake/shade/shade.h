// The shading rule (SPEC sections 1 to 3): how a point that a proxy mapped to
// (u, v) becomes a colour, for a single proxy and image: the proxy vertex
// bake, the proxy atlas bake and the render's ground truth (ProjectionSource)
// call it, so a render shows exactly what such a bake computes. The layers
// bake (bake/engine/layers_bake.h) looks its proxy and camera layers' images up through
// this rule's lookup (filters, wraps) in each layer's working space; the
// photo bakes (bake/photo) still sample bilinearly in linear light with a
// lookup of their own.
//
// The rule, for one MapResult m:
//  - m.status == kUndefined (no mapping): no colour.
//  - kOutside, unless the plane tiles (--wrap repeat, then nothing is
//    outside): --outside clamp samples the image with the wrap rules below
//    (the edge texel), --outside R,G,B[,A] gives that constant.
//  - kOk: the image's bilinear sample (mapping/sample.h) at m.uv; under
//    --filter ewa (ShadeRule::mip set) the EWA lookup over the image's MIP
//    pyramid (mapping/mipmap.h) with the sample's footprint instead, for
//    kOutside under --outside clamp too.
//  Wrap rules: u wraps (periodic) for sphere, cylinder, cone and disk,
//  everything else clamps; the plane with --wrap repeat tiles u and v.
//  Colours are in the working encoding: the image's stored values for an
//  sRGB-encoded image, or linear light with --linear (the image is linearised
//  once per job) or for a linear image (ImageView::color_space kLinear, used
//  as it is: already linear, --linear changes nothing). Constants are given
//  sRGB-encoded and converted like the image; callers average in the working
//  encoding and convert back with stored(), so a bake's result is always
//  sRGB-encoded (issue #11: for an sRGB image without --linear every value
//  is exactly what it was before colour spaces were read).
//  Occlusion, where it is decided per sample (the atlas), is part of the rule
//  too: see ShadeRule::shade().
//
// Hot loops copy one ShadeRule per job and call its inline functions per
// sample: no allocation, no virtual call (dispatch on the proxy stays one
// std::visit per chunk in the caller).
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "bake/shade/options.h"
#include "mapping/image_view.h"
#include "mapping/mipmap.h"
#include "mapping/proxy.h"
#include "mapping/sample.h"

namespace texbake {

// What the rule made of one point.
enum class Shade : uint8_t {
  kImage,     // inside the domain: the image's bilinear sample
  kOutside,   // outside the proxy's (u, v) domain: the --outside constant or the clamped sample
  kConstant,  // occluded or without a mapping under --occluded R,G,B: occluded_color
  kFill,  // the occlusion fill decides (--occluded fill; unmapped points unless --occluded R,G,B)
  kNone,  // no mapping and no occlusion handling asked (project() only): no colour
};

struct Shaded {
  Rgba color{};  // working encoding; meaningful for kImage, kOutside and kConstant
  Shade kind = Shade::kNone;
};

struct ShadeRule {
  ImageView image;  // in the working encoding (a linear copy with --linear)
  WrapMode wrap_u = WrapMode::kClamp, wrap_v = WrapMode::kClamp;
  bool has_outside = true;        // false: a plane with --wrap repeat (tiles, nothing outside)
  bool outside_constant = false;  // --outside R,G,B[,A] (else clamp)
  Rgba outside_color{};           // working encoding
  OccludedMode occluded = OccludedMode::kFill;
  Rgba occluded_color{};  // working encoding
  bool linear = false;    // the working encoding is linear light (image.color_space kLinear)
  // --filter ewa: the pyramid of `image` (same pixels, level 0 is `image`);
  // null: the bilinear lookup (the footprint is ignored). Not owned.
  const MipPyramid* mip = nullptr;
  double max_anisotropy = kDefaultMaxAnisotropy;

  // The image at uv: EWA with `footprint` when mip is set, else bilinear.
  Rgba lookup(UV uv, const UvFootprint& footprint) const {
    if (mip) return sample_ewa(*mip, uv, footprint, wrap_u, wrap_v, max_anisotropy);
    return sample_bilinear(image, uv, wrap_u, wrap_v);
  }

  // The projected colour of a mapped point, no visibility involved: kImage,
  // kOutside, or kNone when m has no mapping. `footprint` (in (u, v)) is used
  // by the EWA lookup only.
  Shaded project(const MapResult& m, const UvFootprint& footprint = {}) const {
    if (m.status == MapStatus::kUndefined) return {{}, Shade::kNone};
    if (m.status == MapStatus::kOutside && has_outside) {
      if (outside_constant) return {outside_color, Shade::kOutside};
      return {lookup(m.uv, footprint), Shade::kOutside};
    }
    return {lookup(m.uv, footprint), Shade::kImage};
  }

  // True when the occlusion fill colours this sample (SPEC section 3):
  // --occluded fill for an occluded or unmapped sample, --occluded project
  // for an unmapped one (it has nothing to project); never with --occluded R,G,B.
  bool needs_fill(const MapResult& m, bool visible) const {
    if (occluded == OccludedMode::kColor) return false;
    return m.status == MapStatus::kUndefined || (!visible && occluded == OccludedMode::kFill);
  }

  // A sample whose visibility is known (the ray towards the projector is
  // free: visible): kFill when needs_fill(); kConstant for an occluded or
  // unmapped sample under --occluded R,G,B; otherwise project() (occluded
  // samples under --occluded project take their projected colour). Never kNone.
  Shaded shade(const MapResult& m, bool visible, const UvFootprint& footprint = {}) const {
    if (needs_fill(m, visible)) return {{}, Shade::kFill};
    if (occluded == OccludedMode::kColor && (m.status == MapStatus::kUndefined || !visible)) {
      return {occluded_color, Shade::kConstant};
    }
    return project(m, footprint);
  }

  // A colour of the working encoding sRGB-encoded, and back (the sRGB curves
  // on R, G, B with `linear`; alpha is never converted).
  Rgba stored(Rgba working) const { return linear ? linear_to_srgb(working) : working; }
  Rgba working(Rgba stored) const { return linear ? srgb_to_linear(stored) : stored; }
};

// True when a job samples `image` in linear light: --linear (`linear`), or
// an image whose values are linear already.
inline bool works_in_linear(const ImageView& image, bool linear) {
  return linear || image.color_space == ColorSpace::kLinear;
}

// The image in the working encoding: for an sRGB-encoded image with
// `linear`, a copy whose R, G, B went through srgb_to_linear (alpha
// unchanged; view.color_space kLinear), computed once, in parallel;
// otherwise the image itself (a linear image is used as it is). Movable
// (view stays valid), not copyable.
struct WorkingImage {
  std::vector<float> pixels;  // the linear copy (empty without `linear`)
  ImageView view;             // what to sample: `pixels`, or the input image

  WorkingImage() = default;
  WorkingImage(WorkingImage&&) = default;
  WorkingImage& operator=(WorkingImage&&) = default;
  WorkingImage(const WorkingImage&) = delete;
  WorkingImage& operator=(const WorkingImage&) = delete;
};
// Precondition: image has width * height pixels of data (may be 0 x 0).
WorkingImage working_image(const ImageView& image, bool linear);

// The MIP pyramid's row runner on the bake's threads (parallel_for_chunks):
// MipPyramid(view, pyramid_rows) for --filter ewa.
void pyramid_rows(std::size_t count, const std::function<void(std::size_t, std::size_t)>& body);

// The rule of one job: sampling `image` (already in the working encoding,
// see working_image: linear when its color_space is kLinear) through `proxy`
// with the shading fields of `options` (outside, outside_color, occluded,
// occluded_color, plane_wrap; filter, samples and visibility are not the
// rule's; `linear` was working_image's). The constant colours, sRGB-encoded,
// are converted to the working encoding. The rule views `image`: keep its
// pixels alive as long as the rule.
ShadeRule make_shade_rule(const ImageView& image, const Proxy& proxy,
                          const VertexBakeOptions& options);
// The same for a camera's photo (mapping/camera.h): both axes clamp (a
// photo does not repeat), and everything outside the photo (behind the
// camera, past the distortion's turning point, off the photo) is kOutside.
ShadeRule make_camera_shade_rule(const ImageView& image, const VertexBakeOptions& options);

}  // namespace texbake
