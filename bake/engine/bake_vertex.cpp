// The proxy vertex bake: the engine's vertex target (bake/engine/layers_bake.h)
// over a one-layer stack under ResultAlpha::kImage, the single projection's
// rules (SPEC section 4). tests/bake/engine/bake_vertex_test.cpp checks it
// against independent references.
#include "bake/engine/bake_vertex.h"

#include <utility>

#include "bake/engine/layers_bake.h"
#include "bake/util/timing.h"

namespace texbake {

Expected<VertexBakeStage> bake_vertex_sample(const MeshData& mesh, const ImageView& image,
                                             const Proxy& proxy, const VertexBakeOptions& options,
                                             Progress* progress, const EmbreeScene* shared_scene) {
  LayersBakeOptions stack;
  stack.alpha = ResultAlpha::kImage;
  stack.occluded = options.occluded;
  stack.occluded_color = options.occluded_color;
  stack.scene = shared_scene;
  Expected<LayersVertexStage> sampled = bake_vertex_layers_sample(
      mesh, {single_projection_layer(image, proxy, options)}, stack, progress);
  if (!sampled) return sampled.error();
  LayersBakeResult& layers = sampled->result;
  const LayerStats& layer = layers.layers.front();
  VertexBakeStage stage;
  VertexBakeResult& result = stage.result;
  result.colors = std::move(layers.colors);
  VertexBakeCounts& c = result.counts;
  c.vertices = mesh.positions.size();
  c.triangles = mesh.triangles.size();
  c.samples = layer.lookups;
  c.occluded = layer.hidden;
  c.undefined = layer.unmapped;
  c.outside = layer.outside;
  c.filled = layers.filled;
  c.unfilled = layers.unfilled;
  result.timings.scene_build = layers.seconds_scene;
  result.timings.bake = layers.seconds_layers;
  result.timings.fill = layers.seconds_fill;
  stage.plan = std::move(sampled->plan);
  return stage;
}

Expected<VertexBakeResult> bake_vertex_finish(const MeshData& mesh, VertexBakeStage stage) {
  const auto start = Clock::now();
  VertexBakeResult& result = stage.result;
  Expected<FillResult> filled = finish_resolve(mesh, result.colors, std::move(stage.plan));
  if (!filled) return filled.error();
  result.timings.fill += seconds_since(start);
  return std::move(result);
}

Expected<VertexBakeResult> bake_vertex(const MeshData& mesh, const ImageView& image,
                                       const Proxy& proxy, const VertexBakeOptions& options,
                                       Progress* progress) {
  Expected<VertexBakeStage> stage = bake_vertex_sample(mesh, image, proxy, options, progress);
  if (!stage) return stage.error();
  return bake_vertex_finish(mesh, std::move(stage).value());
}

}  // namespace texbake
