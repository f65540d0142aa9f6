// MIP pyramid by an exact box filter and the EWA lookup (mapping/mipmap.h).
#include "mapping/mipmap.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "mapping/sample.h"
#include "mapping/tiled_image.h"

namespace texbake {

namespace {

// One output texel of a 1D box reduction: input texels [first, first + count)
// with weights summing to 1 (their overlap with the output's interval).
struct BoxTap {
  int first = 0, count = 0;
  double weight[3] = {0, 0, 0};  // a reduction by < 3 touches at most 3 inputs
};

std::vector<BoxTap> box_taps(int in, int out) {
  std::vector<BoxTap> taps(static_cast<std::size_t>(out));
  const double ratio = static_cast<double>(in) / out;  // in [2, 3) (or 1 for a size-1 side)
  for (int j = 0; j < out; ++j) {
    const double lo = j * ratio, hi = (j + 1) * ratio;
    BoxTap& t = taps[static_cast<std::size_t>(j)];
    t.first = static_cast<int>(std::floor(lo));
    const int last = std::min(in - 1, static_cast<int>(std::ceil(hi)) - 1);
    t.count = last - t.first + 1;
    for (int i = t.first; i <= last; ++i) {
      const double overlap = std::min<double>(i + 1, hi) - std::max<double>(i, lo);
      t.weight[i - t.first] = overlap / ratio;
    }
  }
  return taps;
}

// Row y of `src`: in place in memory, else read into `scratch` (a tiled
// level 0, mapping/tiled_image.h; a failed read leaves zeros and the
// source's error, which the bake reports).
const float* row_of(const ImageView& src, int y, std::vector<float>& scratch) {
  if (src.data) return src.pixel(0, y);
  scratch.resize(static_cast<std::size_t>(src.width) * 4);
  read_rows(src, y, y + 1, scratch.data());
  return scratch.data();
}

// Level `src` reduced to w x h (separable: each output row sums its input
// rows' horizontal reductions, in double; one row of scratch per chunk).
// Rows are independent: the result does not depend on how `for_rows` splits them.
std::vector<float> reduce(const ImageView& src, int w, int h, const RowRunner& for_rows) {
  const std::vector<BoxTap> tx = box_taps(src.width, w), ty = box_taps(src.height, h);
  std::vector<float> out(static_cast<std::size_t>(w) * h * 4);
  if (src.width == 2 * w && src.height == 2 * h) {
    // Even sizes: 2 x 2 blocks of weight 1/4 each, the same sums as below
    // (halving is exact in double).
    for_rows(static_cast<std::size_t>(h), [&](std::size_t begin, std::size_t end) {
      std::vector<float> s0, s1;
      for (std::size_t y = begin; y < end; ++y) {
        const float* r0 = row_of(src, static_cast<int>(2 * y), s0);
        const float* r1 = row_of(src, static_cast<int>(2 * y + 1), s1);
        float* o = &out[y * static_cast<std::size_t>(w) * 4];
        for (int x = 0; x < w; ++x) {
          for (int c = 0; c < 4; ++c) {
            const double top = 0.5 * (static_cast<double>(r0[8 * x + c]) + r0[8 * x + 4 + c]);
            const double bottom = 0.5 * (static_cast<double>(r1[8 * x + c]) + r1[8 * x + 4 + c]);
            o[4 * x + c] = static_cast<float>(0.5 * (top + bottom));
          }
        }
      }
    });
    return out;
  }
  for_rows(static_cast<std::size_t>(h), [&](std::size_t begin, std::size_t end) {
    std::vector<double> acc(static_cast<std::size_t>(w) * 4);
    std::vector<float> scratch;
    for (std::size_t y = begin; y < end; ++y) {
      std::fill(acc.begin(), acc.end(), 0.0);
      const BoxTap& t = ty[y];
      for (int ky = 0; ky < t.count; ++ky) {
        const float* in = row_of(src, t.first + ky, scratch);
        for (int x = 0; x < w; ++x) {
          const BoxTap& u = tx[static_cast<std::size_t>(x)];
          double sum[4] = {0, 0, 0, 0};
          for (int kx = 0; kx < u.count; ++kx) {
            const float* p = in + static_cast<std::size_t>(u.first + kx) * 4;
            for (int c = 0; c < 4; ++c) sum[c] += u.weight[kx] * p[c];
          }
          double* a = &acc[static_cast<std::size_t>(x) * 4];
          for (int c = 0; c < 4; ++c) a[c] += t.weight[ky] * sum[c];
        }
      }
      float* o = &out[y * static_cast<std::size_t>(w) * 4];
      for (std::size_t i = 0; i < acc.size(); ++i) o[i] = static_cast<float>(acc[i]);
    }
  });
  return out;
}

// pbrt-v4's MIPFilterLUT: exp(-alpha r^2) - exp(-alpha), alpha = 2, for r^2
// = i / (n - 1).
constexpr int kLutSize = 128;
const std::array<double, kLutSize>& gaussian_lut() {
  static const std::array<double, kLutSize> lut = [] {
    std::array<double, kLutSize> t{};
    for (int i = 0; i < kLutSize; ++i) {
      const double r2 = static_cast<double>(i) / (kLutSize - 1);
      t[static_cast<std::size_t>(i)] = std::exp(-2 * r2) - std::exp(-2.0);
    }
    return t;
  }();
  return lut;
}

// Texel index i folded into [0, n) (as sample.cpp's fold, int form).
inline int fold(int i, int n, WrapMode mode) {
  if (i >= 0 && i < n) return i;
  if (mode == WrapMode::kRepeat) {
    i %= n;
    return i < 0 ? i + n : i;
  }
  return i < 0 ? 0 : n - 1;
}

// The Gaussian-weighted mean over the ellipse of axes a, b (level-0 pixels,
// scaled here to `level`'s), centred on uv, plus pbrt's one-texel widening.
void ewa_level(const ImageView& level, double scale_x, double scale_y, UV uv, Vec2 a, Vec2 b,
               WrapMode wrap_u, WrapMode wrap_v, double out[4]) {
  const PixelPos c = pixel_from_uv(uv, level.width, level.height);
  const double ax = a.x * scale_x, ay = a.y * scale_y, bx = b.x * scale_x, by = b.y * scale_y;
  // The implicit ellipse A x^2 + B x y + C y^2 < 1 (pbrt-v4 MIPMap::EWA).
  double A = ay * ay + by * by + 1;
  double B = -2 * (ax * ay + bx * by);
  double C = ax * ax + bx * bx + 1;
  const double inv_f = 1 / (A * C - B * B * 0.25);
  A *= inv_f;
  B *= inv_f;
  C *= inv_f;
  const double det = -B * B + 4 * A * C;
  const double inv_det = 1 / det;
  const double half_x = 2 * inv_det * std::sqrt(det * C);
  const double half_y = 2 * inv_det * std::sqrt(A * det);
  const int x0 = static_cast<int>(std::ceil(c.x - half_x));
  const int x1 = static_cast<int>(std::floor(c.x + half_x));
  const int y0 = static_cast<int>(std::ceil(c.y - half_y));
  const int y1 = static_cast<int>(std::floor(c.y + half_y));
  const std::array<double, kLutSize>& lut = gaussian_lut();
  double sum[4] = {0, 0, 0, 0};
  double weights = 0;
  for (int y = y0; y <= y1; ++y) {
    const double dy = y - c.y;
    const int row = fold(y, level.height, wrap_v);
    for (int x = x0; x <= x1; ++x) {
      const double dx = x - c.x;
      const double r2 = A * dx * dx + B * dx * dy + C * dy * dy;
      if (!(r2 < 1)) continue;
      const double w =
          lut[static_cast<std::size_t>(std::min(static_cast<int>(r2 * kLutSize), kLutSize - 1))];
      const Rgba p = level.texel(fold(x, level.width, wrap_u), row);
      for (int k = 0; k < 4; ++k) sum[k] += w * p[k];
      weights += w;
    }
  }
  if (!(weights > 0)) {  // cannot happen (the unit disc always holds a texel centre)
    const Rgba s = sample_bilinear(level, uv, wrap_u, wrap_v);
    for (int k = 0; k < 4; ++k) out[k] = s[k];
    return;
  }
  for (int k = 0; k < 4; ++k) out[k] = sum[k] / weights;
}

// The Gaussian-weighted mean of level `i`'s row means over v half-extent ev
// (level-0 texels) around uv.v, plus the one-texel widening: the 1D EWA of
// a footprint that covers whole rows.
void rows_level(const MipPyramid& mip, int i, double ev, UV uv, WrapMode wrap_v, double out[4]) {
  const ImageView& level = mip.level(i);
  const double cy = (1.0 - uv.v) * level.height - 0.5;
  const double e = ev * level.height / mip.level(0).height;
  const double radius2 = e * e + 1;
  const double radius = std::sqrt(radius2);
  const int y0 = static_cast<int>(std::ceil(cy - radius));
  const int y1 = static_cast<int>(std::floor(cy + radius));
  const std::array<double, kLutSize>& lut = gaussian_lut();
  double sum[4] = {0, 0, 0, 0};
  double weights = 0;
  for (int y = y0; y <= y1; ++y) {
    const double r2 = (y - cy) * (y - cy) / radius2;
    if (!(r2 < 1)) continue;
    const double w =
        lut[static_cast<std::size_t>(std::min(static_cast<int>(r2 * kLutSize), kLutSize - 1))];
    const double* m = mip.row_mean(i, fold(y, level.height, wrap_v));
    for (int k = 0; k < 4; ++k) sum[k] += w * m[k];
    weights += w;
  }
  for (int k = 0; k < 4; ++k) out[k] = sum[k] / weights;  // the unit radius holds a row centre
}

}  // namespace

static void serial_rows(std::size_t count,
                        const std::function<void(std::size_t, std::size_t)>& body) {
  body(0, count);
}

MipPyramid::MipPyramid(const ImageView& base, const RowRunner& for_rows) {
  views_.push_back(base);
  views_.back().mip_levels = nullptr;
  views_.back().mip_level_count = 0;
  if (base.mip_level_count > 0 && !base.decode_srgb && !base.premultiply) {
    for (int i = 0; i < base.mip_level_count; ++i) views_.push_back(base.mip_levels[i]);
  } else {
    const RowRunner& run = for_rows ? for_rows : RowRunner(serial_rows);
    while (views_.back().width > 1 || views_.back().height > 1) {
      const ImageView& src = views_.back();
      const int w = std::max(1, src.width / 2), h = std::max(1, src.height / 2);
      owned_.push_back(reduce(src, w, h, run));
      views_.push_back(ImageView{w, h, owned_.back().data(), base.color_space});
    }
  }
  row_means_.resize(views_.size());
  for (std::size_t i = 0; i < views_.size(); ++i) {
    const std::size_t h = static_cast<std::size_t>(views_[i].height);
    row_means_[i] = std::make_unique<RowMeans>();
    row_means_[i]->once = std::make_unique<std::once_flag[]>(h);
    row_means_[i]->means.assign(h * 4, 0.0);
  }
}

void MipPyramid::compute_row_mean(int i, int y) const {
  const ImageView& level = views_[static_cast<std::size_t>(i)];
  double* m = &row_means_[static_cast<std::size_t>(i)]->means[static_cast<std::size_t>(y) * 4];
  std::vector<float> scratch;
  const float* row = row_of(level, y, scratch);
  for (int x = 0; x < level.width; ++x) {
    const float* p = row + static_cast<std::size_t>(x) * 4;
    for (int k = 0; k < 4; ++k) m[k] += p[k];
  }
  for (int k = 0; k < 4; ++k) m[k] /= level.width;
}

std::size_t MipPyramid::owned_bytes() const {
  std::size_t bytes = 0;
  for (const std::vector<float>& level : owned_) bytes += level.size() * sizeof(float);
  for (const auto& r : row_means_) bytes += r->means.size() * sizeof(double);
  return bytes;
}

Rgba sample_ewa(const MipPyramid& mip, UV uv, UvFootprint footprint, WrapMode wrap_u,
                WrapMode wrap_v, double max_anisotropy) {
  const ImageView& base = mip.level(0);
  const double cap = 2.0 * std::max(base.width, base.height);
  // A NaN coordinate is a caller bug: sample_bilinear defines it. Far-off
  // coordinates (a plane's points far outside) come near: a periodic axis
  // shifted by whole periods (the lattice does not move), a clamped one to
  // just past the widest footprint's reach, where every texel is the edge's.
  if (!std::isfinite(uv.u) || !std::isfinite(uv.v)) {
    return sample_bilinear(base, uv, wrap_u, wrap_v);
  }
  const double reach = 1 + (cap + 2) / std::min(base.width, base.height);
  auto settle = [reach](double t, WrapMode mode) {
    return mode == WrapMode::kRepeat ? t - std::floor(t) : std::clamp(t, -reach, 1 + reach);
  };
  uv = {settle(uv.u, wrap_u), settle(uv.v, wrap_v)};
  // Level-0 pixels (the sign of y does not matter to an ellipse).
  Vec2 a{footprint.a.x * base.width, footprint.a.y * base.height};
  Vec2 b{footprint.b.x * base.width, footprint.b.y * base.height};
  for (Vec2* axis : {&a, &b}) {
    if (!std::isfinite(axis->x)) axis->x = cap;
    if (!std::isfinite(axis->y)) axis->y = cap;
  }
  if (dot(a, a) < dot(b, b)) std::swap(a, b);
  double major = std::sqrt(dot(a, a)), minor = std::sqrt(dot(b, b));
  if (major <= 1) return sample_bilinear(base, uv, wrap_u, wrap_v);  // magnification
  // Periodic u and a footprint as wide as the period (a pole): whole rows.
  double rows_share = 0;
  if (wrap_u == WrapMode::kRepeat) {
    const double width = 2 * std::sqrt(a.x * a.x + b.x * b.x);  // the ellipse's u extent
    rows_share = std::clamp(2 * width / base.width - 1, 0.0, 1.0);
  }
  double rows[4] = {0, 0, 0, 0};
  if (rows_share > 0) {
    const double ev = std::min(cap, std::sqrt(a.y * a.y + b.y * b.y));  // v half-extent
    const double lod = std::max(0.0, std::log2(ev));
    const int top = mip.levels() - 1;
    const int ilod = std::min(top, static_cast<int>(std::floor(lod)));
    rows_level(mip, ilod, ev, uv, wrap_v, rows);
    const double t = ilod < top ? lod - ilod : 0.0;
    if (t > 0) {
      double hi[4];
      rows_level(mip, ilod + 1, ev, uv, wrap_v, hi);
      for (int k = 0; k < 4; ++k) rows[k] += t * (hi[k] - rows[k]);
    }
    if (rows_share == 1) {
      Rgba result;
      for (int k = 0; k < 4; ++k) result[k] = static_cast<float>(rows[k]);
      return result;
    }
  }
  if (major > cap) {
    a = a * (cap / major);
    major = cap;
  }
  if (minor > cap) {
    b = b * (cap / minor);
    minor = cap;
  }
  if (minor * max_anisotropy < major) {
    // Lengthen the minor axis (in its own direction, or across the major one
    // when it has none).
    const double target = major / max_anisotropy;
    b = minor > 0 ? b * (target / minor) : Vec2{-a.y, a.x} * (target / major);
    minor = target;
  }
  const double lod = std::max(0.0, std::log2(minor));
  const int top = mip.levels() - 1;
  const int ilod = static_cast<int>(std::floor(lod));
  auto at = [&](int i, double out[4]) {
    const ImageView& level = mip.level(i);
    ewa_level(level, static_cast<double>(level.width) / base.width,
              static_cast<double>(level.height) / base.height, uv, a, b, wrap_u, wrap_v, out);
  };
  double lo[4], hi[4];
  if (ilod >= top) {
    at(top, lo);
  } else {
    at(ilod, lo);
    const double t = lod - ilod;
    if (t > 0) {
      at(ilod + 1, hi);
      for (int k = 0; k < 4; ++k) lo[k] += t * (hi[k] - lo[k]);
    }
  }
  Rgba result;
  for (int k = 0; k < 4; ++k) {
    result[k] = static_cast<float>(lo[k] + rows_share * (rows[k] - lo[k]));
  }
  return result;
}

}  // namespace texbake
