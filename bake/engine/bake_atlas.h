// The atlas target (SPEC section 4): bake an image through a proxy into a
// texture atlas over a mesh's per-corner UV layout. It is the engine's atlas
// target (bake/engine/layers_bake.h) over a one-layer stack under
// ResultAlpha::kImage; what follows is that rule for one proxy.
//
// Stages (each timed):
//  1. rasterise (bake/atlas/atlas_raster.h): covered texels (conservative, so no
//     bilinear lookup from inside a triangle reads an unbaked texel) and
//     their `samples` supersamples, each with its triangle and barycentrics;
//  2. sample: each sample's 3D point (barycentric on its triangle, in
//     double precision) goes
//     through the proxy's inverse_map and, with Visibility::kFirst, the
//     visibility ray of bake/trace/visibility.h; visible samples take the bilinear
//     image sample (kOutside samples follow options.outside); occluded and
//     undefined samples follow options.occluded: kProject the projected colour
//     (undefined ones have none: they are filled), kColor the constant, kFill
//     the per-vertex inpainting of bake/vertex/occlusion_fill.h (through bake_vertex
//     with the bilinear filter) interpolated barycentrically over the sample's
//     triangle. A texel is the plain mean of its samples. Under
//     shading.filter kEwa the image lookup is sample_ewa (mapping/mipmap.h)
//     over the working image's MIP pyramid instead of the bilinear one; a
//     sample's footprint on the surface is the ellipse through the corners
//     of its cell of the texel (1 / sqrt(samples) of a texel a side): the two
//     3D vectors of one cell step in the atlas's u and v (the triangle's
//     UV-to-3D map) over sqrt(2), then into the image's (u, v) by the inverse
//     mapping's Jacobian (mapping/derivatives.h). With resolve_overlaps a
//     sample inside several triangles prefers a visible one.
//  3. pad: pad_atlas (bake/atlas/atlas_common.h) as options.padding says.
// Stages 1 and 2 run band by band (AtlasBands, kAtlasBandRows rows at a
// time, in parallel), so the samples of the whole atlas are never held at
// once: memory is the atlas itself plus a band's samples per thread. With
// kFill and visibility the fill is computed before the pass (sharing the
// Embree scene); otherwise texels with undefined samples are finished after
// it. The result equals the whole-atlas computation (atlas_stream_test.cpp).
// Covered texels are never changed by the padding. With an explicit N,
// texels neither covered nor padded are transparent black (0, 0, 0, 0).
// With options.shading.linear the image is linearised once, samples average
// in linear and each texel is converted back to sRGB; a linear image
// (ImageView::color_space kLinear) is sampled as it is, in linear light, and
// each texel converted to sRGB: the atlas is always sRGB-encoded (issue
// #11; the writers encode it for their format). Under --occluded R,G,B a
// texel all of whose samples are occluded or unmapped is the constant
// (sRGB-encoded) exactly, as a vertex is in the vertex target; a texel
// only partly so averages it with its other samples in the working
// encoding. Results do not depend on the thread count.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "bake/atlas/atlas_common.h"
#include "bake/shade/options.h"
#include "bake/util/progress.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/proxy.h"
#include "mapping/vec.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct AtlasBakeOptions {
  int size = 2048;                // texels per side, 1 .. kMaxAtlasSize
  int samples = 4;                // supersamples per covered texel, 1 .. kMaxAtlasSamples
  int padding = kPaddingDefault;  // texels of dilation (>= 0), or one of the constants above
  // An overlapping layout (texels under several UV triangles: --uv proxy on a
  // mesh that is not star-shaped as seen from the projector, --uv mesh with
  // shared UVs): with Visibility::kFirst, a sample inside several triangles
  // takes the lowest-index one whose point the projector sees (if none does,
  // the lowest-index one, as without), so shared texels take the visible
  // surface's colour. Costs a full candidate scan per sample and a ray per
  // further candidate; bake_atlas_texture sets it when the layout overlaps.
  bool resolve_overlaps = false;
  // visibility, occluded (+ colour), outside (+ colour), linear, plane_wrap,
  // filter: kEwa filters each supersample by its footprint (below), anything
  // else is the bilinear lookup; shading.samples is not used by the atlas.
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
  Image atlas;                 // size x size RGBA, sRGB-encoded (color_space kSrgb)
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

}  // namespace texbake
