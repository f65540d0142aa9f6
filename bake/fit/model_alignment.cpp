#include "bake/fit/model_alignment.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <vector>

#include "bake/util/parallel.h"

namespace texbake {

namespace {

using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Triangles = std::vector<K::Triangle_3>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

K::Point_3 point(const Float3& p) {
  return {p.x, p.y, p.z};
}

// The mesh's surface for closest-point queries, and its bounding box.
struct Surface {
  Triangles triangles;
  Tree tree;
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  double diagonal = 0;
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // area-weighted
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

Status build_surface(const MeshData& mesh, Surface& s) {
  double area = 0;
  for (const auto& t : mesh.triangles) {
    K::Triangle_3 tri(point(mesh.positions[t[0]]), point(mesh.positions[t[1]]),
                      point(mesh.positions[t[2]]));
    if (tri.is_degenerate()) continue;
    s.triangles.push_back(tri);
  }
  if (s.triangles.empty()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "the mesh has no triangle of non-zero area to measure the model against");
  }
  // Area-weighted centroids: the surface's centre and spread.
  std::vector<std::pair<Eigen::Vector3d, double>> centres;
  for (const K::Triangle_3& t : s.triangles) {
    const double a = std::sqrt(t.squared_area());
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int k = 0; k < 3; ++k) c += Eigen::Vector3d(t[k].x(), t[k].y(), t[k].z()) / 3;
    centres.push_back({c, a});
    s.centroid += a * c;
    area += a;
  }
  s.centroid /= area;
  for (const auto& [c, a] : centres) {
    const Eigen::Vector3d d = c - s.centroid;
    s.covariance += a * d * d.transpose();
  }
  s.covariance /= area;
  for (const Float3& p : mesh.positions) {
    s.lo = {std::min(s.lo.x, double{p.x}), std::min(s.lo.y, double{p.y}),
            std::min(s.lo.z, double{p.z})};
    s.hi = {std::max(s.hi.x, double{p.x}), std::max(s.hi.y, double{p.y}),
            std::max(s.hi.z, double{p.z})};
  }
  s.diagonal = bounding_diagonal(mesh);
  s.tree.insert(s.triangles.begin(), s.triangles.end());
  s.tree.build();
  s.tree.accelerate_distance_queries();
  return ok_status();
}

// measure_model_alignment on a surface already built (fit_model_to_mesh
// measures before and after on the one it fits to).
ModelAlignment measure_on(const Surface& surface, std::span<const Vec3> points, int threads) {
  ModelAlignment a;
  a.points = points.size();
  if (points.size() < kAlignmentMinPoints) return a;  // too few to judge
  const Vec3 lo = surface.lo, hi = surface.hi;
  const double diagonal = surface.diagonal;
  const double margin = kAlignmentBoxMargin * diagonal;
  const double near = kAlignmentNearDistance * diagonal;

  // Every k-th point past kAlignmentMaxPoints: a model of millions of
  // points is judged as well by a fifth of them.
  const std::size_t stride = (points.size() + kAlignmentMaxPoints - 1) / kAlignmentMaxPoints;
  std::vector<Vec3> measured;
  for (std::size_t i = 0; i < points.size(); i += stride) measured.push_back(points[i]);
  a.measured = measured.size();

  // Per point: its distance, or -1 outside the grown box (no query).
  std::vector<double> distance(measured.size(), -1);
  run_in_arena(threads, [&] {
    parallel_for_chunks(measured.size(), 1024, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const Vec3 p = measured[i];
        if (p.x < lo.x - margin || p.y < lo.y - margin || p.z < lo.z - margin ||
            p.x > hi.x + margin || p.y > hi.y + margin || p.z > hi.z + margin) {
          continue;
        }
        distance[i] = std::sqrt(surface.tree.squared_distance(K::Point_3(p.x, p.y, p.z)));
      }
    });
  });
  std::vector<double> in_box;
  for (double d : distance) {
    if (d < 0) continue;
    in_box.push_back(d);
    if (d <= near) ++a.near;
  }
  a.in_box = in_box.size();
  if (!in_box.empty()) {
    const auto mid = in_box.begin() + static_cast<std::ptrdiff_t>(in_box.size() / 2);
    std::nth_element(in_box.begin(), mid, in_box.end());
    a.median_distance = diagonal > 0 ? *mid / diagonal : 0;
  }
  const double share = a.share_near();
  a.verdict = share < kAlignmentMisaligned ? AlignmentVerdict::kMisaligned
              : share < kAlignmentDoubtful ? AlignmentVerdict::kDoubtful
                                           : AlignmentVerdict::kAligned;
  return a;
}

}  // namespace

