// read_layers, bake_vertex_colors_from_layers and
// bake_atlas_texture_from_layers: mesh_io's layers file and
// images, and bake/engine/layers_bake.h behind the API's conventions.
#include <algorithm>
#include <optional>
#include <string>

#include "bake/texbake/run.h"
#include "bake/util/progress.h"
#include "bake/util/timing.h"
#include "mesh_io/image_io.h"
#include "mesh_io/layers_json.h"
#include "mesh_io/mesh_texture.h"
#include "texbake/texbake.h"

namespace texbake {

Expected<LayersSpec> read_layers(const std::filesystem::path& layers_file) {
  return read_layers_file(layers_file);
}

namespace {

// `atlas`: the atlas target, which has no vertex share to spread the area
// filter over (as bake --filter area, refused there too).
Status check_layer_specs(const LayersSpec& spec, bool atlas) {
  if (spec.layers.empty()) return make_error(ErrorCode::kInvalidArgument, "no layers to bake");
  for (std::size_t i = 0; i < spec.layers.size(); ++i) {
    if (atlas && spec.layers[i].filter == LayerFilter::kArea) {
      return make_error(ErrorCode::kInvalidArgument,
                        spec.source + ": layers[" + std::to_string(i) +
                            "].filter: \"area\" applies to the vertex target only (the atlas "
                            "takes \"bilinear\" or \"ewa\" per supersample)");
    }
  }
  return ok_status();
}

VertexFilter layer_filter(LayerFilter f) {
  switch (f) {
    case LayerFilter::kArea:
      return VertexFilter::kArea;
    case LayerFilter::kEwa:
      return VertexFilter::kEwa;
    case LayerFilter::kBilinear:
      break;
  }
  return VertexFilter::kBilinear;
}

// The layers file's base (spec.base, base_color) over the options'.
LayersBakeOptions with_spec_base(LayersBakeOptions options, const LayersSpec& spec) {
  options.base = spec.base;
  options.base_color = spec.base_color;
  return options;
}

// A "cameras" layer's name in the report: its model folder or list, with
// the folder above a numbered COLMAP model (sparse/0).
std::string cameras_name(const std::filesystem::path& cameras) {
  const std::string leaf = cameras.filename().string();
  const bool numbered = !leaf.empty() && std::all_of(leaf.begin(), leaf.end(),
                                                     [](char c) { return c >= '0' && c <= '9'; });
  const std::filesystem::path parent = cameras.parent_path().filename();
  return numbered && !parent.empty() ? (parent / leaf).generic_string() : leaf;
}

// The photos of every "cameras" layer (by layer index; empty for the
// others), with their "masks" (find_masks; its warnings into `warnings`;
// the camera files' notes into `notes`).
Expected<std::vector<std::vector<Photo>>> read_layer_cameras(const LayersSpec& spec,
                                                             std::vector<std::string>& warnings,
                                                             std::vector<std::string>& notes) {
  std::vector<std::vector<Photo>> photos(spec.layers.size());
  for (std::size_t i = 0; i < spec.layers.size(); ++i) {
    const LayerSpec& l = spec.layers[i];
    if (l.cameras.empty()) continue;
    const std::string key = "layers[" + std::to_string(i) + "]";
    Expected<std::vector<Photo>> read =
        read_cameras(l.cameras, l.images, PhotoFolder::kNeeded, &notes);
    if (!read) {
      Error e = read.error();
      e.message = key + ": " + e.message;
      return e;
    }
    if (!l.masks.empty()) {
      if (Status s = find_masks(*read, l.masks, key + ".masks", &warnings); !s) return s.error();
    }
    photos[i] = std::move(read).value();
  }
  return photos;
}

// The photo bake of a "cameras" layer: its blend per point, not filled.
PhotoBakeOptions layer_photo_options(const LayersBakeOptions& options) {
  PhotoBakeOptions o;
  o.strict_photos = options.strict_photos;
  o.consistency_warning = options.consistency_warning;
  o.keep_points = true;
  o.occluded = OccludedMode::kColor;  // unseen points are transparent: no fill needed
  return o;
}

// Bakes the photos of every "cameras" layer i with bake(i, photos, blend)
// into blends[i], points inputs[i] at it and records its seconds. Errors:
// bake's (as kInput), kCancelled.
template <class BakeFn>
Status bake_layer_photos(const std::vector<std::vector<Photo>>& photos, Progress& progress,
                         std::vector<LayerInput>& inputs, std::vector<PhotoLayerPoints>& blends,
                         std::vector<double>& seconds, BakeFn bake) {
  for (std::size_t i = 0; i < photos.size(); ++i) {
    if (photos[i].empty()) continue;
    if (progress.cancelled()) return cancelled_error();
    const auto start = Clock::now();
    if (Status s = bake(i, photos[i], blends[i]); !s) {
      Error e = detail::as_input(s.error());
      if (e.code != ErrorCode::kCancelled) {
        e.message = "layers[" + std::to_string(i) + "]: " + e.message;
      }
      return e;
    }
    inputs[i].photos = &blends[i];
    seconds[i] = seconds_since(start);
  }
  return ok_status();
}

void add_photo_warnings(std::size_t layer, const std::vector<std::string>& warnings,
                        std::vector<std::string>& out) {
  for (const std::string& w : warnings)
    out.push_back("layers[" + std::to_string(layer) + "]: " + w);
}

// Every layer's texture and mask, read into `images` (which must outlive
// the inputs), one progress step per layer; past `cache_mb` (a texture
// with its premultiplied linear copy, a mask alone) through the cache.
Expected<std::vector<LayerInput>> read_layer_inputs(const LayersSpec& spec, Progress& progress,
                                                    std::vector<Image>& images,
                                                    std::size_t cache_mb) {
  images.reserve(2 * spec.layers.size());
  std::vector<LayerInput> inputs;
  for (const LayerSpec& l : spec.layers) {
    if (progress.cancelled()) return cancelled_error();
    LayerInput in;
    in.opacity = l.opacity;
    in.mode = l.mode;
    in.angle_fade = l.angle_fade;
    in.visibility = l.visibility;
    in.outside = l.outside;
    in.outside_color = l.outside_color;
    in.filter = layer_filter(l.filter);
    in.samples = l.samples;
    in.plane_wrap = l.wrap;
    if (!l.cameras.empty()) {  // its photos are baked later (bake_layer_photos)
      in.name = cameras_name(l.cameras);
      inputs.push_back(std::move(in));
      progress.advance(1);
      continue;
    }
    in.name = l.texture.filename().string();
    in.projector = *l.projector;
    Expected<Image> texture = read_image(
        l.texture, texture_read_options(TextureColorSpace::kAuto, cache_mb, true, false));
    if (!texture) return texture.error();
    images.push_back(std::move(texture).value());
    in.texture = images.back().view();
    in.texture_has_alpha = images.back().has_alpha;
    if (!l.mask.empty()) {
      Expected<Image> mask = read_image(
          l.mask, texture_read_options(TextureColorSpace::kAuto, cache_mb, false, false));
      if (!mask) return mask.error();
      images.push_back(std::move(mask).value());
      in.mask = images.back().view();
      in.mask_has_alpha = images.back().has_alpha;
    }
    inputs.push_back(std::move(in));
    progress.advance(1);
  }
  return inputs;
}

// After the layers pass: the error of a texture or mask read through the
// cache whose reads failed (mapping/tiled_image.h), naming the file.
Status check_texels_read(const std::vector<Image>& images) {
  for (const Image& image : images) {
    if (Status s = texbake::check_texels_read(image.view()); !s) return s;
  }
  return ok_status();
}

}  // namespace

Expected<LayerColors> detail::layer_vertex_colors(const MeshData& mesh, const LayersSpec& spec,
                                                  const LayersBakeOptions& given,
                                                  const RunOptions& run) {
  const LayersBakeOptions options = with_spec_base(given, spec);
  const auto start = Clock::now();
  if (Status s = validate_options(options); !s) return s.error();
  if (Status s = check_layer_specs(spec, false); !s) return s.error();
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<LayerColors>(run, [&]() -> Expected<LayerColors> {
    progress.start("layers", spec.layers.size());
    // The images stay alive for the bake: every layer's texture and mask.
    std::vector<Image> images;
    std::vector<std::string> mask_warnings, notes;
    Expected<std::vector<std::vector<Photo>>> photos =
        read_layer_cameras(spec, mask_warnings, notes);
    if (!photos) return photos.error();
    Expected<std::vector<LayerInput>> inputs =
        read_layer_inputs(spec, progress, images, options.cache_mb);
    if (!inputs) return inputs.error();
    LayerColors out;
    out.stats.warnings = std::move(mask_warnings);
    out.stats.notes = std::move(notes);
    // "cameras" layers: the photo bake's blend per vertex.
    std::vector<PhotoLayerPoints> blends(spec.layers.size());
    std::vector<double> photo_seconds(spec.layers.size(), 0.0);
    std::vector<std::vector<SkippedPhoto>> skipped(spec.layers.size());
    if (Status s = bake_layer_photos(
            *photos, progress, *inputs, blends, photo_seconds,
            [&](std::size_t i, const std::vector<Photo>& p, PhotoLayerPoints& b) -> Status {
              // The blend alone: the layer composites it, the engine resolves.
              Expected<PhotoBakeResult> blend =
                  blend_vertex_photos(mesh, p, layer_photo_options(options));
              if (!blend) return blend.error();
              add_photo_warnings(i, blend->warnings, out.stats.warnings);
              skipped[i] = std::move(blend->skipped);
              b.vertices = std::move(blend->points);
              return ok_status();
            });
        !s) {
      return s.error();
    }
    progress.finish();  // "layers": the textures read, the photos blended
    if (progress.cancelled()) return cancelled_error();
    Expected<LayersBakeResult> baked = bake_vertex_layers(mesh, *inputs, options, &progress);
    if (!baked) return detail::as_input(baked.error());
    if (Status s = check_texels_read(images); !s) return s.error();
    out.colors = std::move(baked->colors);
    out.layers = std::move(baked->layers);
    for (std::size_t i = 0; i < out.layers.size(); ++i) {
      out.layers[i].seconds += photo_seconds[i];
      out.layers[i].skipped = std::move(skipped[i]);
    }
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

Expected<LayerAtlas> detail::layer_atlas_texture(const MeshData& mesh, const LayersSpec& spec,
                                                 const LayersBakeOptions& given,
                                                 const AtlasOptions& atlas, const RunOptions& run) {
  const LayersBakeOptions options = with_spec_base(given, spec);
  const auto start = Clock::now();
  if (Status s = validate_options(options); !s) return s.error();
  if (Status s = check_layer_specs(spec, true); !s) return s.error();
  if (atlas.uv == UvLayout::kProxy) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--uv proxy needs a proxy, and a layers bake has none (use --uv generate "
                      "or --uv mesh)");
  }
  const bool base_texture = options.base == LayerBase::kMesh && mesh.has_texture();
  if (base_texture &&
      !(atlas.uv == UvLayout::kMesh || (atlas.uv == UvLayout::kAuto && mesh.has_uvs()))) {
    return make_error(ErrorCode::kInvalidArgument,
                      "base \"mesh\" on the atlas is the mesh's own texture through its own UVs: "
                      "use --uv mesh (or --uv auto on a mesh with UVs)");
  }
  if (options.base == LayerBase::kMesh && !base_texture &&
      mesh.vertex_colors.size() != mesh.positions.size()) {
    return make_error(ErrorCode::kParse,  // the mesh's problem (exit 1), as for the vertex target
                      "base \"mesh\": the mesh has neither a texture nor vertex colours");
  }
  if (Status s = check_uv_layout(mesh, atlas.uv); !s) return s.error();
  // The base texture first: its size is the default --size.
  std::optional<Image> texture;
  AtlasOptions resolved = atlas;
  if (base_texture) {
    Expected<Image> read = read_mesh_texture(mesh);
    if (!read) return detail::as_input(read.error());
    texture = std::move(read).value();
  }
  if (resolved.bake.size == 0) {
    resolved.bake.size = texture ? std::max(texture->width, texture->height) : 2048;
  }
  if (Status s = validate_options(resolved); !s) return s.error();
  if (Status s = check_triangles(mesh); !s) return s.error();
  Progress progress(run.progress);
  return detail::run_call<LayerAtlas>(run, [&]() -> Expected<LayerAtlas> {
    progress.start("layers", spec.layers.size());
    std::vector<Image> images;
    std::vector<std::string> mask_warnings, notes;
    Expected<std::vector<std::vector<Photo>>> photos =
        read_layer_cameras(spec, mask_warnings, notes);
    if (!photos) return photos.error();
    Expected<std::vector<LayerInput>> inputs =
        read_layer_inputs(spec, progress, images, options.cache_mb);
    if (!inputs) return inputs.error();
    progress.finish();
    LayerAtlas out;
    if (Status s = detail::lay_out_atlas(mesh, nullptr, resolved, progress, out.atlas); !s) {
      return s.error();
    }
    std::vector<std::string>& warnings = out.atlas.stats.warnings;
    warnings.insert(warnings.begin(), mask_warnings.begin(), mask_warnings.end());
    out.atlas.stats.notes = std::move(notes);
    // "cameras" layers: the photos' blend per vertex and sample (blend_atlas_photos).
    std::vector<PhotoLayerPoints> blends(spec.layers.size());
    std::vector<double> photo_seconds(spec.layers.size(), 0.0);
    std::vector<std::vector<SkippedPhoto>> skipped(spec.layers.size());
    if (Status s = bake_layer_photos(
            *photos, progress, *inputs, blends, photo_seconds,
            [&](std::size_t i, const std::vector<Photo>& p, PhotoLayerPoints& b) -> Status {
              PhotoAtlasBakeOptions po;
              po.size = resolved.bake.size;
              po.samples = resolved.bake.samples;
              po.photo = layer_photo_options(options);
              // The samples' cosines only for an angle fade (4 bytes a sample).
              po.photo.keep_points = (*inputs)[i].angle_fade.has_value();
              Expected<PhotoAtlasBlend> blend = blend_atlas_photos(out.atlas.mesh, p, po);
              if (!blend) return blend.error();
              add_photo_warnings(i, blend->warnings, out.atlas.stats.warnings);
              skipped[i] = std::move(blend->skipped);
              b = std::move(blend->points);
              return ok_status();
            });
        !s) {
      return s.error();
    }
    if (options.base == LayerBase::kMesh && !base_texture && out.atlas.mesh.vertex_colors.empty()) {
      out.atlas.mesh.vertex_colors = mesh.vertex_colors;  // generated charts: same vertices
    }
    LayersAtlasOptions o;
    o.size = resolved.bake.size;
    o.samples = resolved.bake.samples;
    o.padding = resolved.bake.padding;
    o.layers = options;
    o.resolve_overlaps = out.atlas.uv.overlap_texels > 0;
    if (texture) o.base_texture = texture->view();
    Expected<LayersAtlasResult> baked = bake_atlas_layers(out.atlas.mesh, *inputs, o, &progress);
    if (progress.cancelled()) return cancelled_error();
    if (!baked) return detail::as_input(baked.error());
    if (Status s = check_texels_read(images); !s) return s.error();
    out.atlas.image = std::move(baked->atlas);
    out.atlas.blend = !baked->opaque;
    out.layers = std::move(baked->layers);
    for (std::size_t i = 0; i < out.layers.size(); ++i) {
      out.layers[i].seconds += photo_seconds[i];
      out.layers[i].skipped = std::move(skipped[i]);
    }
    Counts& c = out.atlas.stats.counts;
    c = detail::mesh_counts(mesh);
    c.texels = baked->texels;
    c.samples = baked->samples;
    c.occluded = baked->uncovered;
    c.border_samples = baked->border_samples;
    c.padded = baked->padded;
    Timings& t = out.atlas.stats.timings;
    t.fill = baked->seconds_fill;
    t.scene_build = baked->seconds_scene;
    t.rasterize = baked->seconds_raster;
    t.bake = baked->seconds_layers;
    t.pad = baked->seconds_pad;
    t.total = seconds_since(start);
    return out;
  });
}

}  // namespace texbake
