// The bake engine: every bake's loop over its sample points. A bake is an
// ordered stack of projections (layers) evaluated at the vertices or at
// the atlas's supersamples. Layers (SPEC section 10): several projections
// composited over a base, bottom first, per sample in linear light. The
// single-proxy vertex bake (bake/engine/bake_vertex.h) is a one-layer stack
// under ResultAlpha::kImage (SPEC section 4's rules).
//
// Per sample (a vertex, or an atlas supersample: bake_atlas_layers below)
// and layer, with d = d(P) the direction towards
// the layer's projector and n the smooth vertex normal:
//   a = opacity x image alpha x mask x angle fade x seen
//  - the image is looked up at the projector's (u, v) with its wrap rules
//    (mapping/sample.h) and the layer's filter (LayerInput::filter:
//    bilinear by default, area or EWA as the single-proxy bake) in the
//    layer's working space: by default premultiplied linear RGBA, so a
//    label's transparent border does not bleed dark fringes into its
//    colour; the layer colour L is the straight colour of that lookup;
//  - mask: a second image through the same (u, v): its alpha when it has
//    an alpha channel, else its first channel (a grey image), as stored;
//  - angle fade [a0, a1]: 1 up to a0 degrees between n and d, 0 from a1,
//    linear between; none: 1;
//  - seen: visibility "first": the ray towards an analytic proxy (to
//    infinity, bake/trace/visibility.h) or the segment to a camera's centre
//    is free, and for a camera n . d > 0; "all": 1. Points the projector does
//    not map (kUndefined, behind a camera) are not seen. Points outside the
//    (u, v) domain follow the layer's `outside`: transparent (a = 0), clamp
//    (the clamped lookup, with its alpha and mask) or a constant colour (its
//    alpha; mask 1).
// Compositing, B and alpha the running straight colour and coverage (base
// "none": B = 0, alpha 0; a colour: its linear RGB and alpha; "mesh": the
// mesh's vertex colours, linearised, and their alpha):
//   over      B' = (a L + (1 - a) alpha B) / alpha'   (= a L + (1 - a) B on an opaque base)
//   multiply  B' = B (1 - a + a L)
//   add       B' = B + a L
//   replace   B' = L where a > 0
//   alpha' = 1 - (1 - alpha)(1 - a) for every mode (the coverage).
// Samples with coverage 0 (no base colour, no layer) follow `occluded`
// (OccludedMode::kFill: the harmonic fill of bake/vertex/occlusion_fill.h
// over their RGB, alpha staying 0; kColor: the constant's RGB, alpha 0;
// kProject acts as kFill; ResultAlpha::kImage has its own rules). Results
// do not depend on the thread count.
// One per-point implementation serves both targets: the vertex target's
// points are the vertices with their smooth normals, the atlas's its
// supersamples with the interpolated smooth normals. The single-proxy
// bakes (bake/engine/bake_vertex.h, bake_atlas.h) are one-layer stacks
// under ResultAlpha::kImage.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "bake/photo/photo_bake.h"
#include "bake/shade/options.h"
#include "bake/trace/embree_scene.h"
#include "bake/util/progress.h"
#include "bake/vertex/vertex_resolve.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/mipmap.h"
#include "mapping/projector.h"
#include "mesh_io/image_io.h"
#include "mesh_io/layers_json.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// A "cameras" layer's colours: the photo bake's blend per point
// (bake/photo/photo_bake.h, PhotoBakeOptions::keep_points), for the points
// the layers are baked on. Per point: L = the blend (linear light),
// seen = kSeen, the angle fade at the blend-weighted mean angle to the
// cameras (PhotoPoints::cosine), image alpha and mask 1; a point in no
// camera's view (kNoView) is outside (transparent, or the layer's outside
// colour), one occluded from every camera (kInView) not seen. The stats:
// in domain = in some camera's view, visible = seen. The cosines may be
// empty when the layer has no angle fade.
struct PhotoLayerPoints {
  PhotoPoints vertices;  // per vertex of the mesh (for the atlas: of uv_mesh, for the fill)
  PhotoPoints samples;   // the atlas target: per supersample, texel-major
  // The atlas target: per texel (y * size + x) the index of its first
  // sample in `samples` (its samples follow), kNoTexel when not covered.
  std::vector<uint32_t> texel_first;
  static constexpr uint32_t kNoTexel = 0xffffffffu;
};