Expected<ModelAlignment> measure_model_alignment(const MeshData& mesh, std::span<const Vec3> points,
                                                 int threads) {
  if (points.size() < kAlignmentMinPoints) return measure_on(Surface{}, points, threads);
  Surface surface;
  if (Status s = build_surface(mesh, surface); !s) return s.error();
  return measure_on(surface, points, threads);
}

double bounding_diagonal(const MeshData& mesh) {
  if (mesh.positions.empty()) return 0;
  Vec3 lo{mesh.positions[0].x, mesh.positions[0].y, mesh.positions[0].z}, hi = lo;
  for (const Float3& p : mesh.positions) {
    lo = {std::min(lo.x, double{p.x}), std::min(lo.y, double{p.y}), std::min(lo.z, double{p.z})};
    hi = {std::max(hi.x, double{p.x}), std::max(hi.y, double{p.y}), std::max(hi.z, double{p.z})};
  }
  return length(hi - lo);
}

std::string alignment_figures(const ModelAlignment& a) {
  char text[256];
  std::snprintf(text, sizeof text,
                "%zu of %zu sparse points in the mesh's box, %.1f %% of them within %g %% of its "
                "size of the surface (median distance %.2g %% of its size)",
                a.in_box, a.measured, 100 * a.share_near(), 100 * kAlignmentNearDistance,
                100 * a.median_distance);
  return text;
}

const char* to_string(AlignmentVerdict verdict) {
  switch (verdict) {
    case AlignmentVerdict::kNotMeasured:
      return "not measured";
    case AlignmentVerdict::kAligned:
      return "aligned";
    case AlignmentVerdict::kDoubtful:
      return "doubtful";
    case AlignmentVerdict::kMisaligned:
      return "misaligned";
  }
  return "";
}

namespace {

Eigen::Matrix3d rotation_of(const Similarity& s) {
  Eigen::Matrix3d r;
  r << s.r[0], s.r[1], s.r[2], s.r[3], s.r[4], s.r[5], s.r[6], s.r[7], s.r[8];
  return r;
}

Similarity similarity_of(double scale, const Eigen::Matrix3d& r, const Eigen::Vector3d& t) {
  Similarity s;
  s.scale = scale;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) s.r[3 * i + j] = r(i, j);
  }
  s.t = {t.x(), t.y(), t.z()};
  return s;
}

