// The atlas target (SPEC section 4, issue #4): bake an image through a proxy
// into a texture atlas over a mesh's per-corner UV layout.
//
// Stages (each timed):
//  1. rasterise (bake/atlas/atlas_raster.h): covered texels (conservative, so no
//     bilinear lookup from inside a triangle reads an unbaked texel) and
//     their `samples` supersamples, each with its triangle and barycentrics;
//  2. sample: each sample's 3D point (barycentric on its triangle) goes
//     through the proxy's inverse_map and, with Visibility::kFirst, the
//     visibility ray of bake/trace/visibility.h; visible samples take the bilinear
//     image sample (kOutside samples follow options.outside); occluded and
//     undefined samples follow options.occluded: kProject the projected colour
//     (undefined ones have none: they are filled), kColor the constant, kFill
//     the per-vertex inpainting of bake/vertex/occlusion_fill.h (through bake_vertex
//     with the bilinear filter) interpolated barycentrically over the sample's
//     triangle. A texel is the plain mean of its samples.
//  3. pad (bake/atlas/dilate.h): `padding` rings of 8-neighbour dilation, or
//     push-pull over the whole background for kPaddingInfinite.
// Stages 1 and 2 run band by band (AtlasBands, kAtlasBandRows rows at a
// time, in parallel), so the samples of the whole atlas are never held at
// once: memory is the atlas itself plus a band's samples per thread. With
// kFill and visibility the fill is computed before the pass (sharing the
// Embree scene); otherwise texels with undefined samples are finished after
// it. The result equals the whole-atlas computation (atlas_stream_test.cpp).
// Texels neither covered nor padded are transparent black (0, 0, 0, 0).
// With options.shading.linear the image is linearised once, samples average
// in linear and each texel is converted back to sRGB. Results do not depend
// on the thread count.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "bake/shade/options.h"
#include "bake/util/progress.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

inline constexpr int kPaddingDefault = -1;   // default_padding(size) (bake/atlas/dilate.h)
inline constexpr int kPaddingInfinite = -2;  // push-pull fill of the whole background

struct AtlasBakeOptions {
  int size = 2048;                // texels per side, 1 .. kMaxAtlasSize
  int samples = 4;                // supersamples per covered texel, 1 .. kMaxAtlasSamples
  int padding = kPaddingDefault;  // texels of dilation (>= 0), or one of the constants above
  // visibility, occluded (+ colour), outside (+ colour), linear, plane_wrap;
  // filter and samples are not used by the atlas.
  VertexBakeOptions shading;
};

struct AtlasBakeCounts {
  std::size_t texels = 0;          // covered (baked) texels
  std::size_t samples = 0;         // samples taken (texels * samples per texel)
  std::size_t border_samples = 0;  // samples clamped onto a triangle (chart borders)
  std::size_t occluded = 0;        // samples whose visibility ray is blocked
  std::size_t undefined = 0;       // samples without a mapping
  std::size_t outside = 0;         // samples outside the proxy's (u, v) domain
  std::size_t padded = 0;          // texels filled by padding
};

struct AtlasBakeTimings {  // seconds
  // rasterize and sample interleave per band: the pass's wall time is split
  // between them in proportion to their summed thread time.
  double rasterize = 0;
  double scene_build = 0;  // Embree BVH (0 with Visibility::kAll)
  double sample = 0;       // mapping, rays, image samples, texel means
  double fill = 0;         // per-vertex inpainting for --occluded fill (0 if unused)
  double pad = 0;
};

struct AtlasBakeResult {
  Image atlas;                 // size x size RGBA, in the image's encoding
  std::vector<uint8_t> baked;  // size * size: 1 where covered by the layout
  AtlasBakeCounts counts;
  AtlasBakeTimings timings;
};

// uv_mesh: a mesh with per-corner UVs (MeshData::uvs/corner_uv) covering its
// triangles. Preconditions: image has at least 1 x 1 pixel. Errors: those of
// rasterize_atlas (bad size or samples, no UVs, bad UVs), kInvalidArgument
// for a negative padding other than the constants, kInternal (Embree or the
// fill solver failed), kCancelled (progress's callback returned false: the
// remaining bands are skipped). progress may be null; it hears the stage
// "sample" (the band pass).
Expected<AtlasBakeResult> bake_atlas(const MeshData& uv_mesh, const ImageView& image,
                                     const Proxy& proxy, const AtlasBakeOptions& options,
                                     Progress* progress = nullptr);

// A copy of `mesh` whose faces are its triangles, with per-corner UVs from a
// per-triangle UV table (triangle_uvs[t][k] indexes uvs for corner k of
// mesh.triangles[t], as --uv generate produces it). Normals are carried over
// per corner if present. Precondition: triangle_uvs.size() == mesh.triangles.size().
MeshData mesh_with_triangle_uvs(const MeshData& mesh, const std::vector<Float2>& uvs,
                                const std::vector<std::array<uint32_t, 3>>& triangle_uvs);

}  // namespace texbake
