// The two bake calls over a Bake (texbake.h, "One bake description, two
// targets"), and the per-kind calls as conveniences over them.
#include <type_traits>
#include <utility>
#include <variant>

#include "bake/texbake/run.h"

namespace texbake {

Expected<VertexColors> bake_vertex_colors(const MeshData& mesh, const Bake& bake,
                                          const RunOptions& run) {
  return std::visit(
      [&](const auto& p) -> Expected<VertexColors> {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, ImageProjection>) {
          return detail::image_vertex_colors(mesh, p.image, p.proxy, p.options, run);
        } else if constexpr (std::is_same_v<P, PhotoProjection>) {
          return detail::photo_vertex_colors(mesh, p.photos, p.options, run);
        } else {
          return detail::layer_vertex_colors(mesh, p.spec, p.options, run);
        }
      },
      bake);
}

Expected<BakedAtlas> bake_atlas_texture(const MeshData& mesh, const Bake& bake,
                                        const AtlasOptions& atlas, const RunOptions& run) {
  return std::visit(
      [&](const auto& p) -> Expected<BakedAtlas> {
        using P = std::decay_t<decltype(p)>;
        if constexpr (std::is_same_v<P, ImageProjection>) {
          AtlasOptions options = atlas;
          options.bake.shading = p.options;
          Expected<Atlas> baked = detail::image_atlas_texture(mesh, p.image, p.proxy, options, run);
          if (!baked) return baked.error();
          return BakedAtlas{std::move(baked).value(), {}, {}, {}, {}};
        } else if constexpr (std::is_same_v<P, PhotoProjection>) {
          return detail::photo_atlas_texture(mesh, p.photos, p.options, atlas, run);
        } else {
          return detail::layer_atlas_texture(mesh, p.spec, p.options, atlas, run);
        }
      },
      bake);
}

// ---- The per-kind conveniences ----------------------------------------------

Expected<VertexColors> bake_vertex_colors(const MeshData& mesh, const ImageView& image,
                                          const Proxy& proxy, const VertexBakeOptions& options,
                                          const RunOptions& run) {
  return bake_vertex_colors(mesh, Bake{ImageProjection{image, proxy, options}}, run);
}

Expected<Atlas> bake_atlas_texture(const MeshData& mesh, const ImageView& image, const Proxy& proxy,
                                   const AtlasOptions& options, const RunOptions& run) {
  Expected<BakedAtlas> baked = bake_atlas_texture(
      mesh, Bake{ImageProjection{image, proxy, options.bake.shading}}, options, run);
  if (!baked) return baked.error();
  return std::move(baked->atlas);
}

Expected<PhotoColors> bake_vertex_colors_from_photos(const MeshData& mesh,
                                                     const std::vector<Photo>& photos,
                                                     const PhotoBakeOptions& options,
                                                     const RunOptions& run) {
  return bake_vertex_colors(mesh, Bake{PhotoProjection{photos, options}}, run);
}

Expected<PhotoAtlas> bake_atlas_texture_from_photos(const MeshData& mesh,
                                                    const std::vector<Photo>& photos,
                                                    const PhotoBakeOptions& options,
                                                    const AtlasOptions& atlas,
                                                    const RunOptions& run) {
  return bake_atlas_texture(mesh, Bake{PhotoProjection{photos, options}}, atlas, run);
}

Expected<LayerColors> bake_vertex_colors_from_layers(const MeshData& mesh, const LayersSpec& spec,
                                                     const LayersBakeOptions& options,
                                                     const RunOptions& run) {
  return bake_vertex_colors(mesh, Bake{LayersProjection{spec, options}}, run);
}

Expected<LayerAtlas> bake_atlas_texture_from_layers(const MeshData& mesh, const LayersSpec& spec,
                                                    const LayersBakeOptions& options,
                                                    const AtlasOptions& atlas,
                                                    const RunOptions& run) {
  return bake_atlas_texture(mesh, Bake{LayersProjection{spec, options}}, atlas, run);
}

}  // namespace texbake
