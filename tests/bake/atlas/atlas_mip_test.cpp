// Issue #11 item 4: the default padding is safe for the mip levels a client
// builds. The test box-downsamples the atlas by 2, 4, 8 and 16 itself
// (plain 2 x 2 averaging of RGB, written here, not the code under test) and
// checks, at every level-k texel whose 2^k x 2^k footprint holds at least one
// covered (baked) base texel, that the background does not pull it away
// from the chart colours:
//
//  1. Constant texture (a 1 x 1 image: every covered texel is exactly c):
//     the level-k texel must equal c within 1e-5. A mip level near a chart
//     should be the mean of the chart texels it holds; here that mean is c,
//     and push-pull fills the background with weighted means of c, so any
//     difference beyond float rounding (1e-5 is 1/400 of an 8-bit step) is
//     background seen through the mip. Black (or any other) background
//     shows as (1 - f) c for a footprint covered to a fraction f.
//  2. The Earth map through a sphere: the level-k texel must lie, per
//     channel, within [min, max] (+- 1e-5) of the covered base texels in the
//     level-k footprints around it: its own and its 8 neighbours, widened by
//     the padding rings' reach (a ring texel is a mean of texels at most
//     `rings` = default_padding(size) texels away), i.e. the level-k texels
//     within 1 + ceil(rings / 2^k) of it. Why this holds for the default
//     padding: every filled texel is a convex combination of data texels
//     (covered or ring) of its 2^k block and the 8 around it (the mip-safe
//     push, bake/atlas/dilate.h), so the block's mean, its mip texel, stays
//     in their range. Black (and the plain bilinear push, which can draw
//     from farther: it failed this at 1 to 100 level-3/4 texels per case,
//     by up to 0.05) leaves it wherever the charts around are not black.
//
// Both run on the bunny and the armadillo with --uv generate at 1024 and
// 2048, against the new default padding (must pass) and the old one
// (default_padding(size) rings of dilation only, the rest transparent
// black; must fail: the figures are printed).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "bake/atlas/dilate.h"
#include "bake/engine/bake_atlas.h"
#include "tests/bake/bunny_earth.h"