// One layer, ready to bake: its projector and images (any colour space:
// sampled in linear light), or its photos' blend (`photos` set: then the
// projector, texture and mask are not used). The mask view is empty (data
// null) when none.
struct LayerInput {
  std::string name;                          // for the report (e.g. the texture's file name)
  const PhotoLayerPoints* photos = nullptr;  // a "cameras" layer (outlives the bake)
  Projector projector;
  ImageView texture;
  bool texture_has_alpha = true;
  ImageView mask;
  bool mask_has_alpha = false;  // take the mask's alpha (else its first channel)
  double opacity = 1;
  LayerMode mode = LayerMode::kOver;
  std::optional<std::array<double, 2>> angle_fade;  // degrees
  LayerVisibility visibility = LayerVisibility::kFirst;
  LayerOutside outside = LayerOutside::kTransparent;
  Rgba outside_color{0, 0, 0, 0};  // sRGB-encoded, straight alpha
  // The lookup of the image (and only of the image: the mask is bilinear),
  // the single-proxy bake's (bake/shade/shade.h, SPEC sections 4 and 13):
  //  - kBilinear: the bilinear lookup at the point's (u, v);
  //  - kArea (the vertex target): the mean of `samples` bilinear lookups over
  //    the vertex's share of its triangles (bake/vertex/vertex_share.h; its
  //    undefined samples left out, its outside ones following `outside`,
  //    transparent ones adding 0), visibility decided at the vertex; on the
  //    atlas target the bilinear lookup per supersample, as the proxy atlas;
  //  - kEwa (an analytic proxy only: kInvalidArgument for a camera): the EWA
  //    lookup over the working image's MIP pyramid with the footprint of the
  //    proxy bake: the vertex's share (bake/shade/footprint.h), or the atlas
  //    supersample's cell (bake/atlas/atlas_common.h cell_tangents).
  // A "cameras" layer is the photo bake's own lookup: kBilinear only.
  VertexFilter filter = VertexFilter::kBilinear;
  int samples = 16;  // kArea: lookups per vertex (>= 1)
  double max_anisotropy = kDefaultMaxAnisotropy;
  // The plane proxy's wrap (SPEC section 2 --wrap): kRepeat tiles the image
  // in u and v (nothing is outside); ignored by the other projectors.
  WrapMode plane_wrap = WrapMode::kClamp;
  // The layer's working space (SPEC section 1): true, linear light with
  // premultiplied alpha (layers and photos); false, the stored encoding with
  // straight alpha (the single-proxy bake without --linear: its lookups,
  // area means and EWA run on the image's stored values, linear light for a
  // linear image). A stack none of whose layers looks up in linear light
  // composites, averages texels and fills in the sRGB encoding too (so a
  // one-layer stack is the single-proxy bake); otherwise an sRGB-encoded
  // layer's colour is linearised before it composites.
  bool linear = true;
  // With `linear`: straight alpha, not premultiplied (the single-proxy
  // bake's --linear: the image's RGB linearised, alpha kept, looked up and
  // averaged straight; SPEC section 1).
  bool straight = false;
};

// The single-proxy bake's projection as a layer (for ResultAlpha::kImage):
// the image in its stored encoding with straight alpha, or with
// options.linear in linear light with straight alpha; the options'
// visibility, outside (clamp or the colour), filter (and its samples) and
// plane wrap.
LayerInput single_projection_layer(const ImageView& image, const Proxy& proxy,
                                   const VertexBakeOptions& options);

