#include "bake/vertex/vertex_resolve.h"

#include <utility>

#include "bake/util/parallel.h"
#include "mapping/sample.h"

namespace texbake {

VertexResolvePlan plan_resolve(const MeshData& mesh, std::vector<Rgba>& colors,
                               const std::vector<uint8_t>& unknown, VertexResolve how) {
  VertexResolvePlan p;
  p.how = std::move(how);
  const std::size_t n = colors.size();
  bool any = false;
  for (std::size_t v = 0; v < n && !any; ++v) any = unknown[v] != 0;
  if (!any) return p;
  if (!p.how.fill) {
    for (std::size_t v = 0; v < n; ++v) {
      if (unknown[v]) p.constant.push_back(static_cast<uint32_t>(v));
    }
    return p;
  }
  std::vector<Rgba>* target = &colors;
  if (p.how.coverage) {
    // The fill works on the colour alone: alpha (the coverage) is set aside.
    p.unknown = unknown;
    p.coverage_rgb.resize(n);
    for (std::size_t v = 0; v < n; ++v)
      p.coverage_rgb[v] = {colors[v][0], colors[v][1], colors[v][2], 1};
    target = &p.coverage_rgb;
  }
  p.plan = plan_fill(mesh, *target, unknown, [&p](uint32_t v) {
    if (p.how.fallback) return p.how.fallback(v);
    p.constant.push_back(v);  // replaced by the constant after the encoding
    return Rgba{0, 0, 0, 1};
  });
  p.solve = true;
  return p;
}

Expected<FillResult> finish_resolve(const MeshData& mesh, std::vector<Rgba>& colors,
                                    VertexResolvePlan plan) {
  FillResult result;
  if (plan.solve) {
    std::vector<Rgba>& target = plan.how.coverage ? plan.coverage_rgb : colors;
    Expected<FillResult> filled = solve_fill(mesh, target, std::move(plan.plan));
    if (!filled) return filled.error();
    result = *filled;
    if (plan.how.coverage) {
      for (std::size_t v = 0; v < colors.size(); ++v) {
        if (plan.unknown[v]) colors[v] = {target[v][0], target[v][1], target[v][2], 0};
      }
    }
  }
  if (plan.how.linear) {
    parallel_for_chunks(colors.size(), 16384, [&](std::size_t begin, std::size_t end) {
      for (std::size_t v = begin; v < end; ++v) colors[v] = linear_to_srgb(colors[v]);
    });
  }
  const Rgba& k = plan.how.constant;
  const Rgba constant = plan.how.coverage ? Rgba{k[0], k[1], k[2], 0} : k;
  for (uint32_t v : plan.constant) colors[v] = constant;
  return result;
}

Expected<FillResult> resolve_vertices(const MeshData& mesh, std::vector<Rgba>& colors,
                                      const std::vector<uint8_t>& unknown, VertexResolve how) {
  return finish_resolve(mesh, colors, plan_resolve(mesh, colors, unknown, std::move(how)));
}

}  // namespace texbake
