// Colouring a texture atlas from several calibrated photographs (SPEC
// section 9, `bake --cameras` with the atlas target): the atlas's
// supersamples (bake/atlas/atlas_raster.h) take the place of the vertex
// bake's vertices, with the same cull, visibility, quality, exposure and
// blend rules (bake/photo/photo_bake.h, sharing bake/photo/photo_view.h).
//
// Stages, photos read one at a time (never all at once); 1 to 5 are the
// blend (blend_atlas_photos below), 6 and 7 the bake engine's:
//  1. the vertex photo blend (blend_vertex_photos) on the same mesh: its
//     exposure gains (solved on vertex samples) are the atlas's, and its
//     per-vertex blend is what the fill resolves (the vertex photo bake's
//     colours, bake/engine/photo_vertex.h), for the unseen samples under
//     --occluded fill, interpolated barycentrically over the sample's
//     triangle in linear light, as the proxy atlas does with its per-vertex fill;
//  2. rasterise the layout: covered texels and their supersamples (triangle
//     and barycentrics);
//  3. geometry pass, per camera: each sample's point P and normal; cull
//     (inside the photo, in front, within 75 degrees, the face normal
//     facing C, and not masked out: mask value m > 0, photo_bake.h
//     "Masks"), the segment P -> C traced (bake/photo/segments.h); per
//     sample q_max (and the first camera reaching it and its m, for kBest;
//     the sum of the cameras' m, for kMean), and one bit per camera and
//     sample saying the camera sees it, so no segment is traced twice;
//  4. weight pass (kSoft only, no ray): per sample the sum W of its
//     weights m exp(-(1 - q / q_max) / 0.1);
//  5. colour pass, per photo: for every sample it sees, w / W times its
//     gain times the sample of the linearised photo (the alpha-weighted
//     bilinear mean, photo_view.h's sample_masked) is added to the
//     sample's colour (and w / W to the camera's weight share);
//  6. the blend as one "cameras" layer through the engine's atlas target
//     under the single projection's rule (bake/engine/layers_bake.h,
//     ResultAlpha::kImage): texel = the plain mean of its samples in
//     linear light, encoded to sRGB (alpha 1); under --occluded R,G,B a
//     texel all of whose samples are unseen is the colour exactly, one
//     partly so averages it (decoded) with its other samples;
//  7. padding as the proxy atlas (pad_atlas of bake/atlas/atlas_common.h).

// Normal: the interpolated smooth vertex normal (normalised) gives
// cos(theta) and the 75-degree cut, as the vertex bake's smooth normals
// do: q, and so the blend weights, vary continuously across triangle
// edges (the face normal would change every weight in steps at each edge,
// which shows as faceting where two photos disagree), and at a vertex the
// sample's q is the vertex bake's. The face normal adds SPEC's back-face
// rule (face normal . d > 0), which the smooth normal alone can miss at
// creases.
//
// A masked photo's mask (its alpha) is kept from stage 1 for stages 3 and 4
// at one byte a pixel when every alpha value is one an 8-bit file decodes
// to (given back exactly); otherwise the photo is read again for it in
// stage 3 and, for kSoft, stage 4. Stages 1 and 5 decode the next photo
// while they work on one (photo_view.h prefetching_reader): two photos in
// memory at once. Every photo is read twice (stages 1 and 5).
//
// Memory: the samples (12 bytes each), per sample q_max, W, the colour and
// its state (21 bytes; kBest 4 more), one bit per camera and sample, the atlas, the
// Embree scene, two photos (the one baked, the next one read) and the kept
// masks (one byte per pixel of each masked photo): a 2048 atlas with 4 samples (about 12 M
// samples at 70 % coverage) and 100 photos holds some 0.6 GB besides the
// photo and the scene (measured: the bunny subdivided to 1.2 M triangles,
// 10.6 M samples, 8 photos of 960 x 720: 0.81 GB peak for the whole
// command). Stages 6 and 7 hold the blend (13 bytes a sample: state and
// colour; 17 a vertex), the atlas and, in turn, the fill's solver and the
// engine's bands. When no triangle reaches the atlas (no texels) no fill
// runs, and vertices_filled and vertices_unfilled are 0. An overlapping layout is baked with each
// sample on its lowest-index triangle (AtlasBakeOptions::resolve_overlaps has no counterpart here:
// which surface is "visible" differs per photo). Results do not depend on the thread count.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bake/atlas/atlas_common.h"  // kPaddingDefault, kPaddingInfinite
#include "bake/engine/layers_bake.h"
#include "bake/photo/photo_bake.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

