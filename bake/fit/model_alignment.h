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

#include <array>
#include <cstddef>
#include <span>
#include <string>

#include "mapping/camera.h"
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

// The diagonal of the bounding box of the mesh's vertices (D above).
double bounding_diagonal(const MeshData& mesh);

// "N of M sparse points in the mesh's box, P % of them within 1 % of its
// size of the surface (median distance Q % of its size)".
std::string alignment_figures(const ModelAlignment& a);

// "aligned", "doubtful", "misaligned", "not measured".
const char* to_string(AlignmentVerdict verdict);

// ---- Bringing a model into the mesh's frame (texbake cameras align) ----

// A similarity X' = scale R X + t (R a rotation, row by row).
struct Similarity {
  double scale = 1;
  std::array<double, 9> r{1, 0, 0, 0, 1, 0, 0, 0, 1};
  Vec3 t;

  Vec3 apply(Vec3 x) const {
    return Vec3{r[0] * x.x + r[1] * x.y + r[2] * x.z, r[3] * x.x + r[4] * x.y + r[5] * x.z,
                r[6] * x.x + r[7] * x.y + r[8] * x.z} *
               scale +
           t;
  }
};

// A 4x4 matrix (16 numbers, row by row) as a similarity: the last row
// 0 0 0 1, the upper 3x3 a positive scale times a rotation (columns
// orthogonal and of equal length within 1e-6 relative, determinant > 0).
// Errors (kInvalidArgument) name `what` and say which condition fails.
Expected<Similarity> similarity_from_matrix(std::span<const double> m, const std::string& what);

// The camera seeing the world moved by `s` as it saw the world before: the
// world-to-camera pose R_c, t_c becomes R_c R^T, scale t_c - R_c R^T t (the
// centre C becomes s(C)); the intrinsics are kept.
Expected<CameraProjector> transform_camera(const CameraProjector& camera, const Similarity& s);

// The least-squares similarity taking each model[i] onto mesh[i] (Umeyama's
// closed form, Eigen) and how well the pairs agree with it: the RMS and the
// largest of |s(model[i]) - mesh[i]| and the index of that largest one.
struct PairFit {
  Similarity transform;  // model -> mesh
  double rms = 0;
  double largest = 0;
  std::size_t worst = 0;
};

// Errors (kInvalidArgument): the spans differ in size, fewer than 3 pairs,
// a point not finite, either side's points on one line or at one place
// (their spread's second axis below 1e-6 of the first: the rotation about
// that line is not determined). The rotation is always proper (Umeyama's
// sign correction): pairs of a mirrored frame show as large residuals.
Expected<PairFit> similarity_from_pairs(std::span<const Vec3> model, std::span<const Vec3> mesh);

struct ModelFit {
  Similarity transform;    // model -> mesh
  ModelAlignment before;   // the points as given
  ModelAlignment after;    // the points moved by `transform`
  double trimmed_rms = 0;  // of the best 70 % of the points, relative to the diagonal
  int candidates = 0;      // initial guesses tried
};

// The similarity that brings a model's sparse points onto the surface of
// `mesh`: a global initial guess (the principal axes and spread of the
// points against those of the surface, each of the 24 ways to match the
// axes with a proper rotation), each refined by trimmed ICP with scale
// (closest points on the triangles, CGAL; the 70 % nearest kept;
// point-to-point steps by Umeyama's least-squares similarity, Eigen), the
// best three refined further, point-to-point then point-to-plane (the
// linearised similarity step along the surface normals), the one of least
// trimmed RMS kept. At most 10000 points are used (evenly strided; 1500 for
// the 24 guesses). Errors: kInvalidArgument (fewer than kAlignmentMinPoints
// points, a mesh without area), kInternal.
Expected<ModelFit> fit_model_to_mesh(const MeshData& mesh, std::span<const Vec3> points,
                                     int threads = 0);

}  // namespace texbake
