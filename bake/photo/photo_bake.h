// Colouring a mesh's vertices from several calibrated photographs (SPEC
// section 9, `bake --cameras`): every vertex is carried through each
// camera's lens model (mapping/camera.h, forward distortion; no photo is
// undistorted or resampled), tested for visibility along the segment to the
// camera's centre, and the photos that see it are blended per vertex in
// linear light with exposure gains.
//
// Per camera, in order (photos are read one at a time, the next one while
// this one is baked, so memory holds two photos plus the samples):
//  1. cull: the vertex projects inside the photo, in front of the camera,
//     with its smooth normal within 75 degrees of d = normalize(C - P)
//     (back-facing and grazing points are not seen);
//  2. visibility: the segment from P to C hits no triangle (Embree, tnear
//     and tfar pulled in by the relative offset of bake/trace/visibility.h);
//  3. sample: the photo's bilinear sample at the camera's (u, v), sRGB
//     decoded to linear, and the quality q = cos(theta) (f / z)^2 border
//     (f the mean focal length, z the depth, border rising from 0 at the
//     photo's edge to 1 at 5 % of min(W, H) inside).
// Then: exposure gains (ExposureMode::kGain: per photo and channel, least
// squares in the log domain over pairs of photos seeing the same vertex,
// log g_a + log c_a = log g_b + log c_b, pairs with a near-black value left
// out, with the gains' geometric mean fixed at 1 and a weak prior towards 1
// for photos that share no vertex: a photo scaled by s gets 1 / s times its
// gain; a photo that sees no vertex takes no part and keeps gain 1); the
// blend (soft: weights exp(-(1 - q / q_max) / 0.1), best: the largest q,
// mean: equal), each weight times the sample's mask value (see "Masks"
// below; a pair in the gain solve weighs the product of its two mask
// values); unseen vertices follow `occluded`
// (the harmonic fill of bake/vertex/occlusion_fill.h by default). Results do
// not depend on the thread count. The cull, quality, weights and photo
// reading are bake/photo/photo_view.h's, shared with the atlas target
// (bake/engine/photo_atlas.h), which runs this bake first. The blend is
// blend_vertex_photos below; the unseen vertices are resolved by the bake
// engine (bake/engine/photo_vertex.h: the blend as one "cameras" layer
// under the single projection's rule).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "bake/shade/options.h"
#include "mapping/camera.h"
#include "mapping/error.h"
#include "mapping/image_view.h"
#include "mapping/sample.h"
#include "mesh_io/image_io.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// One photograph and the camera that took it.
struct Photo {
  std::string name;  // for messages and the report (COLMAP's image name)
  CameraProjector camera;
  std::filesystem::path path;  // the photo's file
  // Its mask file in COLMAP's convention (--masks DIR: DIR/<name>.png; see
  // "Masks" below), or empty: the photo's own alpha only.
  std::filesystem::path mask;
};

// Masks (SPEC section 9). A photo's alpha channel is its mask: each sample's
// weight is multiplied by the alpha bilinearly interpolated at the camera's
// (u, v), and its colour is the alpha-weighted bilinear mean of the four
// texels (the photo is premultiplied by alpha in linear light, sampled, and
// divided by the sampled alpha), so masked-out texels never bleed into the
// colour. Alpha 0 there: the photo does not see the point at all (not in
// view, not visible, not in the blend, q_max or the exposure solve). A mask
// file (Photo::mask) follows COLMAP's rule, binary: a pixel whose value is 0
// (every colour channel 0) is masked out, any other value keeps the pixel
// whole (a grey 128 counts as 255, as in COLMAP's feature extraction); it
// multiplies the photo's own alpha. It must have the photo's size. A photo
// without alpha and mask is sampled exactly as before masks existed.

enum class PhotoBlend { kSoft, kBest, kMean };
enum class ExposureMode { kGain, kNone };

struct PhotoImage;

