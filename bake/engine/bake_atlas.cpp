// The proxy atlas bake: the engine's atlas target (bake/engine/layers_bake.h)
// over a one-layer stack under ResultAlpha::kImage, the single projection's
// rules (SPEC section 4). tests/bake/atlas/atlas_bake_test.cpp and
// atlas_stream_test.cpp check it against independent references.
#include "bake/engine/bake_atlas.h"

#include <utility>

#include "bake/engine/layers_bake.h"

namespace texbake {

Expected<AtlasBakeResult> bake_atlas(const MeshData& mesh, const ImageView& image,
                                     const Proxy& proxy, const AtlasBakeOptions& options,
                                     Progress* progress) {
  LayersAtlasOptions stack =
      single_projection_atlas(options.size, options.samples, options.padding,
                              options.shading.occluded, options.shading.occluded_color);
  stack.resolve_overlaps = options.resolve_overlaps;
  // The atlas's lookup is bilinear or EWA (the area filter is the vertex
  // target's: shading.samples is not used here).
  VertexBakeOptions shading = options.shading;
  if (shading.filter != VertexFilter::kEwa) shading.filter = VertexFilter::kBilinear;
  Expected<LayersAtlasResult> baked =
      bake_atlas_layers(mesh, {single_projection_layer(image, proxy, shading)}, stack, progress);
  if (!baked) return baked.error();
  const LayerStats& layer = baked->layers.front();
  AtlasBakeResult result;
  result.atlas = std::move(baked->atlas);
  result.atlas.has_alpha = false;  // the image's alpha is a colour channel, not a coverage
  result.baked = std::move(baked->baked);
  AtlasBakeCounts& c = result.counts;
  c.texels = baked->texels;
  c.samples = baked->samples;
  c.border_samples = baked->border_samples;
  c.occluded = layer.hidden;
  c.undefined = layer.unmapped;
  c.outside = layer.outside;
  c.padded = baked->padded;
  AtlasBakeTimings& t = result.timings;
  t.rasterize = baked->seconds_raster;
  t.scene_build = baked->seconds_scene;
  t.sample = baked->seconds_layers;
  t.fill = baked->seconds_fill;
  t.pad = baked->seconds_pad;
  return result;
}

}  // namespace texbake
