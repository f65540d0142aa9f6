// Options of texbake's baking stages, one struct per stage (xatlas-style:
// every field defaulted, units and the meaning of special values stated).
// Only the CLI sees strings; everything here is an enum or a number.
#pragma once

#include <array>

#include "mapping/image_view.h"
#include "mapping/proxy.h"

namespace texbake {

// How a colour is taken from the image (SPEC sections 4 and 13). The vertex
// target knows all three; the atlas bilinear (kBilinear or kArea: the
// bilinear lookup per supersample, as always) and kEwa.
enum class VertexFilter {
  kBilinear,  // one bilinear sample at the vertex
  kArea,      // average of `samples` bilinear samples over the vertex's share of
              // its adjacent triangles (area-weighted, stratified, deterministic)
  kEwa,       // one footprint-filtered lookup (mapping/mipmap.h sample_ewa) whose
              // footprint is the inverse mapping's Jacobian (mapping/derivatives.h)
              // times the sample's footprint on the surface (bake/shade/footprint.h):
              // the vertex's share of its triangles, or the atlas supersample's cell
};

// SPEC section 3.
enum class Visibility {
  kFirst,  // a point is coloured only if the ray towards the projector is free
  kAll,    // no test: every point takes the projected colour
};

// What occluded points get (SPEC section 3).
enum class OccludedMode {
  kFill,     // smooth inpainting from visible neighbours over the mesh
  kProject,  // the projected colour anyway
  kColor,    // a constant colour (VertexBakeOptions::occluded_color)
};

// Points outside the proxy's (u, v) domain (SPEC section 2).
enum class OutsideMode {
  kClamp,  // the sampler clamps to the edge texel (v; u too for quad/plane)
  kColor,  // a constant colour (VertexBakeOptions::outside_color)
};

struct VertexBakeOptions {
  VertexFilter filter = VertexFilter::kArea;
  // Bilinear samples per vertex for VertexFilter::kArea (>= 1). Ignored by
  // kBilinear and kEwa (one lookup per vertex).
  int samples = 16;

  Visibility visibility = Visibility::kFirst;
  OccludedMode occluded = OccludedMode::kFill;
  // RGBA in [0, 1], sRGB-encoded whatever the image's colour space (issue
  // #11): an occluded vertex, or an atlas texel whose samples are all
  // occluded, gets exactly this colour; a partly occluded texel averages it
  // with its other samples in the working encoding.
  Rgba occluded_color{0, 0, 0, 1};

  OutsideMode outside = OutsideMode::kClamp;
  // RGBA in [0, 1], sRGB-encoded; in a linear working encoding (`linear`, or
  // a linear image) it is linearised before it enters an average.
  Rgba outside_color{0, 0, 0, 1};

  // SPEC section 1 --linear: convert the image's RGB from sRGB to linear once,
  // average in linear, convert each vertex's result back to sRGB. Alpha is
  // never converted. An image whose ImageView::color_space is kLinear is
  // always sampled in linear light (this flag changes nothing for it); the
  // result is sRGB-encoded either way.
  bool linear = false;

  // The plane proxy's texture wrap (SPEC section 2 --wrap): kClamp (default)
  // clamps u and v to the edge texel; kRepeat tiles the image in u and v, so no
  // plane point is outside. Ignored by the other proxies, whose wrap the SPEC fixes.
  WrapMode plane_wrap = WrapMode::kClamp;
};

}  // namespace texbake
