#include "bake/fit/model_alignment.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
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

}  // namespace

Expected<ModelAlignment> measure_model_alignment(const MeshData& mesh, std::span<const Vec3> points,
                                                 int threads) {
  ModelAlignment a;
  a.points = points.size();
  if (points.size() < kAlignmentMinPoints) return a;  // too few to judge

  // The surface: the mesh's triangles of non-zero area (CGAL's distance to
  // a degenerate triangle is not defined).
  Triangles triangles;
  triangles.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    K::Triangle_3 tri(point(mesh.positions[t[0]]), point(mesh.positions[t[1]]),
                      point(mesh.positions[t[2]]));
    if (!tri.is_degenerate()) triangles.push_back(tri);
  }
  if (triangles.empty()) {
    return make_error(ErrorCode::kInvalidArgument,
                      "the mesh has no triangle of non-zero area to check the model against");
  }
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Float3& p : mesh.positions) {
    lo = {std::min(lo.x, double{p.x}), std::min(lo.y, double{p.y}), std::min(lo.z, double{p.z})};
    hi = {std::max(hi.x, double{p.x}), std::max(hi.y, double{p.y}), std::max(hi.z, double{p.z})};
  }
  const double diagonal = length(hi - lo);
  const double margin = kAlignmentBoxMargin * diagonal;
  const double near = kAlignmentNearDistance * diagonal;

  // Every k-th point past kAlignmentMaxPoints: a model of millions of
  // points is judged as well by a fifth of them.
  const std::size_t stride = (points.size() + kAlignmentMaxPoints - 1) / kAlignmentMaxPoints;
  std::vector<Vec3> measured;
  for (std::size_t i = 0; i < points.size(); i += stride) measured.push_back(points[i]);
  a.measured = measured.size();

  Tree tree(triangles.begin(), triangles.end());
  tree.build();
  tree.accelerate_distance_queries();
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
        distance[i] = std::sqrt(tree.squared_distance(K::Point_3(p.x, p.y, p.z)));
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

}  // namespace texbake
