// The vertex photo bake (SPEC section 9, `bake --cameras`; the rules are
// bake/photo/photo_bake.h's): the photos' blend per vertex
// (blend_vertex_photos, streamed one photo at a time) as one "cameras"
// layer through the bake engine's vertex target under the single
// projection's rule (bake/engine/layers_bake.h ResultAlpha::kImage): a seen
// vertex takes its blend, alpha 1; the others the fill in linear light
// (--occluded project acts as fill) or the --occluded colour as given, and
// a component no photo sees that colour.
#pragma once

#include <vector>

#include "bake/photo/photo_bake.h"
#include "mapping/error.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

// Errors: blend_vertex_photos's (bake/photo/photo_bake.h), kInternal (the
// fill). result.points is kept with options.keep_points, else empty.
Expected<PhotoBakeResult> bake_vertex_from_photos(const MeshData& mesh,
                                                  const std::vector<Photo>& photos,
                                                  const PhotoBakeOptions& options,
                                                  const PhotoReader& reader = {});

}  // namespace texbake