// Trimmed ICP with scale from `start`: at most `iterations` steps over
// `points` (fewer once the trimmed error stops falling); each step takes
// every point's closest point on the surface, keeps the 70 % nearest and
// solves the similarity step: point-to-point (Umeyama's closed form; robust
// from far away) or, with `to_plane`, point-to-plane (the linearised
// rotation, translation and scale step about the points' centre that
// minimises the distances along the surface normals; converges in a few
// steps where point-to-point slides slowly). Returns the transform and its
// trimmed RMS (absolute).
std::pair<Similarity, double> icp(const Surface& surface, const std::vector<Vec3>& points,
                                  Similarity start, int iterations, bool to_plane) {
  const std::size_t n = points.size();
  const std::size_t keep = std::max<std::size_t>(7, n * 7 / 10);
  std::vector<Vec3> closest(n), normal(n), moved(n);
  std::vector<double> distance(n);
  std::vector<std::size_t> order(n);
  Similarity s = start;
  double rms = INFINITY;
  for (int it = 0; it <= iterations; ++it) {
    parallel_for_chunks(n, 256, [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i) {
        const Vec3 q = s.apply(points[i]);
        const auto [c, triangle] =
            surface.tree.closest_point_and_primitive(K::Point_3(q.x, q.y, q.z));
        const K::Vector_3 nrm = CGAL::cross_product(triangle->vertex(1) - triangle->vertex(0),
                                                    triangle->vertex(2) - triangle->vertex(0));
        moved[i] = q;
        closest[i] = {c.x(), c.y(), c.z()};
        normal[i] = normalize(Vec3{nrm.x(), nrm.y(), nrm.z()});
        distance[i] = length(closest[i] - q);
      }
    });
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::nth_element(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(keep - 1),
                     order.end(), [&](std::size_t a, std::size_t b) {
                       return distance[a] < distance[b] || (distance[a] == distance[b] && a < b);
                     });
    double sum = 0;
    for (std::size_t k = 0; k < keep; ++k) sum += distance[order[k]] * distance[order[k]];
    const double previous = rms;
    rms = std::sqrt(sum / static_cast<double>(keep));
    // Converged (the trimmed error no longer falls), or the last step.
    if (it == iterations || (std::isfinite(previous) && previous - rms <= 1e-6 * previous)) break;
    if (!to_plane) {
      Eigen::Matrix3Xd src(3, keep), dst(3, keep);
      for (std::size_t k = 0; k < keep; ++k) {
        const Vec3 p = points[order[k]], c = closest[order[k]];
        src.col(static_cast<Eigen::Index>(k)) << p.x, p.y, p.z;
        dst.col(static_cast<Eigen::Index>(k)) << c.x, c.y, c.z;
      }
      const Eigen::Matrix4d m = Eigen::umeyama(src, dst, true);
      const Eigen::Matrix3d sr = m.topLeftCorner<3, 3>();
      const double scale = std::cbrt(sr.determinant());
      if (!(scale > 0) || !std::isfinite(scale)) break;
      s = similarity_of(scale, sr / scale, m.topRightCorner<3, 1>());
      continue;
    }
    // Point-to-plane: q' = c0 + (1 + d) R(w) (q - c0) + tau, linearised:
    // n . (q - c) + n . (w x a + tau + d a) = 0 with a = q - c0, one row
    // [a x n, n, n . a] per kept point; least squares over (w, tau, d).
    Eigen::Vector3d c0 = Eigen::Vector3d::Zero();
    for (std::size_t k = 0; k < keep; ++k) {
      const Vec3 q = moved[order[k]];
      c0 += Eigen::Vector3d(q.x, q.y, q.z);
    }
    c0 /= static_cast<double>(keep);
    Eigen::Matrix<double, 7, 7> ata = Eigen::Matrix<double, 7, 7>::Zero();
    Eigen::Matrix<double, 7, 1> atb = Eigen::Matrix<double, 7, 1>::Zero();
    for (std::size_t k = 0; k < keep; ++k) {
      const std::size_t i = order[k];
      const Eigen::Vector3d q(moved[i].x, moved[i].y, moved[i].z);
      const Eigen::Vector3d c(closest[i].x, closest[i].y, closest[i].z);
      const Eigen::Vector3d nn(normal[i].x, normal[i].y, normal[i].z);
      const Eigen::Vector3d a = q - c0;
      Eigen::Matrix<double, 7, 1> row;
      row << a.cross(nn), nn, nn.dot(a);
      ata += row * row.transpose();
      atb -= row * nn.dot(q - c);
    }
    const Eigen::Matrix<double, 7, 1> x = ata.ldlt().solve(atb);
    if (!x.allFinite()) break;
    const Eigen::Vector3d w = x.head<3>(), tau = x.segment<3>(3);
    const double d = x[6];
    const double angle = w.norm();
    const Eigen::Matrix3d rw = angle > 0 ? Eigen::AngleAxisd(angle, w / angle).toRotationMatrix()
                                         : Eigen::Matrix3d::Identity().eval();
    if (!(1 + d > 0)) break;
    // The step after s: x -> c0 + (1 + d) rw (s(x) - c0) + tau.
    const Eigen::Matrix3d r = rw * rotation_of(s);
    const Eigen::Vector3d t = c0 + (1 + d) * rw * (Eigen::Vector3d(s.t.x, s.t.y, s.t.z) - c0) + tau;
    s = similarity_of((1 + d) * s.scale, r, t);
  }
  return {s, rms};
}

}  // namespace