// What a vertex target's alpha is, and which vertices the fill resolves.
enum class ResultAlpha {
  // Layers (SPEC section 10): alpha is the coverage; the vertices with
  // coverage 0 are resolved (their RGB filled, alpha 0).
  kCoverage,
  // The single projection (SPEC section 4): one layer (opacity 1, no mask,
  // no angle fade, mode "over", base "none", outside clamp or a colour),
  // whose filtered lookup is the vertex's RGBA, alpha included (the image's
  // alpha is a colour channel, averaged and filled as one). A vertex is
  // known where the projector maps and sees it, whatever its alpha; a
  // hidden one (mapped, its visibility ray blocked) is resolved by
  // `occluded` (kProject: its projected colour; kFill: the fill), one with
  // no mapping by the fill (or the constant under kColor). A component of
  // unknown vertices that touches no known vertex takes its projected
  // colour, or the image's mean where it has none. One "cameras" layer
  // (opacity 1, no angle fade) is the photo bake's rule instead: a seen
  // vertex takes its blend, alpha 1; the others the fill in linear light
  // (kProject acts as kFill) or the constant, and a component no photo
  // sees the constant (bake/photo/photo_bake.h).
  kImage,
};

struct LayersBakeOptions {
  LayerBase base = LayerBase::kNone;
  Rgba base_color{0, 0, 0, 0};  // sRGB-encoded, straight alpha (LayerBase::kColor)
  OccludedMode occluded = OccludedMode::kFill;
  Rgba occluded_color{0, 0, 0, 1};  // sRGB-encoded; its RGB is used, alpha stays 0
  // The memory budget in MiB (--cache-mb) for each layer's texture and
  // mask, as the API reads them (texbake/texbake.h): past it they are read
  // in tiles through OpenImageIO's ImageCache (mesh_io/image_io.h); 0: decoded whole.
  std::size_t cache_mb = kDefaultCacheMb;
  // A "cameras" layer's photo that cannot be read is left out with a
  // warning (LayerStats::skipped); with strict_photos it is an error.
  bool strict_photos = false;
  // A "cameras" layer's photos that disagree on the mesh are a warning
  // (PhotoBakeOptions::consistency_warning); off with --no-alignment-check.
  bool consistency_warning = true;
  // The result's alpha and which samples the fill resolves (ResultAlpha).
  ResultAlpha alpha = ResultAlpha::kCoverage;
  // A scene already built over the mesh (EmbreeScene::build) for the
  // visibility rays, instead of building one; not owned. The same results.
  const EmbreeScene* scene = nullptr;
};

struct LayerStats {
  std::string name;
  // Seconds spent on this layer: its preparation, its share of the layers
  // stage (by the threads' time in it) and of the atlas target's fill, plus
  // for a "cameras" layer the photo bake.
  double seconds = 0;
  bool photos = false;        // a "cameras" layer (name: its model or list)
  std::size_t in_domain = 0;  // samples the projector maps inside its (u, v) domain
  std::size_t visible = 0;    // of the mapped samples, those it sees
  std::size_t blended = 0;    // samples with a > 0
  double mean_alpha = 0;      // mean a over all samples
  // The lookups (the vertex target's filter's: kArea one per share point,
  // the fallbacks' included; the atlas target's: one per coloured sample)
  // and of those the ones outside the (u, v) domain; samples mapped but not
  // seen (a blocked ray, a camera facing away); samples without a mapping
  // (or whose area filter found none).
  std::size_t lookups = 0, outside = 0, hidden = 0, unmapped = 0;
  std::vector<SkippedPhoto> skipped;  // a "cameras" layer: its photos left out
};

