#include "bake/atlas/atlas_raster.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>

#include "bake/shade/sample_pattern.h"
#include "bake/util/parallel.h"
#include "mapping/image_view.h"

namespace texbake {
namespace {

// Rows per work item (kAtlasBandRows). Bands (not square tiles) keep the
// texels of each work item contiguous and ascending, so the per-band results
// concatenate into the final ascending order without a sort.
constexpr int kBandRows = kAtlasBandRows;

// Conservative slack on the one-texel dilation, in texels: rounding must
// never drop a texel that a lookup can reach (extra coverage is harmless).
constexpr double kCoverSlack = 1e-7;

using P2 = PixelPos;

using TriPx = std::array<P2, 3>;  // corners in continuous pixel coordinates

struct Bary {
  double b0, b1, b2;
};

// Closest point of segment ab to p, as barycentrics (1 - t, t).
inline double segment_param(P2 p, P2 a, P2 b) {
  const P2 ab = b - a;
  const double len2 = dot(ab, ab);
  if (len2 <= 0) return 0;
  return std::clamp(dot(p - a, ab) / len2, 0.0, 1.0);
}

// Closest point of triangle abc to p, as barycentrics. Ericson, Real-Time
// Collision Detection (2005), section 5.1.5 (Voronoi regions), with a
// fallback to the three edges for degenerate (zero-area) triangles, where
// Ericson's denominators vanish.
Bary closest_barycentric(P2 p, P2 a, P2 b, P2 c) {
  const P2 ab = b - a, ac = c - a;
  const double area2 = cross(ab, ac);
  if (std::abs(area2) <= 1e-12 * (dot(ab, ab) + dot(ac, ac))) {
    const double t_ab = segment_param(p, a, b), t_ac = segment_param(p, a, c),
                 t_bc = segment_param(p, b, c);
    const Bary cand[3] = {{1 - t_ab, t_ab, 0}, {1 - t_ac, 0, t_ac}, {0, 1 - t_bc, t_bc}};
    Bary best = cand[0];
    double best_d = std::numeric_limits<double>::infinity();
    for (const Bary& q : cand) {
      const P2 x{q.b0 * a.x + q.b1 * b.x + q.b2 * c.x, q.b0 * a.y + q.b1 * b.y + q.b2 * c.y};
      const double d = dot(p - x, p - x);
      if (d < best_d) best_d = d, best = q;
    }
    return best;
  }
  const P2 ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};
  const P2 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return {1 - v, v, 0};
  }
  const P2 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return {1 - w, 0, w};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - w, w};
  }
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {1 - v - w, v, w};
}

// Barycentrics of p if the (non-degenerate) triangle contains it (edges
// included), else false.
inline bool contains(const TriPx& t, P2 p, double* b1, double* b2) {
  const P2 ab = t[1] - t[0], ac = t[2] - t[0], ap = p - t[0];
  const double area2 = cross(ab, ac);
  if (area2 == 0) return false;
  const double c1 = cross(ap, ac), c2 = cross(ab, ap);
  // Sign test first: dividing by area2 keeps the signs, so this rejects only
  // points the exact test below rejects too, without its two divisions (the
  // rasteriser's hot spot on dense meshes: most candidates fail here).
  if (area2 > 0 ? (c1 < 0 || c2 < 0) : (c1 > 0 || c2 > 0)) return false;
  const double l1 = c1 / area2;
  const double l2 = c2 / area2;
  if (l1 < 0 || l2 < 0 || l1 + l2 > 1) return false;
  *b1 = l1;
  *b2 = l2;
  return true;
}

// Separating-axis test of a triangle against squares of half-size h: the
// axes are x, y (handled by the caller's bounding box) and the three edge
// normals. Precomputed per triangle, evaluated per texel.
struct EdgeAxes {
  P2 n[3];
  double lo[3], hi[3];  // the triangle's projection interval on n[k]
  double reach[3];      // the square's half-extent on n[k]: h * (|nx| + |ny|)

  EdgeAxes(const TriPx& t, double h) {
    for (int k = 0; k < 3; ++k) {
      const P2 e = t[(k + 1) % 3] - t[k];
      n[k] = {-e.y, e.x};
      const double a = dot(n[k], t[0]), b = dot(n[k], t[1]), c = dot(n[k], t[2]);
      lo[k] = std::min({a, b, c});
      hi[k] = std::max({a, b, c});
      reach[k] = h * (std::abs(n[k].x) + std::abs(n[k].y));
    }
  }
  bool overlaps(P2 centre) const {
    for (int k = 0; k < 3; ++k) {
      const double c = dot(n[k], centre);
      if (c + reach[k] < lo[k] || c - reach[k] > hi[k]) return false;
    }
    return true;
  }
};

}  // namespace

