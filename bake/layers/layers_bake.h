// Layers (SPEC section 10): several projections composited over a base,
// bottom first, per sample in linear light.
//
// Per sample (a vertex here) and layer, with d = d(P) the direction towards
// the layer's projector and n the smooth vertex normal:
//   a = opacity x image alpha x mask x angle fade x seen
//  - the image is sampled bilinearly at the projector's (u, v) with its wrap
//    rules (mapping/sample.h) as premultiplied linear RGBA, so a label's
//    transparent border does not bleed dark fringes into its colour; the
//    layer colour L is the straight colour of that sample;
//  - mask: a second image through the same (u, v): its alpha when it has
//    an alpha channel, else its first channel (a grey image), as stored;
//  - angle fade [a0, a1]: 1 up to a0 degrees between n and d, 0 from a1,
//    linear between; none: 1;
//  - seen: visibility "first": the ray towards an analytic proxy (to
//    infinity, bake/trace/visibility.h) or the segment to a camera's centre
//    is free, and for a camera n . d > 0; "all": 1. Points the projector does
//    not map (kUndefined, behind a camera) are not seen. Points outside the
//    (u, v) domain follow the layer's `outside`: transparent (a = 0), clamp
//    (the clamped lookup, with its alpha and mask) or a constant colour (its
//    alpha; mask 1).
// Compositing, B and alpha the running straight colour and coverage (base
// "none": B = 0, alpha 0; a colour: its linear RGB and alpha; "mesh": the
// mesh's vertex colours, linearised, and their alpha):
//   over      B' = (a L + (1 - a) alpha B) / alpha'   (= a L + (1 - a) B on an opaque base)
//   multiply  B' = B (1 - a + a L)
//   add       B' = B + a L
//   replace   B' = L where a > 0
//   alpha' = 1 - (1 - alpha)(1 - a) for every mode (the coverage).
// Samples with coverage 0 (no base colour, no layer) follow `occluded`
// (OccludedMode::kFill: the harmonic fill of bake/vertex/occlusion_fill.h
// over their RGB, alpha staying 0; kColor: the constant's RGB, alpha 0;
// kProject acts as kFill). Results do not depend on the thread count.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bake/shade/options.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/projector.h"
#include "mesh_io/layers_json.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// One layer, ready to bake: its projector and images (any colour space:
// sampled in linear light). The mask view is empty (data null) when none.
struct LayerInput {
  std::string name;  // for the report (e.g. the texture's file name)
  Projector projector;
  ImageView texture;
  bool texture_has_alpha = true;
  ImageView mask;
  bool mask_has_alpha = false;  // take the mask's alpha (else its first channel)
  double opacity = 1;
  LayerMode mode = LayerMode::kOver;
  std::optional<std::array<double, 2>> angle_fade;  // degrees
  LayerVisibility visibility = LayerVisibility::kFirst;
  LayerOutside outside = LayerOutside::kTransparent;
  Rgba outside_color{0, 0, 0, 0};  // sRGB-encoded, straight alpha
};

struct LayersBakeOptions {
  LayerBase base = LayerBase::kNone;
  Rgba base_color{0, 0, 0, 0};  // sRGB-encoded, straight alpha (LayerBase::kColor)
  OccludedMode occluded = OccludedMode::kFill;
  Rgba occluded_color{0, 0, 0, 1};  // sRGB-encoded; its RGB is used, alpha stays 0
};

struct LayerStats {
  std::string name;
  std::size_t in_domain = 0;  // samples the projector maps inside its (u, v) domain
  std::size_t visible = 0;    // of the mapped samples, those it sees
  std::size_t blended = 0;    // samples with a > 0
  double mean_alpha = 0;      // mean a over all samples
};

struct LayersBakeResult {
  std::vector<Rgba> colors;  // per vertex, sRGB-encoded RGB, straight alpha = coverage
  std::vector<LayerStats> layers;
  std::size_t uncovered = 0;  // vertices with coverage 0
  std::size_t filled = 0;     // of those, coloured by the fill
  double seconds_scene = 0, seconds_layers = 0, seconds_fill = 0;
};

// Errors: kInvalidArgument (no layers; base "mesh" on a mesh without vertex
// colours; an empty texture), kInternal (Embree, the fill).
Expected<LayersBakeResult> bake_vertex_layers(const MeshData& mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersBakeOptions& options);

}  // namespace texbake
