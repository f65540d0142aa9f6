#include "bake/engine/photo_vertex.h"

#include <utility>

#include "bake/engine/layers_bake.h"
#include "bake/util/timing.h"

namespace texbake {

Expected<PhotoBakeResult> bake_vertex_from_photos(const MeshData& mesh,
                                                  const std::vector<Photo>& photos,
                                                  const PhotoBakeOptions& options,
                                                  const PhotoReader& reader) {
  Expected<PhotoBakeResult> blended = blend_vertex_photos(mesh, photos, options, reader);
  if (!blended) return blended.error();
  PhotoBakeResult& result = *blended;
  const auto start = Clock::now();
  PhotoLayerPoints points;
  points.vertices = std::move(result.points);
  LayerInput layer;
  layer.name = "photos";
  layer.photos = &points;
  LayersBakeOptions stack;
  stack.alpha = ResultAlpha::kImage;
  stack.occluded = options.occluded;
  stack.occluded_color = options.occluded_color;
  Expected<LayersVertexStage> stage = bake_vertex_layers_sample(mesh, {layer}, stack);
  if (!stage) return stage.error();
  // The blend is read: kept for the caller, or freed before the fill's solve.
  if (options.keep_points) {
    result.points = std::move(points.vertices);
  } else {
    result.points = {};
    points.vertices = {};
  }
  Expected<LayersBakeResult> resolved = bake_vertex_layers_finish(mesh, std::move(*stage));
  if (!resolved) return resolved.error();
  result.colors = std::move(resolved->colors);
  result.filled = resolved->filled;
  result.unfilled = resolved->unfilled;
  result.seconds_fill = seconds_since(start);
  return std::move(result);
}

}  // namespace texbake