SampleOffset sample_offset(int s, int n) {
  if (n <= 1) return {0, 0};
  const int k = static_cast<int>(std::lround(std::sqrt(static_cast<double>(n))));
  if (k * k == n) {
    return {(s % k + 0.5) / k - 0.5, (s / k + 0.5) / k - 0.5};
  }
  const double y = radical_inverse2(static_cast<uint32_t>(s)) + 0.5 / n;
  return {(s + 0.5) / n - 0.5, (y - std::floor(y)) - 0.5};
}

namespace {

// The rows of an n-row atlas that a triangle's samples may touch (its pixel
// rows dilated by one, for the bilinear footprint): false when none.
bool dilated_rows(const TriPx& p, int n, int& lo, int& hi) {
  const double ymin = std::min({p[0].y, p[1].y, p[2].y});
  const double ymax = std::max({p[0].y, p[1].y, p[2].y});
  const double l = std::max(std::ceil(ymin - 1 - kCoverSlack), 0.0);
  const double h = std::min(std::floor(ymax + 1 + kCoverSlack), n - 1.0);
  if (l > h) return false;
  lo = static_cast<int>(l);
  hi = static_cast<int>(h);
  return true;
}

}  // namespace

Status AtlasBands::check(const MeshData& mesh, const AtlasRasterOptions& options, bool* covers) {
  const int n = options.size;
  const int spt = options.samples;
  if (n < 1 || n > kMaxAtlasSize) {
    return make_error(ErrorCode::kInvalidArgument, "--size " + std::to_string(n) +
                                                       " is out of range (1 .. " +
                                                       std::to_string(kMaxAtlasSize) + ")");
  }
  if (spt < 1 || spt > kMaxAtlasSamples) {
    return make_error(ErrorCode::kInvalidArgument, "--samples " + std::to_string(spt) +
                                                       " is out of range (1 .. " +
                                                       std::to_string(kMaxAtlasSamples) + ")");
  }
  if (!mesh.has_uvs() || mesh.triangle_corners.size() != mesh.triangles.size()) {
    return make_error(ErrorCode::kInvalidArgument, "the mesh has no UV coordinates");
  }
  // The first bad triangle is reported.
  const std::size_t tri_count = mesh.triangles.size();
  std::vector<uint8_t> bad(tri_count, 0);
  std::atomic<bool> any_rows{false};
  parallel_for_chunks(tri_count, 4096, [&](std::size_t begin, std::size_t end) {
    bool rows = false;
    for (std::size_t t = begin; t < end; ++t) {
      TriPx p{};
      for (int k = 0; k < 3; ++k) {
        const uint32_t corner = mesh.triangle_corners[t][k];
        if (corner >= mesh.corner_uv.size() || mesh.corner_uv[corner] >= mesh.uvs.size()) {
          bad[t] = 1;
          break;
        }
        const Float2 uv = mesh.uvs[mesh.corner_uv[corner]];
        if (!std::isfinite(uv.u) || !std::isfinite(uv.v)) {
          bad[t] = 2;
          break;
        }
        const PixelPos pp = pixel_from_uv(UV{uv.u, uv.v}, n, n);
        p[k] = {pp.x, pp.y};
      }
      int lo = 0, hi = 0;
      if (!bad[t] && !rows) rows = dilated_rows(p, n, lo, hi);
    }
    if (rows) any_rows.store(true, std::memory_order_relaxed);
  });
  if (covers) *covers = any_rows.load();
  for (std::size_t t = 0; t < tri_count; ++t) {
    if (bad[t]) {
      return make_error(ErrorCode::kParse, "triangle " + std::to_string(t) +
                                               (bad[t] == 1 ? " has a UV index out of range"
                                                            : " has a non-finite UV coordinate"));
    }
  }
  return ok_status();
}