struct PhotoAtlasBakeOptions {
  int size = 2048;                // texels per side, 1 .. kMaxAtlasSize
  int samples = 4;                // supersamples per covered texel, 1 .. kMaxAtlasSamples
  int padding = kPaddingDefault;  // as AtlasBakeOptions::padding
  PhotoBakeOptions photo;         // blend, exposure, occluded (+ colour)
};

struct PhotoAtlasBakeResult {
  Image atlas;                 // size x size RGBA, sRGB-encoded (color_space kSrgb)
  std::vector<uint8_t> baked;  // size * size: 1 where covered by the layout
  // Per photo: in_view, visible and weight_share over the atlas samples;
  // gain, photo size and scaled from the vertex bake (stage 1).
  std::vector<PhotoCameraStats> cameras;
  PhotoConsistency consistency;    // the vertex bake's (photo_bake.h)
  std::size_t texels = 0;          // covered texels
  std::size_t samples = 0;         // their supersamples
  std::size_t border_samples = 0;  // samples clamped onto a triangle (chart borders)
  std::size_t seen = 0;            // samples seen by at least one photo
  std::size_t filled = 0;          // unseen samples coloured by the fill (not --occluded R,G,B)
  std::size_t padded = 0;          // texels filled by padding
  // Vertices seen by some photo (stage 1), and the fill's: vertices filled,
  // and left in components no photo sees (they take the --occluded colour).
  std::size_t vertices_seen = 0, vertices_filled = 0, vertices_unfilled = 0;
  std::vector<std::string> warnings;
  // Photos left out by stage 1 (unreadable; PhotoBakeOptions::strict_photos):
  // `cameras` and the later stages have the others only.
  std::vector<SkippedPhoto> skipped;
  // Seconds: stage 1 (vertex), 2 (rasterize, with the engine's bands), the
  // scenes, 3 (geometry), 4 and 5 (photos), the fill's solve, 6 and 7 (texels).
  double seconds_vertex = 0, seconds_rasterize = 0, seconds_scene = 0, seconds_geometry = 0,
         seconds_photos = 0, seconds_fill = 0, seconds_texels = 0;
};

// Stages 1 to 5: the photos' blend per vertex and per atlas supersample,
// what a "cameras" layer of the engine's atlas target takes.
struct PhotoAtlasBlend {
  // Per vertex of uv_mesh (stage 1) and per supersample (texel-major;
  // texel_first per texel of the size x size atlas); cosines only with
  // options.photo.keep_points (an angle fade needs them).
  PhotoLayerPoints points;
  std::vector<PhotoCameraStats> cameras;  // as PhotoAtlasBakeResult's
  PhotoConsistency consistency;
  std::vector<std::string> warnings;
  std::vector<SkippedPhoto> skipped;
  std::size_t texels = 0, samples = 0, border_samples = 0;
  std::size_t seen = 0;           // samples seen by some photo
  std::size_t vertices_seen = 0;  // vertices seen by some photo
  double seconds_vertex = 0, seconds_rasterize = 0, seconds_scene = 0, seconds_geometry = 0,
         seconds_photos = 0;
};

// Errors: as bake_atlas_from_photos's below but for the padding (not used).
Expected<PhotoAtlasBlend> blend_atlas_photos(const MeshData& uv_mesh,
                                             const std::vector<Photo>& photos,
                                             const PhotoAtlasBakeOptions& options,
                                             const PhotoReader& reader = {});

// uv_mesh: a mesh with per-corner UVs covering its triangles (as for
// bake_atlas). Errors: blend_vertex_photos's (a photo unreadable or of
// the wrong size, no photos, ...), rasterize_atlas's (bad size or samples,
// no UVs, bad UVs), kInvalidArgument for a bad padding, kInternal (Embree).
// `reader` (default: mesh_io's read_image) is called twice per photo, in
// photo order, one call at a time: by stage 1, then by stage 5; a masked
// photo whose mask was not kept (see above) also by stage 3 and (kSoft)
// stage 4. Errors also: a mask file's (read_mask's, or of
// another size than its photo).
Expected<PhotoAtlasBakeResult> bake_atlas_from_photos(const MeshData& uv_mesh,
                                                      const std::vector<Photo>& photos,
                                                      const PhotoAtlasBakeOptions& options,
                                                      const PhotoReader& reader = {});

}  // namespace texbake
