// What every call of texbake/texbake.h shares (internal to bake/texbake/):
// running in the call's task arena with exceptions turned into errors, the
// mesh counts of Stats, and the re-coding of the work's errors.
#pragma once

#include <exception>
#include <new>
#include <optional>
#include <string>
#include <utility>

#include "bake/util/parallel.h"
#include "bake/util/progress.h"
#include "texbake/texbake.h"

namespace texbake {
class EmbreeScene;
}

namespace texbake::detail {

// The implementations of the per-kind bakes (texbake.h: the public calls
// over a Bake and their per-kind conveniences call these).
Expected<VertexColors> image_vertex_colors(const MeshData& mesh, const ImageView& image,
                                           const Proxy& proxy, const VertexBakeOptions& options,
                                           const RunOptions& run);
Expected<Atlas> image_atlas_texture(const MeshData& mesh, const ImageView& image,
                                    const Proxy& proxy, const AtlasOptions& options,
                                    const RunOptions& run);
Expected<PhotoColors> photo_vertex_colors(const MeshData& mesh, const std::vector<Photo>& photos,
                                          const PhotoBakeOptions& options, const RunOptions& run);
Expected<PhotoAtlas> photo_atlas_texture(const MeshData& mesh, const std::vector<Photo>& photos,
                                         const PhotoBakeOptions& options, const AtlasOptions& atlas,
                                         const RunOptions& run);
Expected<LayerColors> layer_vertex_colors(const MeshData& mesh, const LayersSpec& spec,
                                          const LayersBakeOptions& options, const RunOptions& run);
Expected<LayerAtlas> layer_atlas_texture(const MeshData& mesh, const LayersSpec& spec,
                                         const LayersBakeOptions& options,
                                         const AtlasOptions& atlas, const RunOptions& run);

// bake_vertex_colors (texbake.h) on a visibility scene already built over
// `mesh` (JobCache::scene; null: built here), the image consumed when
// `owned` is given (then `image` is its view).
Expected<VertexColors> bake_vertex_colors_on(const MeshData& mesh, const ImageView& image,
                                             Image* owned, const Proxy& proxy,
                                             const VertexBakeOptions& options,
                                             const RunOptions& run, const EmbreeScene* scene);

// Runs work() (returning Expected<T>) inside a task arena of run.threads
// threads; std::bad_alloc and other exceptions become kInternal errors
// ("out of memory", "unexpected failure: ..."), so nothing escapes the API.
template <class T, class Work>
Expected<T> run_call(const RunOptions& run, Work&& work) {
  std::optional<Expected<T>> out;
  try {
    run_in_arena(run.threads, [&] { out.emplace(work()); });
  } catch (const std::bad_alloc&) {
    return make_error(ErrorCode::kInternal, "out of memory");
  } catch (const std::exception& e) {
    return make_error(ErrorCode::kInternal, std::string("unexpected failure: ") + e.what());
  }
  return std::move(*out);
}

// An error of the work done after the options were validated: a stage
// saying kInvalidArgument/kUnsupported there (e.g. "zero total area" from
// UV generation) means the input cannot be worked on, so it becomes kParse
// (category kInput). Other codes are kept.
Error as_input(Error error);

// vertices, triangles, degenerate_triangles and unreferenced_vertices of
// `mesh` (as read_mesh counts them in MeshIssues).
Counts mesh_counts(const MeshData& mesh);

// The mesh's counts `mesh` (mesh_counts) with the sample figures every bake
// counts alike (samples, occluded, undefined, outside) from its own counts
// `b` (VertexBakeCounts, AtlasBakeCounts).
template <class BakeCounts>
Counts bake_counts(const Counts& mesh, const BakeCounts& b) {
  Counts c = mesh;
  c.samples = b.samples;
  c.occluded = b.occluded;
  c.undefined = b.undefined;
  c.outside = b.outside;
  return c;
}

// A proxy that maps nothing of the mesh (issue #12): when all `total`
// points (vertices, or atlas samples) have no mapping (status undefined),
// kParse "the proxy maps none of the mesh's N WHAT ..."; when more than
// kUndefinedWarnShare of them have none, a warning in `warnings`.
inline constexpr double kUndefinedWarnShare = 0.5;
Status check_mapped(std::size_t undefined, std::size_t total, const std::string& what,
                    std::vector<std::string>& warnings);

// kUsage "the image has no pixels" for an empty view.
Status check_image(const ImageView& image);

// A colour component outside [0, 1] (or NaN) in the shading options that
// use it: kUsage naming --occluded / --outside.
Status check_shading_colors(const VertexBakeOptions& options);

// The UV layout stage of the atlas bakes (bake_atlas_texture and
// bake_atlas_texture_from_photos): lays out `mesh`'s UVs as options.uv says
// (proxy: null for a bake without one, which refuses kProxy) into
// atlas.mesh, atlas.uv, atlas.repeat_u, atlas.stats.warnings and
// timings.uv_layout. Progress stage "uv_layout". Errors: the layout's (as
// as_input), kCancelled. With `consumed` (the caller's own `mesh`, given up):
// `mesh` is moved into atlas.mesh when the layout keeps its UVs, and freed
// once atlas.mesh is made otherwise, so the bake holds one mesh, not two;
// `mesh` must not be read afterwards.
Status lay_out_atlas(const MeshData& mesh, const Proxy* proxy, const AtlasOptions& options,
                     Progress& progress, Atlas& atlas, MeshData* consumed = nullptr);

}  // namespace texbake::detail