Expected<AtlasBands> AtlasBands::prepare(const MeshData& mesh, const AtlasRasterOptions& options) {
  if (Status s = check(mesh, options); !s) return s.error();
  const int n = options.size;
  const int spt = options.samples;
  const std::size_t tri_count = mesh.triangles.size();
  AtlasBands bands;
  bands.size_ = n;
  bands.samples_ = spt;
  bands.overlaps_ = options.overlap_candidates;

  // Triangle corners in pixel space (SPEC section 1 via pixel_from_uv).
  std::vector<TriPx>& px = bands.px_;
  px.resize(tri_count);
  parallel_for_chunks(tri_count, 4096, [&](std::size_t begin, std::size_t end) {
    for (std::size_t t = begin; t < end; ++t) {
      for (int k = 0; k < 3; ++k) {
        const Float2 uv = triangle_uv(mesh, t, k);
        const PixelPos pp = pixel_from_uv(UV{uv.u, uv.v}, n, n);
        px[t][k] = {pp.x, pp.y};
      }
    }
  });

  // Bin triangles into bands of rows by their dilated row range.
  const int band_total = (n + kBandRows - 1) / kBandRows;
  std::vector<int>& row_lo = bands.row_lo_;
  std::vector<int>& row_hi = bands.row_hi_;
  row_lo.resize(tri_count);
  row_hi.resize(tri_count);
  std::vector<uint32_t>& band_start = bands.band_start_;
  band_start.assign(band_total + 1, 0);
  for (std::size_t t = 0; t < tri_count; ++t) {
    if (!dilated_rows(px[t], n, row_lo[t], row_hi[t])) {
      row_lo[t] = 1;
      row_hi[t] = 0;
      continue;
    }
    for (int b = row_lo[t] / kBandRows; b <= row_hi[t] / kBandRows; ++b) ++band_start[b + 1];
  }
  for (int b = 0; b < band_total; ++b) band_start[b + 1] += band_start[b];
  std::vector<uint32_t>& band_tris = bands.band_tris_;
  band_tris.resize(band_start[band_total]);
  {
    std::vector<uint32_t> fill(band_start.begin(), band_start.end() - 1);
    for (std::size_t t = 0; t < tri_count; ++t) {
      if (row_lo[t] > row_hi[t]) continue;
      for (int b = row_lo[t] / kBandRows; b <= row_hi[t] / kBandRows; ++b) {
        band_tris[fill[b]++] = static_cast<uint32_t>(t);
      }
    }
  }

  bands.offsets_.resize(spt);
  for (int s = 0; s < spt; ++s) bands.offsets_[s] = sample_offset(s, spt);
  return bands;
}

void AtlasBands::rasterize(std::size_t band, AtlasRaster& out, AtlasBandScratch& scratch) const {
  const int n = size_;
  const int spt = samples_;
  const std::vector<TriPx>& px = px_;
  out.size = n;
  out.samples_per_texel = spt;
  out.texels.clear();
  out.sample_triangle.clear();
  out.sample_b1.clear();
  out.sample_b2.clear();
  out.alt_sample.clear();
  out.alt_triangle.clear();
  out.alt_b1.clear();
  out.alt_b2.clear();
  out.border_samples = 0;

  std::vector<uint32_t>& pair_texel = scratch.pair_texel;
  std::vector<uint32_t>& pair_tri = scratch.pair_tri;
  std::vector<uint32_t>& count = scratch.count;
  std::vector<uint32_t>& cand = scratch.cand;
  const int y0 = static_cast<int>(band) * kBandRows;
  const int y1 = std::min(n, y0 + kBandRows);
  const std::size_t local_count = static_cast<std::size_t>(y1 - y0) * n;
  pair_texel.clear();
  pair_tri.clear();
  // Triangles arrive in ascending index order, so each texel's candidate
  // list (after the stable counting sort below) is ascending too.
  for (uint32_t i = band_start_[band]; i < band_start_[band + 1]; ++i) {
    const uint32_t t = band_tris_[i];
    const auto& p = px[t];
    const double xmin = std::min({p[0].x, p[1].x, p[2].x});
    const double xmax = std::max({p[0].x, p[1].x, p[2].x});
    const int x_lo = static_cast<int>(std::max(std::ceil(xmin - 1 - kCoverSlack), 0.0));
    const int x_hi = static_cast<int>(std::min(std::floor(xmax + 1 + kCoverSlack), n - 1.0));
    const int r_lo = std::max(row_lo_[t], y0), r_hi = std::min(row_hi_[t], y1 - 1);
    const EdgeAxes axes(px[t], 1 + kCoverSlack);
    for (int y = r_lo; y <= r_hi; ++y) {
      for (int x = x_lo; x <= x_hi; ++x) {
        if (!axes.overlaps({static_cast<double>(x), static_cast<double>(y)})) continue;
        pair_texel.push_back(static_cast<uint32_t>((y - y0) * n + x));
        pair_tri.push_back(t);
      }
    }
  }
  count.assign(local_count + 1, 0);
  for (uint32_t lt : pair_texel) ++count[lt + 1];
  for (std::size_t k = 0; k < local_count; ++k) count[k + 1] += count[k];
  cand.resize(pair_tri.size());
  scratch.fill.assign(count.begin(), count.end() - 1);
  for (std::size_t k = 0; k < pair_tri.size(); ++k) {
    cand[scratch.fill[pair_texel[k]]++] = pair_tri[k];
  }

  for (std::size_t lt = 0; lt < local_count; ++lt) {
    const uint32_t c0 = count[lt], c1 = count[lt + 1];
    if (c0 == c1) continue;
    const int x = static_cast<int>(lt % n), y = y0 + static_cast<int>(lt / n);
    out.texels.push_back(static_cast<uint32_t>(y) * static_cast<uint32_t>(n) + x);
    for (int s = 0; s < spt; ++s) {
      const P2 q{x + offsets_[s].dx, y + offsets_[s].dy};
      double b1 = 0, b2 = 0;
      uint32_t chosen = 0xFFFFFFFFu;
      for (uint32_t k = c0; k < c1; ++k) {
        if (contains(px[cand[k]], q, &b1, &b2)) {
          chosen = cand[k];
          if (overlaps_) {
            const auto sample = static_cast<uint32_t>(out.sample_triangle.size());
            for (uint32_t j = k + 1; j < c1; ++j) {
              double a1 = 0, a2 = 0;
              if (!contains(px[cand[j]], q, &a1, &a2)) continue;
              out.alt_sample.push_back(sample);
              out.alt_triangle.push_back(cand[j]);
              out.alt_b1.push_back(static_cast<float>(a1));
              out.alt_b2.push_back(static_cast<float>(a2));
            }
          }
          break;
        }
      }
      if (chosen == 0xFFFFFFFFu) {
        // Border sample: nearest point of the nearest candidate.
        double best = std::numeric_limits<double>::infinity();
        for (uint32_t k = c0; k < c1; ++k) {
          const auto& p = px[cand[k]];
          const Bary w = closest_barycentric(q, p[0], p[1], p[2]);
          const P2 cp{w.b0 * p[0].x + w.b1 * p[1].x + w.b2 * p[2].x,
                      w.b0 * p[0].y + w.b1 * p[1].y + w.b2 * p[2].y};
          const double d = dot(q - cp, q - cp);
          if (d < best) best = d, chosen = cand[k], b1 = w.b1, b2 = w.b2;
        }
        ++out.border_samples;
      }
      out.sample_triangle.push_back(chosen);
      out.sample_b1.push_back(static_cast<float>(b1));
      out.sample_b2.push_back(static_cast<float>(b2));
    }
  }
}