struct PhotoBakeOptions {
  PhotoBlend blend = PhotoBlend::kSoft;
  ExposureMode exposure = ExposureMode::kGain;  // ignored with a single photo
  OccludedMode occluded =
      OccludedMode::kFill;          // for vertices no photo sees (kProject acts as kFill)
  Rgba occluded_color{0, 0, 0, 1};  // sRGB-encoded, with OccludedMode::kColor
  // The largest angle (degrees, in (0, 90]) between a point's normal and the
  // direction to a camera at which the camera still sees it: SPEC section
  // 9's 75 for several photos; 90 for one camera given as a proxy (a point
  // is then seen unless it faces away).
  double max_view_angle_deg = 75;
  // How the photos' colour space is taken (--texture-colorspace).
  TextureColorSpace color_space = TextureColorSpace::kAuto;
  // Keep the blend per point (PhotoPoints below: a "cameras" layer,
  // bake/engine/layers_bake.h, composites it instead of the colours): the
  // vertex photo bake returns it, with the blend's cosines
  // (blend_vertex_photos and blend_atlas_photos always give the states and
  // colours, their cosines only with this; bake_atlas_from_photos ignores
  // it and returns no points).
  bool keep_points = false;
  // Called with each photo the bake uses (its index among them, as in
  // PhotoBakeResult::cameras), its image as loaded (linear light, alpha its
  // mask; photo_view.h load_photo) and whether it is masked (some alpha
  // below 1: PhotoCameraStats::masked), before the bake samples it; empty:
  // not called. The photo atlas keeps the masks from it, so that its later
  // passes need not read and decode the photos again for them.
  std::function<void(std::size_t, const PhotoImage&, bool masked)> on_photo;
  // A photo that cannot be read (missing, unreadable, not an image: its
  // reader's error) is left out with a warning and listed in `skipped`
  // (SPEC section 9); with strict_photos it is an error (--strict-photos).
  bool strict_photos = false;
  // Warn (PhotoBakeResult::warnings) when the photos disagree on the mesh
  // (photo_consistency_warning below); off with --no-alignment-check.
  bool consistency_warning = true;
};

// A photo left out of a bake because it cannot be read.
struct SkippedPhoto {
  std::string name;            // Photo::name
  std::filesystem::path path;  // Photo::path
  std::string reason;          // the reader's error
};

// The blend of every point (vertex, or atlas supersample) before any fill
// (PhotoBakeOptions::keep_points): what a "cameras" layer composites.
struct PhotoPoints {
  enum State : uint8_t {
    kNoView = 0,  // in no camera's view (outside every photo, behind, or turned away)
    kInView = 1,  // in some camera's view (the cull), but occluded from all of them
    kSeen = 2,    // seen by at least one camera: rgb and cosine hold its blend
  };
  std::vector<uint8_t> state;
  std::vector<std::array<float, 3>>
      rgb;  // the blend in linear light, gains applied (0 unless kSeen)
  // The blend-weighted mean of cos(theta) between the point's normal and the
  // directions to the cameras that see it (1 unless kSeen): a layer's angle
  // fade takes this angle.
  std::vector<float> cosine;
  std::size_t size() const { return state.size(); }
};

struct PhotoCameraStats {
  std::string name;
  std::size_t in_view = 0;              // vertices inside the photo, in front and facing the camera
  std::size_t visible = 0;              // of those, the segment to the camera is free
  double weight_share = 0;              // its share of all blend weights (sums to 1 over cameras)
  std::array<double, 3> gain{1, 1, 1};  // exposure gain per channel (linear light)
  int photo_width = 0, photo_height = 0;
  bool scaled = false;  // the photo has the camera's aspect at another size
  // Photo-consistency (PhotoConsistency below): the vertices it sees with
  // another photo, and its mean relative deviation from their consensus.
  std::size_t shared = 0;
  double deviation = 0;
  // The photo has a mask: its alpha (times its mask file's) is below 1
  // somewhere; masked_share is the share of its pixels at 0 (masked out).
  bool masked = false;
  double masked_share = 0;
};

