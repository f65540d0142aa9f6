// What the atlas bakes share (the proxy, photo and layers atlases): the
// padding of the background, the EWA footprint of a supersample, and a
// mesh with a generated layout's per-corner UVs.
//
// Padding (--padding), after the covered texels are baked:
//  - kPaddingDefault: default_padding(size) rings of 8-neighbour dilation
//    (all four channels: the rings are opaque), then push-pull of the
//    colour over the rest of the background with alpha 0
//    (PushPullMode::kMipSafe). Every texel then holds a chart colour or a
//    smooth continuation of the charts, so the box-filtered mip levels a
//    client builds never average in black; alpha still says which texels
//    are baked (or padding rings) for clients that use it;
//  - N >= 0: N rings of dilation only, the rest transparent black (0 = none);
//  - kPaddingInfinite: push-pull of all four channels over the whole
//    background (an opaque atlas).
// Covered texels are never changed by the padding.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "mapping/error.h"
#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// default_padding(size) rings (bake/atlas/dilate.h), then push-pull colour, alpha 0
inline constexpr int kPaddingDefault = -1;
inline constexpr int kPaddingInfinite = -2;  // push-pull fill of the whole background, opaque

// kInvalidArgument unless padding is a texel count 0 .. kMaxAtlasSize or
// one of the constants: "--padding N is not a texel count (0 ..
// kMaxAtlasSize) or 'inf'".
Status check_padding(int padding);

// pad_atlas: pads a size x size RGBA atlas (sRGB-encoded) whose
// covered texels are `baked`, as `padding` says (a count >= 0,
// kPaddingDefault or kPaddingInfinite: see the file comment). Returns the
// texels filled. Shared with the photo atlas (bake/engine/photo_atlas.h).
std::size_t pad_atlas(std::span<float> rgba, std::span<const uint8_t> baked, int size, int padding);

// --filter ewa on the atlas (the proxy atlas and the layers engine share it):
// the surface footprint of a supersample on triangle t of uv_mesh, the 3D
// vectors of `cell` (atlas UV units) step in the atlas's u and in its v (the
// triangle's UV-to-3D map is affine); a triangle whose UVs are degenerate
// has none (zero vectors: bilinear). ewa_cell(size, samples) is that cell
// step: the supersample's cell side 1 / (size sqrt(samples)) over sqrt(2)
// (the ellipse through the cell's corners), 0.85 of it at one sample per texel.
void cell_tangents(const MeshData& uv_mesh, uint32_t t, double cell, Vec3& ts, Vec3& tt);
double ewa_cell(int size, int samples);

// A copy of `mesh` whose faces are its triangles, with per-corner UVs from a
// per-triangle UV table (triangle_uvs[t][k] indexes uvs for corner k of
// mesh.triangles[t], as --uv generate produces it). Normals are carried over
// per corner if present. Precondition: triangle_uvs.size() == mesh.triangles.size().
MeshData mesh_with_triangle_uvs(const MeshData& mesh, const std::vector<Float2>& uvs,
                                const std::vector<std::array<uint32_t, 3>>& triangle_uvs);

}  // namespace texbake