Expected<AtlasRaster> rasterize_atlas(const MeshData& mesh, const AtlasRasterOptions& options) {
  Expected<AtlasBands> prepared = AtlasBands::prepare(mesh, options);
  if (!prepared) return prepared.error();
  const AtlasBands& bands = *prepared;
  std::vector<AtlasRaster> results(bands.band_count());
  parallel_for_chunks(bands.band_count(), 1, [&](std::size_t band_begin, std::size_t band_end) {
    AtlasBandScratch scratch;
    for (std::size_t band = band_begin; band < band_end; ++band) {
      bands.rasterize(band, results[band], scratch);
    }
  });

  AtlasRaster raster;
  raster.size = bands.size();
  raster.samples_per_texel = bands.samples_per_texel();
  std::size_t texel_total = 0, sample_total = 0;
  for (const AtlasRaster& r : results) {
    texel_total += r.texels.size();
    sample_total += r.sample_count();
  }
  raster.texels.reserve(texel_total);
  raster.sample_triangle.reserve(sample_total);
  raster.sample_b1.reserve(sample_total);
  raster.sample_b2.reserve(sample_total);
  for (AtlasRaster& r : results) {
    const auto sample_base = static_cast<uint32_t>(raster.sample_triangle.size());
    for (uint32_t s : r.alt_sample) raster.alt_sample.push_back(sample_base + s);
    raster.alt_triangle.insert(raster.alt_triangle.end(), r.alt_triangle.begin(),
                               r.alt_triangle.end());
    raster.alt_b1.insert(raster.alt_b1.end(), r.alt_b1.begin(), r.alt_b1.end());
    raster.alt_b2.insert(raster.alt_b2.end(), r.alt_b2.begin(), r.alt_b2.end());
    raster.texels.insert(raster.texels.end(), r.texels.begin(), r.texels.end());
    raster.sample_triangle.insert(raster.sample_triangle.end(), r.sample_triangle.begin(),
                                  r.sample_triangle.end());
    raster.sample_b1.insert(raster.sample_b1.end(), r.sample_b1.begin(), r.sample_b1.end());
    raster.sample_b2.insert(raster.sample_b2.end(), r.sample_b2.begin(), r.sample_b2.end());
    raster.border_samples += r.border_samples;
    r = AtlasRaster{};  // release as we go: keeps the peak near one copy
  }
  return raster;
}

std::vector<uint8_t> coverage_mask(const AtlasRaster& raster) {
  std::vector<uint8_t> mask(static_cast<std::size_t>(raster.size) * raster.size, 0);
  for (uint32_t t : raster.texels) mask[t] = 1;
  return mask;
}

}  // namespace texbake