namespace texbake {
namespace {

// An RGB image in double with its coverage count per texel: level 0 is the
// atlas, level k + 1 the 2 x 2 box average of level k (the sizes here are
// powers of two).
struct MipLevel {
  int n = 0;
  std::vector<std::array<double, 3>> rgb;  // box mean of all base texels
  std::vector<std::array<double, 3>> cov;  // sum of the covered base texels' RGB
  std::vector<std::array<double, 3>> lo;   // per channel min of covered (inf: none)
  std::vector<std::array<double, 3>> hi;   // per channel max of covered
  std::vector<int> covered;                // covered base texels in the footprint
};

MipLevel base_level(const std::vector<float>& rgba, const std::vector<uint8_t>& baked, int n) {
  MipLevel l;
  l.n = n;
  const std::size_t count = static_cast<std::size_t>(n) * n;
  l.rgb.resize(count);
  l.cov.assign(count, {0, 0, 0});
  l.lo.assign(count, {INFINITY, INFINITY, INFINITY});
  l.hi.assign(count, {-INFINITY, -INFINITY, -INFINITY});
  l.covered.assign(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    for (int c = 0; c < 3; ++c) {
      l.rgb[i][c] = rgba[i * 4 + c];
      if (baked[i]) l.cov[i][c] = l.lo[i][c] = l.hi[i][c] = rgba[i * 4 + c];
    }
    l.covered[i] = baked[i] ? 1 : 0;
  }
  return l;
}

MipLevel half(const MipLevel& f) {
  MipLevel l;
  l.n = f.n / 2;
  const std::size_t count = static_cast<std::size_t>(l.n) * l.n;
  l.rgb.assign(count, {0, 0, 0});
  l.cov.assign(count, {0, 0, 0});
  l.lo.assign(count, {INFINITY, INFINITY, INFINITY});
  l.hi.assign(count, {-INFINITY, -INFINITY, -INFINITY});
  l.covered.assign(count, 0);
  for (int y = 0; y < l.n; ++y) {
    for (int x = 0; x < l.n; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * l.n + x;
      for (int dy = 0; dy < 2; ++dy) {
        for (int dx = 0; dx < 2; ++dx) {
          const std::size_t j = static_cast<std::size_t>(2 * y + dy) * f.n + (2 * x + dx);
          for (int c = 0; c < 3; ++c) {
            l.rgb[i][c] += f.rgb[j][c] / 4;
            l.cov[i][c] += f.cov[j][c];
            l.lo[i][c] = std::min(l.lo[i][c], f.lo[j][c]);
            l.hi[i][c] = std::max(l.hi[i][c], f.hi[j][c]);
          }
          l.covered[i] += f.covered[j];
        }
      }
    }
  }
  return l;
}

struct LevelFigures {
  std::size_t checked = 0, bad = 0;
  double worst = 0;  // largest departure beyond the criterion's bound
};

// Criterion 1 (constant texture c) at one level.
LevelFigures constant_check(const MipLevel& l, const std::array<double, 3>& c) {
  LevelFigures f;
  for (std::size_t i = 0; i < l.rgb.size(); ++i) {
    if (l.covered[i] == 0) continue;
    ++f.checked;
    double e = 0;
    for (int ch = 0; ch < 3; ++ch) e = std::max(e, std::abs(l.rgb[i][ch] - c[ch]));
    f.worst = std::max(f.worst, e);
    f.bad += e > 1e-5;
  }
  return f;
}

// Criterion 2: the range of the covered texels in the level texels within
// Chebyshev distance r (in level texels) of this one.
LevelFigures range_check(const MipLevel& l, int r) {
  LevelFigures f;
  for (int y = 0; y < l.n; ++y) {
    for (int x = 0; x < l.n; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * l.n + x;
      if (l.covered[i] == 0) continue;
      ++f.checked;
      std::array<double, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
      for (int yy = std::max(0, y - r); yy <= std::min(l.n - 1, y + r); ++yy) {
        for (int xx = std::max(0, x - r); xx <= std::min(l.n - 1, x + r); ++xx) {
          const std::size_t j = static_cast<std::size_t>(yy) * l.n + xx;
          for (int ch = 0; ch < 3; ++ch) {
            lo[ch] = std::min(lo[ch], l.lo[j][ch]);
            hi[ch] = std::max(hi[ch], l.hi[j][ch]);
          }
        }
      }
      double e = 0;
      for (int ch = 0; ch < 3; ++ch) {
        e = std::max({e, lo[ch] - l.rgb[i][ch], l.rgb[i][ch] - hi[ch]});
      }
      f.worst = std::max(f.worst, e);
      f.bad += e > 1e-5;
    }
  }
  return f;
}

struct Case {
  std::string mesh;
  int size;
};

// The four configurations; each mesh is loaded once.
const MeshData& load(const std::string& name) {
  static std::map<std::string, MeshData> cache;
  if (auto it = cache.find(name); it != cache.end()) return it->second;
  auto read = read_mesh(test::shared_data(name));
  EXPECT_TRUE(read) << name;
  return cache[name] = read ? std::move(read->mesh) : MeshData{};
}

// A sphere around the mesh's bounding box, pole +y (both meshes are y up).
Proxy sphere_around(const MeshData& mesh) {
  Vec3 lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
  for (const Float3& p : mesh.positions) {
    lo = {std::min(lo.x, double(p.x)), std::min(lo.y, double(p.y)), std::min(lo.z, double(p.z))};
    hi = {std::max(hi.x, double(p.x)), std::max(hi.y, double(p.y)), std::max(hi.z, double(p.z))};
  }
  const Vec3 c = (lo + hi) * 0.5;
  return make_proxy(SphereParams{c, length(hi - lo) / 2, {0, 1, 0}, Vec3{0, 0, 1}}).value();
}

class AtlasMip : public ::testing::TestWithParam<Case> {};

TEST_P(AtlasMip, DefaultPaddingSurvivesBoxDownsampling) {
  const Case& p = GetParam();
  const MeshData& mesh = load(p.mesh);
  ASSERT_GT(mesh.triangles.size(), 0u);
  const test::BunnyEarth* be = test::bunny_earth();
  ASSERT_NE(be, nullptr);
  auto uv_mesh = test::bunny_with_generated_uvs(mesh, p.size);
  ASSERT_TRUE(uv_mesh) << uv_mesh.error().message;
  const Proxy proxy = sphere_around(mesh);

  Image constant;
  constant.width = constant.height = 1;
  const std::array<double, 3> c{0.9, 0.7, 0.5};
  constant.pixels = {0.9f, 0.7f, 0.5f, 1.f};

  AtlasBakeOptions o;
  o.size = p.size;
  o.samples = 1;
  o.shading.visibility = Visibility::kAll;  // the padding is the subject, not visibility
  const int n = p.size;
  const int rings = default_padding(n);
  for (int image = 0; image < 2; ++image) {
    const ImageView view = image == 0 ? constant.view() : be->earth.view();
    auto baked = bake_atlas(*uv_mesh, view, proxy, o);
    ASSERT_TRUE(baked) << baked.error().message;
    const std::vector<float>& now = baked->atlas.pixels;
    // The old default from the same bake: covered texels, then the rings.
    std::vector<float> old(now.size(), 0.f);
    std::vector<uint8_t> mask = baked->baked;
    for (std::size_t t = 0; t < mask.size(); ++t) {
      if (mask[t]) std::copy(&now[t * 4], &now[t * 4] + 4, &old[t * 4]);
    }
    dilate(old, mask, n, n, rings);
    // The rings are as before (all four channels), the rest has alpha 0.
    for (std::size_t t = 0; t < mask.size(); ++t) {
      if (mask[t]) {
        ASSERT_EQ(std::vector<float>(&now[t * 4], &now[t * 4] + 4),
                  std::vector<float>(&old[t * 4], &old[t * 4] + 4))
            << "texel " << t;
      } else {
        ASSERT_EQ(now[t * 4 + 3], 0.f) << "texel " << t;
      }
    }

    MipLevel new_level = base_level(now, baked->baked, n);
    MipLevel old_level = base_level(old, baked->baked, n);
    std::size_t old_bad = 0;
    for (int k = 1; k <= 4; ++k) {
      new_level = half(new_level);
      old_level = half(old_level);
      // Blocks around: one, plus those the rings reach (a ring texel is a
      // mean of texels within `rings` texels).
      const int around = 1 + (rings + (1 << k) - 1) / (1 << k);
      const LevelFigures fn =
          image == 0 ? constant_check(new_level, c) : range_check(new_level, around);
      const LevelFigures fo =
          image == 0 ? constant_check(old_level, c) : range_check(old_level, around);
      std::printf(
          "[ %s %d %s level %d (1/%d): %zu texels with chart; push-pull %zu beyond "
          "(worst %.2g), old padding %zu beyond (worst %.3f) ]\n",
          p.mesh.c_str(), n, image == 0 ? "constant" : "earth", k, 1 << k, fn.checked, fn.bad,
          fn.worst, fo.bad, fo.worst);
      EXPECT_EQ(fn.bad, 0u) << p.mesh << " " << n << " level " << k << " worst " << fn.worst;
      old_bad += fo.bad;
    }
    // The criterion tells the old padding apart (the test can fail).
    EXPECT_GT(old_bad, 0u) << p.mesh << " " << n;
  }
}

INSTANTIATE_TEST_SUITE_P(BunnyAndArmadillo, AtlasMip,
                         ::testing::Values(Case{"bunny00.off", 1024}, Case{"bunny00.off", 2048},
                                           Case{"armadillo.off", 1024},
                                           Case{"armadillo.off", 2048}),
                         [](const auto& info) {
                           return info.param.mesh.substr(0, info.param.mesh.find('.')) +
                                  std::to_string(info.param.size);
                         });

}  // namespace
}  // namespace texbake