struct LayersBakeResult {
  // Per vertex, sRGB-encoded RGB, straight alpha = coverage (ResultAlpha::kImage:
  // the image's alpha; a "cameras" layer's 1, or the --occluded colour's).
  std::vector<Rgba> colors;
  std::vector<LayerStats> layers;
  std::size_t uncovered = 0;  // vertices with coverage 0 (kImage: the unknown vertices)
  std::size_t filled = 0;     // of those, coloured by the fill
  std::size_t unfilled = 0;   // of those, in components the fill could not reach
  double seconds_scene = 0, seconds_layers = 0, seconds_fill = 0;
};

// Errors: kInvalidArgument (no layers; base "mesh" on a mesh without vertex
// colours; an empty texture; under ResultAlpha::kImage a stack that is not
// one bare layer: in the stored encoding or straight linear light, or one
// "cameras" layer),
// kParse (a tiled texture's tiles could not be read), kInternal (Embree, the fill), kCancelled
// (progress's callback returned false: the remaining blocks and the fill
// are skipped). progress may be null; it hears the stages "bake" (the
// blocks of vertices through every layer) and "fill", as the proxy vertex
// bake's.
Expected<LayersBakeResult> bake_vertex_layers(const MeshData& mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersBakeOptions& options,
                                              Progress* progress = nullptr);

// The same in two steps, for callers that free the images before the
// fill's solve (the memory peak): bake_vertex_layers_sample does all that
// reads the images (the layers, the fill's plan and fallbacks; stage
// "bake"); bake_vertex_layers_finish solves the fill and encodes the
// colours. bake_vertex_layers = finish(sample(...)) with the stage "fill"
// around the finish.
struct LayersVertexStage {
  LayersBakeResult result;  // colours still in the working space
  VertexResolvePlan plan;
};
Expected<LayersVertexStage> bake_vertex_layers_sample(const MeshData& mesh,
                                                      const std::vector<LayerInput>& layers,
                                                      const LayersBakeOptions& options,
                                                      Progress* progress = nullptr);
Expected<LayersBakeResult> bake_vertex_layers_finish(const MeshData& mesh, LayersVertexStage stage);

// ---- The atlas target -------------------------------------------------------
//
// bake_atlas_layers: the supersamples of the atlas (bake/atlas/atlas_raster.h,
// streamed band by band like bake/engine/bake_atlas.h) take the place of the
// vertices: each sample's point (barycentric on its triangle) and its
// interpolated smooth vertex normal (normalised; the face's when they cancel)
// go through every layer as above, composited over the sample's base:
//  - "none": B = 0, alpha 0; a colour: its linear RGB and alpha;
//  - "mesh" with options.base_texture (the mesh's own texture; uv_mesh must
//    carry the mesh's own UVs, the layout the texture was painted in): the
//    texture's bilinear lookup (premultiplied linear, then straight) at the
//    centre of the sample's TEXEL, so that all samples of a texel share the
//    base and an atlas at the texture's size keeps it exactly where no layer
//    reaches (the texture is resampled to the atlas grid at other sizes);
//  - "mesh" without a texture: the mesh's vertex colours (linearised)
//    interpolated barycentrically over the sample's triangle.
// Texel = the mean of its samples in premultiplied linear light (so the
// coverage averages: a texel half covered by an opaque layer over "none" has
// alpha 0.5 and the layer's colour), written straight-alpha, sRGB-encoded.
// A texel none of whose samples is covered (alpha 0) takes, under kFill, the
// mean of its samples' fill colours: the vertex target's result on uv_mesh
// (bake_vertex_layers over the same scene, with the bilinear lookup; base
// "none" when the base is the texture) interpolated barycentrically; under
// kColor the constant's RGB exactly; alpha stays 0.
// Under ResultAlpha::kImage (the single projection, SPEC section 4) a
// texel is instead the plain mean of its samples' RGBA in the layer's
// working space (alpha a colour channel): a seen sample's lookup (outside
// the domain: the clamped lookup or the --outside colour), a hidden one's
// under kProject; hidden samples under kFill and unmapped ones under kFill
// or kProject take the fill (the vertex target under kImage with kFill,
// interpolated over the sample's triangle), added after the coloured
// samples; under kColor such samples take the constant, and a texel all of
// whose samples take it is the constant exactly. With visibility and kFill
// the fill is computed before the pass; otherwise only the texels that
// need it wait for the pass's end. Padding:
// pad_atlas (bake/atlas/atlas_common.h) as `padding` says. Layer stats count
// samples (in_domain, visible, blended, hidden, unmapped; lookups, one per
// coloured sample, and of those the ones outside the domain; mean alpha
// over all samples), after the overlap choice (resolve_overlaps).
// Memory: the atlas, every layer's working image, and one band of samples
// per thread. Results do not depend on the thread count.