Expected<Similarity> similarity_from_matrix(std::span<const double> m, const std::string& what) {
  auto bad = [&](const std::string& why) {
    return make_error(ErrorCode::kInvalidArgument, what + ": " + why);
  };
  if (m.size() != 16) {
    return bad("expected 16 numbers (a 4x4 matrix, row by row), got " + std::to_string(m.size()));
  }
  for (double v : m) {
    if (!std::isfinite(v)) return bad("a number is not finite");
  }
  if (m[12] != 0 || m[13] != 0 || m[14] != 0 || m[15] != 1) {
    return bad("the last row must be 0 0 0 1 (a similarity, not a projection)");
  }
  Eigen::Matrix3d a;
  a << m[0], m[1], m[2], m[4], m[5], m[6], m[8], m[9], m[10];
  const double det = a.determinant();
  if (!(det > 0)) return bad("the upper 3x3 must have a positive determinant (no mirroring)");
  const double scale = std::cbrt(det);
  const Eigen::Matrix3d r = a / scale;
  if ((r.transpose() * r - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6) {
    return bad(
        "the upper 3x3 is not a scale times a rotation (its columns must be orthogonal "
        "and of equal length)");
  }
  return similarity_of(scale, r, Eigen::Vector3d(m[3], m[7], m[11]));
}

Expected<PairFit> similarity_from_pairs(std::span<const Vec3> model, std::span<const Vec3> mesh) {
  auto bad = [](const std::string& why) { return make_error(ErrorCode::kInvalidArgument, why); };
  if (model.size() != mesh.size()) return bad("the model's and the mesh's points differ in number");
  if (model.size() < 3) {
    return bad(std::to_string(model.size()) + " point pairs: at least 3 are needed");
  }
  const auto n = static_cast<Eigen::Index>(model.size());
  Eigen::Matrix3Xd src(3, n), dst(3, n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Vec3 a = model[static_cast<std::size_t>(k)], b = mesh[static_cast<std::size_t>(k)];
    src.col(k) << a.x, a.y, a.z;
    dst.col(k) << b.x, b.y, b.z;
  }
  if (!src.allFinite() || !dst.allFinite()) return bad("a point is not finite");
  // Umeyama needs each side spread over a plane at least.
  for (const auto* side : {&src, &dst}) {
    const Eigen::Matrix3Xd centred = side->colwise() - side->rowwise().mean();
    const Eigen::JacobiSVD<Eigen::Matrix3Xd> svd(centred);
    const Eigen::Vector3d sv = svd.singularValues();
    if (!(sv(1) > 1e-6 * sv(0))) {
      return bad(std::string("the ") + (side == &src ? "model's" : "mesh's") +
                 " points lie on one line (or at one place): at least 3 not on a line are "
                 "needed");
    }
  }
  const Eigen::Matrix4d m = Eigen::umeyama(src, dst, true);
  const Eigen::Matrix3d sr = m.topLeftCorner<3, 3>();
  const double scale = std::cbrt(sr.determinant());
  if (!(scale > 0) || !std::isfinite(scale)) {
    return make_error(ErrorCode::kInternal, "the pairs' similarity has no positive scale");
  }
  PairFit fit;
  fit.transform = similarity_of(scale, sr / scale, m.topRightCorner<3, 1>());
  double sum = 0;
  for (std::size_t k = 0; k < model.size(); ++k) {
    const double d = length(fit.transform.apply(model[k]) - mesh[k]);
    sum += d * d;
    if (d > fit.largest) {
      fit.largest = d;
      fit.worst = k;
    }
  }
  fit.rms = std::sqrt(sum / static_cast<double>(model.size()));
  return fit;
}

Expected<CameraProjector> transform_camera(const CameraProjector& camera, const Similarity& s) {
  CameraSpec spec = camera.spec();
  Eigen::Matrix3d rc;
  rc << spec.pose.r[0], spec.pose.r[1], spec.pose.r[2], spec.pose.r[3], spec.pose.r[4],
      spec.pose.r[5], spec.pose.r[6], spec.pose.r[7], spec.pose.r[8];
  const Eigen::Matrix3d r = rotation_of(s);
  const Eigen::Matrix3d rc2 = rc * r.transpose();
  const Eigen::Vector3d tc(spec.pose.t.x, spec.pose.t.y, spec.pose.t.z);
  const Eigen::Vector3d t2 = s.scale * tc - rc2 * Eigen::Vector3d(s.t.x, s.t.y, s.t.z);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) spec.pose.r[3 * i + j] = rc2(i, j);
  }
  spec.pose.t = {t2.x(), t2.y(), t2.z()};
  return CameraProjector::make(std::move(spec));
}