// How well the photos agree on the mesh, after the exposure gains (SPEC
// section 9, "Alignment"): over the vertices seen by two photos or more,
// each photo's gain-corrected luminance Y_i (linear light, Rec. 709
// weights) against their median m: the vertex's deviation is the mean of
// |Y_i - m| / max(m, 0.05) (for two photos |Y_1 - Y_2| / (Y_1 + Y_2)); a
// vertex agrees when its deviation is at most kAgreeDeviation. Cameras that
// see the mesh where they should agree up to lighting and resampling; a
// model in another frame, or poses off by many pixels, makes each photo
// show another part of the surface at a vertex. A mesh of one colour agrees
// under any pose, so the figures can only raise a doubt, never prove a model
// misaligned (the sparse points do that: bake/fit/model_alignment.h).
inline constexpr double kAgreeDeviation = 0.1;
struct PhotoConsistency {
  std::size_t vertices = 0;  // vertices seen by two photos or more
  double agreeing = 0;       // their share whose deviation is <= kAgreeDeviation
  double median_deviation = 0;
  double gain_ratio = 1;  // the largest gain over the smallest, any channel
};

struct PhotoBakeResult {
  std::vector<Rgba> colors;  // one per vertex, sRGB-encoded, alpha 1
  std::vector<PhotoCameraStats> cameras;
  std::size_t seen = 0;      // vertices seen by at least one photo
  std::size_t filled = 0;    // unseen vertices coloured by the fill
  std::size_t unfilled = 0;  // unseen vertices in components no photo sees
  std::vector<std::string> warnings;
  // Photos left out (unreadable), in photo order; `cameras` has the others'
  // entries only, in photo order.
  std::vector<SkippedPhoto> skipped;
  // Per vertex: bake_vertex_from_photos with PhotoBakeOptions::keep_points
  // (else empty); blend_vertex_photos always (cosine 1 without keep_points).
  PhotoPoints points;
  PhotoConsistency consistency;
  double seconds_scene = 0, seconds_photos = 0, seconds_blend = 0, seconds_fill = 0;
};

// Reads one photo: an RGBA float image, top row first, and the encoding of
// its values (sRGB for 8/16-bit photos, linear for EXR: mesh_io's rules).
// The default reads the file with mesh_io's read_image.
struct PhotoImage {
  int width = 0, height = 0;
  std::vector<float> pixels;
  ColorSpace color_space = ColorSpace::kSrgb;
};
using PhotoReader = std::function<Expected<PhotoImage>(const Photo& photo)>;

// bake_vertex_from_photos (bake/engine/photo_vertex.h) errors: a photo
// that cannot be read with options.strict_photos ("the
// photo of camera NAME: " and its reader's error; else it is left out with
// a warning), every photo left out (kIo "no usable photo: ..."), a photo
// whose size is neither the camera's nor of the same aspect (kParse, naming
// the photo and both sizes), a mask file that cannot be read or is of
// another size than its photo ("the mask of camera NAME: " naming the file;
// always an error: the photo without its mask would bake what the mask
// hides), no photos (kInvalidArgument), kInternal
// (Embree or the fill). A reader's kCancelled is returned as is. A photo of the same aspect and
// another size is used with the camera's (u, v) (which do not depend on the resolution) and a
// warning.
// The warning the bake gives (with consistency_warning) when the photos'
// agreement is doubtful: at least kConsistencyMinVertices vertices seen by
// several photos of which fewer than kConsistencyDoubtful agree, or exposure
// gains spread wider than kGainRatioDoubtful (a photo matched against the
// wrong part of the surface is "corrected" towards it). Empty: no doubt.
inline constexpr std::size_t kConsistencyMinVertices = 100;
inline constexpr double kConsistencyDoubtful = 0.5;
inline constexpr double kGainRatioDoubtful = 4;
std::string photo_consistency_warning(const PhotoConsistency& c);

// "62 % of 5120 vertices seen by several photos agree within 10 %, median
// deviation 4.1 %, gains within 1.3x": the figures as one phrase.
std::string consistency_figures(const PhotoConsistency& c);

// The blend per vertex (stages cull, visibility, sample, gains and blend
// above), before any fill: result.points holds every vertex's (state, rgb;
// cosine with options.keep_points, else 1), `seen`, the cameras' stats,
// warnings, skipped photos and consistency; colors, filled and unfilled
// are left empty (0). The vertex photo bake (bake/engine/photo_vertex.h)
// is this blend as a "cameras" layer through the bake engine, which
// resolves the unseen vertices. Errors: the above but the fill's.
Expected<PhotoBakeResult> blend_vertex_photos(const MeshData& mesh,
                                              const std::vector<Photo>& photos,
                                              const PhotoBakeOptions& options,
                                              const PhotoReader& reader = {});

}  // namespace texbake
