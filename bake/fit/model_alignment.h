// Is a camera model in the mesh's frame? (SPEC section 9, "Alignment".) A
// structure-from-motion model carries sparse 3D points (COLMAP's points3D):
// in the mesh's frame, most of those inside the mesh's bounding box lie on
// its surface; in the model's own frame (a raw reconstruction, never
// aligned), almost none do. The distance of each point to the surface is
// CGAL's (an AABB tree of the mesh's triangles; only bake/fit includes CGAL).
//
// The figures, with D the diagonal of the mesh's bounding box:
//  - in the box: points within the box grown by 10 % of D on every side
//    (points of the background, far from the object, are not counted
//    against it);
//  - near: of those, the points within 1 % of D of the surface;
//  - the median distance of the points in the box, relative to D.
// The verdict: misaligned when fewer than 10 % of the points in the box are
// near (or none is in the box), doubtful below 40 %, aligned otherwise; not
// measured with fewer than 20 points. Results do not depend on the thread
// count.
#pragma once

#include <cstddef>
#include <span>
#include <string>

#include "mapping/error.h"
#include "mapping/vec.h"
#include "mesh_io/mesh_data.h"

namespace texbake {

inline constexpr double kAlignmentBoxMargin = 0.10;     // of the diagonal
inline constexpr double kAlignmentNearDistance = 0.01;  // of the diagonal
inline constexpr double kAlignmentMisaligned = 0.10;    // share near below: misaligned
inline constexpr double kAlignmentDoubtful = 0.40;      // share near below: doubtful
inline constexpr std::size_t kAlignmentMinPoints = 20;
inline constexpr std::size_t kAlignmentMaxPoints = 200000;  // measured (evenly strided)

enum class AlignmentVerdict { kNotMeasured, kAligned, kDoubtful, kMisaligned };

struct ModelAlignment {
  std::size_t points = 0;      // sparse points in the model
  std::size_t measured = 0;    // of those, measured (every k-th past kAlignmentMaxPoints)
  std::size_t in_box = 0;      // measured points in the grown box
  std::size_t near = 0;        // of those, within kAlignmentNearDistance of the surface
  double median_distance = 0;  // of the points in the box, relative to the diagonal
  AlignmentVerdict verdict = AlignmentVerdict::kNotMeasured;

  double share_near() const {
    return in_box ? static_cast<double>(near) / static_cast<double>(in_box) : 0;
  }
};

// The figures and the verdict for `points` against `mesh` (its triangles).
// `threads`: 0 for all cores. Errors: kInvalidArgument for a mesh without a
// triangle of non-zero area.
Expected<ModelAlignment> measure_model_alignment(const MeshData& mesh, std::span<const Vec3> points,
                                                 int threads = 0);

// "N of M sparse points in the mesh's box, P % of them within 1 % of its
// size of the surface (median distance Q % of its size)".
std::string alignment_figures(const ModelAlignment& a);

// "aligned", "doubtful", "misaligned", "not measured".
const char* to_string(AlignmentVerdict verdict);

}  // namespace texbake