struct LayersAtlasOptions {
  int size = 2048;           // texels per side, 1 .. kMaxAtlasSize
  int samples = 4;           // supersamples per covered texel, 1 .. kMaxAtlasSamples
  int padding = -1;          // as AtlasBakeOptions::padding (kPaddingDefault = -1)
  LayersBakeOptions layers;  // base (+ colour), occluded (+ colour), alpha, scene
  ImageView base_texture;    // base "mesh": the mesh's texture (data null: its vertex colours)
  // An overlapping layout (texels under several UV triangles: --uv proxy on
  // a mesh that is not star-shaped as seen from the projector, --uv mesh
  // with shared UVs): a sample inside several triangles takes the
  // lowest-index one that some layer sees (visibility "first"; if none
  // does, the lowest-index one, as without), so shared texels take the
  // visible surface's colour. Costs a full candidate scan per sample and
  // every layer's lookup at each further candidate. Not with a "cameras"
  // layer (its blend is per sample): then ignored.
  bool resolve_overlaps = false;
};

// The atlas options of a single projection (ResultAlpha::kImage, its
// occluded rule; size, samples, padding) for bake_atlas_layers.
LayersAtlasOptions single_projection_atlas(int size, int samples, int padding,
                                           OccludedMode occluded, const Rgba& occluded_color);

struct LayersAtlasResult {
  Image atlas;                     // size x size RGBA, sRGB-encoded, straight alpha = coverage
  std::vector<uint8_t> baked;      // size * size: 1 where covered by the layout
  std::vector<LayerStats> layers;  // per layer, over the atlas samples
  std::size_t texels = 0, samples = 0, border_samples = 0;
  // kCoverage only (under ResultAlpha::kImage alpha is the image's: 0 and
  // true): samples with coverage 0, and whether every covered texel has
  // alpha 1.
  std::size_t uncovered = 0;
  std::size_t padded = 0;  // texels filled by padding
  bool opaque = true;
  // The fill's vertex target (when a fill ran): its vertices filled, and
  // those in components it could not reach.
  std::size_t vertices_filled = 0, vertices_unfilled = 0;
  // seconds_raster and seconds_layers split the band pass's wall time by
  // the threads' time in rasterising and in the layers.
  double seconds_raster = 0, seconds_fill = 0, seconds_scene = 0, seconds_layers = 0;
  double seconds_pad = 0;
};

// uv_mesh: a mesh with per-corner UVs covering its triangles (as for
// bake_atlas). Errors: kInvalidArgument (no layers, an empty image, a bad
// padding, base "mesh" with neither a texture nor vertex colours, under
// ResultAlpha::kImage a stack that is not one bare layer), kParse (a tiled
// texture's tiles could not be read),
// rasterize_atlas's (bad size or samples, no UVs, bad UVs), kInternal
// (Embree, the fill), kCancelled (progress's callback; stage "sample", per
// band).
Expected<LayersAtlasResult> bake_atlas_layers(const MeshData& uv_mesh,
                                              const std::vector<LayerInput>& layers,
                                              const LayersAtlasOptions& options,
                                              Progress* progress = nullptr);

}  // namespace texbake