Expected<ModelFit> fit_model_to_mesh(const MeshData& mesh, std::span<const Vec3> points,
                                     int threads) {
  if (points.size() < kAlignmentMinPoints) {
    return make_error(ErrorCode::kInvalidArgument,
                      "the model has " + std::to_string(points.size()) +
                          " sparse points: at least " + std::to_string(kAlignmentMinPoints) +
                          " are needed to align it (or give the transform)");
  }
  ModelFit fit;
  Surface surface;
  if (Status s = build_surface(mesh, surface); !s) return s.error();
  fit.before = measure_on(surface, points, threads);

  // The points used: at most 10000 for the refinement, 1500 for the guesses.
  auto strided = [&](std::size_t most) {
    const std::size_t stride = (points.size() + most - 1) / most;
    std::vector<Vec3> out;
    for (std::size_t i = 0; i < points.size(); i += stride) out.push_back(points[i]);
    return out;
  };
  const std::vector<Vec3> fine = strided(10000), coarse = strided(1500);

  // Their centre and spread, against the surface's.
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const Vec3& p : fine) centroid += Eigen::Vector3d(p.x, p.y, p.z);
  centroid /= static_cast<double>(fine.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : fine) {
    const Eigen::Vector3d d = Eigen::Vector3d(p.x, p.y, p.z) - centroid;
    covariance += d * d.transpose();
  }
  covariance /= static_cast<double>(fine.size());
  if (!(covariance.trace() > 0)) {
    return make_error(ErrorCode::kInvalidArgument, "the model's sparse points are all one point");
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> model_axes(covariance);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> mesh_axes(surface.covariance);
  const double scale0 = std::sqrt(surface.covariance.trace() / covariance.trace());

  // Every proper signed permutation matching the model's axes to the mesh's.
  std::vector<std::pair<Similarity, double>> guesses;
  std::array<int, 3> perm{0, 1, 2};
  run_in_arena(threads, [&] {
    do {
      for (int signs = 0; signs < 8; ++signs) {
        Eigen::Matrix3d d = Eigen::Matrix3d::Zero();
        for (int k = 0; k < 3; ++k) d(perm[k], k) = (signs >> k) & 1 ? -1 : 1;
        const Eigen::Matrix3d r =
            mesh_axes.eigenvectors() * d * model_axes.eigenvectors().transpose();
        if (r.determinant() < 0) continue;
        const Eigen::Vector3d t = surface.centroid - scale0 * r * centroid;
        guesses.push_back(icp(surface, coarse, similarity_of(scale0, r, t), 8, false));
      }
    } while (std::next_permutation(perm.begin(), perm.end()));
  });
  fit.candidates = static_cast<int>(guesses.size());
  std::stable_sort(guesses.begin(), guesses.end(),
                   [](const auto& a, const auto& b) { return a.second < b.second; });
  // The best three, refined on the finer set (point-to-point, then
  // point-to-plane); the least trimmed RMS wins.
  std::pair<Similarity, double> best{Similarity{}, INFINITY};
  run_in_arena(threads, [&] {
    for (std::size_t g = 0; g < std::min<std::size_t>(3, guesses.size()); ++g) {
      std::pair<Similarity, double> refined = icp(surface, fine, guesses[g].first, 10, false);
      refined = icp(surface, fine, refined.first, 30, true);
      if (refined.second < best.second) best = refined;
    }
  });
  fit.transform = best.first;
  fit.trimmed_rms = surface.diagonal > 0 ? best.second / surface.diagonal : 0;
  std::vector<Vec3> moved;
  moved.reserve(points.size());
  for (const Vec3& p : points) moved.push_back(fit.transform.apply(p));
  fit.after = measure_on(surface, moved, threads);
  return fit;
}

}  // namespace texbake
