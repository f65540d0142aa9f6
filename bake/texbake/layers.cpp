// read_layers and bake_vertex_colors_from_layers: mesh_io's layers file and
// images, and bake/layers behind the API's conventions.
#include "bake/texbake/run.h"
#include "bake/util/progress.h"
#include "bake/util/timing.h"
#include "mesh_io/image_io.h"
#include "mesh_io/layers_json.h"
#include "texbake/texbake.h"

namespace texbake {

Expected<LayersSpec> read_layers(const std::filesystem::path& layers_file) {
  return read_layers_file(layers_file);
}

Expected<LayerColors> bake_vertex_colors_from_layers(const MeshData& mesh, const LayersSpec& spec,
                                                     const LayersBakeOptions& options,
                                                     const RunOptions& run) {
  const auto start = Clock::now();
  if (spec.layers.empty()) return make_error(ErrorCode::kInvalidArgument, "no layers to bake");
  if (Status s = check_triangles(mesh); !s) return s.error();
  for (std::size_t i = 0; i < spec.layers.size(); ++i) {
    if (!spec.layers[i].cameras.empty()) {
      return make_error(
          ErrorCode::kUnsupported,
          "layers[" + std::to_string(i) +
              "]: a \"cameras\" layer (several photos) "
              "is not supported yet; a single camera as \"proxy\" or \"proxy_file\" is");
    }
  }
  Progress progress(run.progress);
  return detail::run_call<LayerColors>(run, [&]() -> Expected<LayerColors> {
    progress.start("layers", spec.layers.size());
    // The images stay alive for the bake: every layer's texture and mask.
    std::vector<Image> images;
    images.reserve(2 * spec.layers.size());
    std::vector<LayerInput> inputs;
    for (const LayerSpec& l : spec.layers) {
      if (progress.cancelled()) return cancelled_error();
      LayerInput in;
      in.name = l.texture.filename().string();
      in.projector = *l.projector;
      Expected<Image> texture = read_image(l.texture);
      if (!texture) return texture.error();
      images.push_back(std::move(texture).value());
      in.texture = images.back().view();
      in.texture_has_alpha = images.back().has_alpha;
      if (!l.mask.empty()) {
        Expected<Image> mask = read_image(l.mask);
        if (!mask) return mask.error();
        images.push_back(std::move(mask).value());
        in.mask = images.back().view();
        in.mask_has_alpha = images.back().has_alpha;
      }
      in.opacity = l.opacity;
      in.mode = l.mode;
      in.angle_fade = l.angle_fade;
      in.visibility = l.visibility;
      in.outside = l.outside;
      in.outside_color = l.outside_color;
      inputs.push_back(std::move(in));
      progress.advance(1);
    }
    Expected<LayersBakeResult> baked = bake_vertex_layers(mesh, inputs, options);
    if (!baked) return detail::as_input(baked.error());
    progress.finish();
    LayerColors out;
    out.colors = std::move(baked->colors);
    out.layers = std::move(baked->layers);
    Counts& c = out.stats.counts;
    c = detail::mesh_counts(mesh);
    c.samples = mesh.positions.size() * spec.layers.size();
    c.occluded = baked->uncovered;
    c.filled = baked->filled;
    Timings& t = out.stats.timings;
    t.scene_build = baked->seconds_scene;
    t.bake = baked->seconds_layers;
    t.fill = baked->seconds_fill;
    t.total = seconds_since(start);
    return out;
  });
}

}  // namespace texbake
