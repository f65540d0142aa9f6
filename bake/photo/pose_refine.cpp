#include "bake/photo/pose_refine.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>
#include <numeric>
#include <span>

#include "bake/photo/photo_view.h"
#include "bake/photo/segments.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "mesh_io/vertex_normals.h"

namespace texbake {

namespace {

constexpr std::size_t kBlock = 1024;  // points or pairs per parallel block
constexpr int kMinLevelSide = 48;     // the coarsest level's shorter side is at least this
constexpr int kMaxLevels = 5;
constexpr double kMaxViewAngleDeg = 75;   // the photo bake's cull (SPEC section 9)
constexpr double kDepthTolerance = 0.02;  // discontinuity: tangent plane missed by 2 % of depth
constexpr int kContourRays = 8;
constexpr double kHuberSigmas = 1.5;
constexpr double kTruncationSigmas = 6;
constexpr double kMinSigma = 1e-3;  // linear light: below 8-bit quantisation in the mid-tones
constexpr int kMaxTries = 6;        // Levenberg-Marquardt damping increases per step
constexpr int kMaxParams = 10;      // 6 pose + fx fy cx cy

// ---- Photos as pyramids ----------------------------------------------------

// One level of a photo: linear-light RGB as 16-bit integers (value * 65535:
// steps of 1.5e-5, far below an 8-bit photo's, at half of float's memory:
// every photo stays in memory for the whole refinement).
struct Level {
  int w = 0, h = 0;
  std::vector<uint16_t> rgb;
  // A masked photo's alpha (photo_bake.h "Masks"; a coarser texel: the mean
  // of the four below it), the colours then straight (not premultiplied: a
  // coarser texel is the alpha-weighted mean of the colours below it). Empty:
  // the photo has no mask. A sample is taken only where the four texels it
  // interpolates all have some alpha: a masked-out pixel is never used.
  std::vector<float> alpha;
  bool covered(int x, int y) const {
    return alpha.empty() || alpha[static_cast<std::size_t>(y) * w + x] > 0;
  }
  float at(int x, int y, int ch) const {
    return rgb[3 * (static_cast<std::size_t>(y) * w + x) + ch] * (1.0f / 65535.0f);
  }
};

struct Pyramid {
  std::vector<Level> levels;
  double sx = 1, sy = 1;  // photo pixels per camera pixel (a photo scaled to its camera)
};

int level_count(int w, int h) {
  int levels = 1;
  while (levels < kMaxLevels && std::min(w, h) / (1 << levels) >= kMinLevelSide) ++levels;
  return levels;
}

uint16_t to_u16(float v) {
  return static_cast<uint16_t>(std::clamp(v, 0.0f, 1.0f) * 65535.0f + 0.5f);
}

// Level 0 is the photo; each next one the 2x2 box mean of the one before (an
// odd last row or column dropped), so that texel j of level L covers photo
// pixels [j 2^L, (j + 1) 2^L). `masked`: the photo's colours are
// premultiplied by its alpha (load_photo), which the levels keep apart.
Pyramid make_pyramid(const PhotoImage& image, bool masked, double sx, double sy, int levels) {
  Pyramid p;
  p.sx = sx, p.sy = sy;
  p.levels.resize(static_cast<std::size_t>(levels));
  Level& base = p.levels[0];
  base.w = image.width, base.h = image.height;
  const std::size_t n = static_cast<std::size_t>(base.w) * base.h;
  base.rgb.resize(3 * n);
  if (masked) base.alpha.resize(n);
  parallel_for_chunks(n, 1 << 14, [&](std::size_t b, std::size_t e) {
    for (std::size_t i = b; i < e; ++i) {
      const float a = masked ? image.pixels[4 * i + 3] : 1.0f;
      if (masked) base.alpha[i] = a;
      for (int ch = 0; ch < 3; ++ch) {
        base.rgb[3 * i + ch] = a > 0 ? to_u16(image.pixels[4 * i + ch] / a) : 0;
      }
    }
  });
  for (int l = 1; l < levels; ++l) {
    const Level& f = p.levels[l - 1];
    Level& c = p.levels[l];
    c.w = std::max(1, f.w / 2), c.h = std::max(1, f.h / 2);
    c.rgb.resize(3 * static_cast<std::size_t>(c.w) * c.h);
    if (masked) c.alpha.resize(static_cast<std::size_t>(c.w) * c.h);
    for (int y = 0; y < c.h; ++y) {
      const int y0 = std::min(2 * y, f.h - 1), y1 = std::min(2 * y + 1, f.h - 1);
      for (int x = 0; x < c.w; ++x) {
        const int x0 = std::min(2 * x, f.w - 1), x1 = std::min(2 * x + 1, f.w - 1);
        const std::size_t out = static_cast<std::size_t>(y) * c.w + x;
        const std::size_t in[4] = {
            static_cast<std::size_t>(y0) * f.w + x0, static_cast<std::size_t>(y0) * f.w + x1,
            static_cast<std::size_t>(y1) * f.w + x0, static_cast<std::size_t>(y1) * f.w + x1};
        if (!masked) {
          for (int ch = 0; ch < 3; ++ch) {
            unsigned sum = 2;
            for (std::size_t k : in) sum += f.rgb[3 * k + ch];
            c.rgb[3 * out + ch] = static_cast<uint16_t>(sum / 4);
          }
          continue;
        }
        float weight = 0;
        for (std::size_t k : in) weight += f.alpha[k];
        c.alpha[out] = weight / 4;
        for (int ch = 0; ch < 3; ++ch) {
          float sum = 0;
          for (std::size_t k : in) sum += f.alpha[k] * f.rgb[3 * k + ch] * (1.0f / 65535.0f);
          c.rgb[3 * out + ch] = weight > 0 ? to_u16(sum / weight) : 0;
        }
      }
    }
  }
  return p;
}

// The level's bilinear value at (x, y) (texel centres at integers) and, with
// gx/gy, its gradient: the central differences of the four texels around,
// interpolated bilinearly (smooth across texel boundaries, unlike the
// derivative of the bilinear interpolant). False outside [1, w - 2] x [1, h
// - 2], where the differences would need texels beyond the edge, and for a
// masked photo where one of the four texels interpolated has alpha 0.
bool sample_level(const Level& l, double x, double y, double rgb[3], double* gx, double* gy) {
  if (!(x >= 1 && y >= 1 && x <= l.w - 2 && y <= l.h - 2)) return false;
  const int x0 = std::min(static_cast<int>(x), l.w - 3),
            y0 = std::min(static_cast<int>(y), l.h - 3);
  if (!(l.covered(x0, y0) && l.covered(x0 + 1, y0) && l.covered(x0, y0 + 1) &&
        l.covered(x0 + 1, y0 + 1))) {
    return false;
  }
  const double fx = x - x0, fy = y - y0;
  const double w00 = (1 - fx) * (1 - fy), w10 = fx * (1 - fy), w01 = (1 - fx) * fy, w11 = fx * fy;
  for (int ch = 0; ch < 3; ++ch) {
    const auto t = [&](int xx, int yy) {
      return static_cast<double>(l.at(std::clamp(xx, 0, l.w - 1), std::clamp(yy, 0, l.h - 1), ch));
    };
    rgb[ch] = w00 * t(x0, y0) + w10 * t(x0 + 1, y0) + w01 * t(x0, y0 + 1) + w11 * t(x0 + 1, y0 + 1);
    if (!gx) continue;
    const auto dx = [&](int xx, int yy) { return (t(xx + 1, yy) - t(xx - 1, yy)) / 2; };
    const auto dy = [&](int xx, int yy) { return (t(xx, yy + 1) - t(xx, yy - 1)) / 2; };
    gx[ch] =
        w00 * dx(x0, y0) + w10 * dx(x0 + 1, y0) + w01 * dx(x0, y0 + 1) + w11 * dx(x0 + 1, y0 + 1);
    gy[ch] =
        w00 * dy(x0, y0) + w10 * dy(x0 + 1, y0) + w01 * dy(x0, y0 + 1) + w11 * dy(x0 + 1, y0 + 1);
  }
  return true;
}

// ---- Cameras -----------------------------------------------------------------

bool one_focal(CameraModel m) {
  return m == CameraModel::kSimplePinhole || m == CameraModel::kSimpleRadial ||
         m == CameraModel::kRadial;
}
bool has_distortion(CameraModel m) {
  return m != CameraModel::kSimplePinhole && m != CameraModel::kPinhole;
}

// A camera being refined: its pose (X_cam = r X + t) and linear intrinsics;
// the lens distortion stays the input camera's (`lens`), applied to the
// normalised image plane before the intrinsics.
struct CamState {
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t = Eigen::Vector3d::Zero();
  double fx = 1, fy = 1, cx = 0, cy = 0;
  Eigen::Vector3d centre() const { return -r.transpose() * t; }
};

struct Lens {
  const CameraProjector* camera = nullptr;
  bool distorted = false;
  double fx = 1, fy = 1, cx = 0, cy = 0;  // the input's, to undo its linear part
  int width = 0, height = 0;              // the camera's image size
  double max_r2 = 0;
  int focal_params = 2;  // 1 for the one-focal models
};

Lens lens_of(const CameraProjector& camera) {
  Lens l;
  l.camera = &camera;
  const CameraSpec& s = camera.spec();
  l.distorted = has_distortion(s.model);
  const bool one = one_focal(s.model);
  l.focal_params = one ? 1 : 2;
  l.fx = s.params[0];
  l.fy = one ? s.params[0] : s.params[1];
  l.cx = s.params[one ? 1 : 2];
  l.cy = s.params[one ? 2 : 3];
  l.width = s.width, l.height = s.height;
  l.max_r2 = camera.max_radius2();
  return l;
}

CamState state_of(const CameraProjector& camera, const Lens& lens) {
  CamState c;
  const CameraPose& p = camera.spec().pose;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) c.r(i, j) = p.r[3 * i + j];
  }
  c.t = {p.t.x, p.t.y, p.t.z};
  c.fx = lens.fx, c.fy = lens.fy, c.cx = lens.cx, c.cy = lens.cy;
  return c;
}

// Where a point lands: camera coordinates, normalised (a, b), distorted
// normalised (da, db) and the pixel (camera pixels, COLMAP's convention).
struct Projected {
  Eigen::Vector3d xc;
  double a = 0, b = 0, da = 0, db = 0, px = 0, py = 0;
};

bool distort(const Lens& lens, double a, double b, double& da, double& db) {
  if (!lens.distorted) {
    da = a, db = b;
    return true;
  }
  const Vec2 p = lens.camera->pixel_of_normalised(a, b);
  da = (p.x - lens.cx) / lens.fx;
  db = (p.y - lens.cy) / lens.fy;
  return true;
}

bool project(const CamState& c, const Lens& lens, const Eigen::Vector3d& x, Projected& out) {
  out.xc = c.r * x + c.t;
  if (!(out.xc.z() > 0)) return false;
  out.a = out.xc.x() / out.xc.z(), out.b = out.xc.y() / out.xc.z();
  if (!(out.a * out.a + out.b * out.b <= lens.max_r2)) return false;
  distort(lens, out.a, out.b, out.da, out.db);
  out.px = c.fx * out.da + c.cx;
  out.py = c.fy * out.db + c.cy;
  return out.px >= 0 && out.px <= lens.width && out.py >= 0 && out.py <= lens.height;
}

// d(da, db) / d(a, b): the identity without distortion, else central
// differences of the lens model (smooth polynomials: h = 1e-6 leaves an
// error near 1e-10, far below what a step needs).
Eigen::Matrix2d distortion_jacobian(const Lens& lens, double a, double b) {
  if (!lens.distorted) return Eigen::Matrix2d::Identity();
  const double h = 1e-6 * std::max(1.0, std::hypot(a, b));
  Eigen::Matrix2d d;
  double pa, pb, ma, mb;
  distort(lens, a + h, b, pa, pb);
  distort(lens, a - h, b, ma, mb);
  d(0, 0) = (pa - ma) / (2 * h), d(1, 0) = (pb - mb) / (2 * h);
  distort(lens, a, b + h, pa, pb);
  distort(lens, a, b - h, ma, mb);
  d(0, 1) = (pa - ma) / (2 * h), d(1, 1) = (pb - mb) / (2 * h);
  return d;
}

double rotation_angle(const Eigen::Matrix3d& r) {
  return Eigen::AngleAxisd(r).angle();
}

// ---- The loss ----------------------------------------------------------------

struct Loss {
  double delta = 1, cap = 1;  // Huber threshold, truncation
  double rho(double e) const {
    e = std::min(e, cap);
    return e <= delta ? e * e / 2 : delta * (e - delta / 2);
  }
  double weight(double e) const { return e <= delta ? 1 : (e <= cap ? delta / e : 0); }
};

// ---- The refinement ------------------------------------------------------------

class Refiner {
 public:
  Refiner(const EmbreeScene& scene, double offset, double size, std::vector<Vec3> points,
          std::vector<Vec3> normals, std::vector<Pyramid> pyramids, std::vector<Lens> lenses,
          std::vector<CamState> states, const PoseRefineOptions& options)
      : scene_(scene),
        offset_(offset),
        size_(size),
        points_(std::move(points)),
        normals_(std::move(normals)),
        pyr_(std::move(pyramids)),
        lens_(std::move(lenses)),
        state_(std::move(states)),
        initial_(state_),
        options_(options),
        cams_(state_.size()),
        gain_(cams_, {1, 1, 1}),
        loss_(cams_),
        iterations_(cams_, 0),
        clamped_(cams_, 0) {
    offsets_.assign(cams_ + 1, 0);
    for (std::size_t c = 0; c < cams_; ++c) {
      offsets_[c + 1] = offsets_[c] + (options.intrinsics ? 8 + lens_[c].focal_params : 6);
    }
  }

  std::size_t cameras() const { return cams_; }
  const CamState& state(std::size_t c) const { return state_[c]; }
  const std::array<double, 3>& gain(std::size_t c) const { return gain_[c]; }
  int iterations(std::size_t c) const { return iterations_[c]; }
  bool clamped(std::size_t c) const { return clamped_[c] != 0; }
  // Did any step move a photo measurably?
  bool moved() const {
    return std::any_of(iterations_.begin(), iterations_.end(), [](int n) { return n > 0; });
  }
  // Back to the input poses: the refinement and its steps are dropped.
  void reset() {
    state_ = initial_;
    std::fill(clamped_.begin(), clamped_.end(), 0);
    std::fill(iterations_.begin(), iterations_.end(), 0);
  }

  // The pairs (point, photo) of `level`: the points each photo sees at its
  // current pose, away from depth discontinuities. Returns the number of
  // points seen by two photos or more.
  std::size_t build_pairs(int level);
  // RMS residual per channel and pair count per photo at the current poses
  // on `level` (gains and consensus solved first).
  void measure(int level, std::vector<double>& rms, std::vector<std::size_t>& count);
  // One level: up to `iterations` rounds of gains and consensus, then one
  // joint Levenberg-Marquardt step on every photo's parameters. False when
  // cancelled.
  bool refine_level(int level, int iterations, Progress* progress);

 private:
  void sample_camera(std::size_t c, int level);
  void solve_consensus(int rounds);
  void point_sums();
  void update_sigmas_and_weights();
  bool target(uint32_t pair, double t[3]) const;
  // One joint step; false when no step lowered the cost or the accepted
  // one moved no photo measurably (converged).
  bool joint_step(int level, double& lambda);
  // The joint cost at `states` (every point's consensus re-solved with
  // the fixed weights, truncated Huber per sample) and, with s and g, the
  // reduced normal equations of all photos' parameters (the consensus
  // colours eliminated). Fixed blocks of points, summed in order.
  double joint(const std::vector<CamState>& states, int level, Eigen::MatrixXd* s,
               Eigen::VectorXd* g);
  bool clamp_to_bounds(std::size_t c, CamState& s) const;

  const EmbreeScene& scene_;
  double offset_, size_;
  std::vector<Vec3> points_, normals_;
  std::vector<Pyramid> pyr_;
  std::vector<Lens> lens_;
  std::vector<CamState> state_, initial_;
  PoseRefineOptions options_;
  std::size_t cams_;
  std::vector<std::array<double, 3>> gain_;
  std::vector<Loss> loss_;
  std::vector<int> offsets_;  // each photo's first parameter in the joint system
  std::vector<int> iterations_;
  std::vector<uint8_t> clamped_;

  // Pairs, photo-major: photo c's are [cam_first_[c], cam_first_[c + 1]).
  std::vector<uint32_t> cam_first_, pair_point_, pair_cam_;
  std::vector<std::array<float, 3>> pair_val_;  // the photo's sample, linear, before the gain
  std::vector<uint8_t> pair_ok_;                // inside the level at the current pose
  std::vector<uint8_t> pair_in_;                // ok and not an outlier: in the consensus
  std::vector<float> pair_w_;                   // its IRLS (Huber) weight this iteration
  // Points: their pairs (CSR) and the consensus sums sum g * val, count.
  std::vector<uint32_t> point_first_, point_pairs_;
  std::vector<std::array<double, 3>> sum_;
  std::vector<double> count_;
};

std::size_t Refiner::build_pairs(int level) {
  const double radius_px = 2 + std::ldexp(2.0, level);
  const double min_cosine = std::cos(kMaxViewAngleDeg * std::numbers::pi / 180);
  const std::size_t n = points_.size();
  std::vector<std::vector<uint8_t>> seen(cams_, std::vector<uint8_t>(n, 0));
  for (std::size_t c = 0; c < cams_; ++c) {
    const CamState s = state_[c];
    const Lens& lens = lens_[c];
    const Eigen::Vector3d ce = s.centre();
    const Vec3 centre{ce.x(), ce.y(), ce.z()};
    const double rho = radius_px / ((s.fx + s.fy) / 2);
    uint8_t* out = seen[c].data();
    parallel_for_blocks(n, kBlock, [&](std::size_t, std::size_t begin, std::size_t end) {
      std::vector<Vec3> cand;
      std::vector<uint32_t> index;
      std::vector<double> depth;
      SegmentScratch scratch;
      std::vector<uint8_t> occluded;
      Projected pr;
      for (std::size_t i = begin; i < end; ++i) {
        const Vec3 p = points_[i];
        if (!project(s, lens, {p.x, p.y, p.z}, pr)) continue;
        const Vec3 to_camera = centre - p;
        const double distance = length(to_camera);
        if (!(distance > 0 && dot(normals_[i], to_camera) > min_cosine * distance)) continue;
        cand.push_back(p);
        index.push_back(static_cast<uint32_t>(i));
        depth.push_back(pr.xc.z());
      }
      occluded.assign(cand.size(), 0);
      occluded_segments(scene_, offset_, cand, centre, scratch, occluded.data());
      // Depth discontinuities: rays around the projection against the tangent plane.
      RayArrays rays;
      rays.resize(kContourRays * cand.size());
      std::vector<uint32_t> ray_owner;
      std::size_t m = 0;
      for (std::size_t k = 0; k < cand.size(); ++k) {
        if (occluded[k]) continue;
        const Eigen::Vector3d xc = s.r * Eigen::Vector3d(cand[k].x, cand[k].y, cand[k].z) + s.t;
        const double a = xc.x() / xc.z(), b = xc.y() / xc.z();
        for (int j = 0; j < kContourRays; ++j) {
          const double phi = 2 * std::numbers::pi * j / kContourRays;
          const Eigen::Vector3d d = s.r.transpose() * Eigen::Vector3d(a + rho * std::cos(phi),
                                                                      b + rho * std::sin(phi), 1);
          rays.set(m++, centre, {d.x(), d.y(), d.z()});
        }
        ray_owner.push_back(static_cast<uint32_t>(k));
      }
      std::vector<Hit> hits(m);
      if (m) scene_.intersect(rays.batch(m), hits.data());
      for (std::size_t o = 0; o < ray_owner.size(); ++o) {
        const std::size_t k = ray_owner[o];
        const Vec3 nrm = normals_[index[k]];
        bool smooth = true;
        for (int j = 0; j < kContourRays && smooth; ++j) {
          const std::size_t r = o * kContourRays + j;
          const Hit& hit = hits[r];
          const Vec3 d{rays.dir_x[r], rays.dir_y[r], rays.dir_z[r]};
          const double nd = dot(nrm, d);
          if (hit.triangle == kNoHit || nd == 0) {
            smooth = false;
            break;
          }
          // The ray's depth (t: its camera z is 1) where it meets the tangent plane.
          const double plane = dot(nrm, cand[k] - centre) / nd;
          smooth = std::abs(hit.t - plane) <= kDepthTolerance * depth[k];
        }
        if (smooth) out[index[k]] = 1;
      }
    });
  }
  // Pairs, photo-major, points in order; then each point's pairs.
  cam_first_.assign(cams_ + 1, 0);
  pair_point_.clear();
  pair_cam_.clear();
  for (std::size_t c = 0; c < cams_; ++c) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!seen[c][i]) continue;
      pair_point_.push_back(static_cast<uint32_t>(i));
      pair_cam_.push_back(static_cast<uint32_t>(c));
    }
    cam_first_[c + 1] = static_cast<uint32_t>(pair_point_.size());
  }
  const std::size_t pairs = pair_point_.size();
  point_first_.assign(n + 1, 0);
  for (uint32_t p : pair_point_) ++point_first_[p + 1];
  for (std::size_t i = 0; i < n; ++i) point_first_[i + 1] += point_first_[i];
  point_pairs_.resize(pairs);
  std::vector<uint32_t> next(point_first_.begin(), point_first_.end() - 1);
  for (std::size_t k = 0; k < pairs; ++k)
    point_pairs_[next[pair_point_[k]]++] = static_cast<uint32_t>(k);
  pair_val_.assign(pairs, {0, 0, 0});
  pair_ok_.assign(pairs, 0);
  pair_in_.assign(pairs, 0);
  pair_w_.assign(pairs, 0);
  sum_.assign(n, {0, 0, 0});
  count_.assign(n, 0);
  std::size_t shared = 0;
  for (std::size_t i = 0; i < n; ++i) shared += point_first_[i + 1] - point_first_[i] >= 2;
  return shared;
}

void Refiner::sample_camera(std::size_t c, int level) {
  const CamState s = state_[c];
  const Lens& lens = lens_[c];
  const Pyramid& py = pyr_[c];
  const Level& l = py.levels[static_cast<std::size_t>(level)];
  const double scale = std::ldexp(1.0, -level);
  const uint32_t b0 = cam_first_[c], b1 = cam_first_[c + 1];
  parallel_for_blocks(b1 - b0, kBlock, [&](std::size_t, std::size_t begin, std::size_t end) {
    Projected pr;
    for (std::size_t k = b0 + begin; k < b0 + end; ++k) {
      const Vec3 p = points_[pair_point_[k]];
      double v[3];
      pair_ok_[k] = project(s, lens, {p.x, p.y, p.z}, pr) &&
                    sample_level(l, pr.px * py.sx * scale - 0.5, pr.py * py.sy * scale - 0.5, v,
                                 nullptr, nullptr);
      if (pair_ok_[k]) {
        pair_val_[k] = {static_cast<float>(v[0]), static_cast<float>(v[1]),
                        static_cast<float>(v[2])};
      }
    }
  });
}

// The consensus sums of every point from its pairs in the consensus.
void Refiner::point_sums() {
  parallel_for_blocks(points_.size(), kBlock, [&](std::size_t, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      std::array<double, 3> s{0, 0, 0};
      double w = 0;
      for (uint32_t j = point_first_[i]; j < point_first_[i + 1]; ++j) {
        const uint32_t k = point_pairs_[j];
        if (!pair_in_[k]) continue;
        const uint32_t c = pair_cam_[k];
        for (int ch = 0; ch < 3; ++ch) s[ch] += gain_[c][ch] * pair_val_[k][ch];
        w += 1;
      }
      sum_[i] = s;
      count_[i] = w;
    }
  });
}

// Gains and consensus by alternation, both in closed form: C_i the mean of
// the gained samples of point i, then g_c = sum val C / sum val^2 per
// channel over photo c's samples of points seen twice or more; the gains'
// geometric mean per channel fixed at 1 (the data leave a common factor free).
void Refiner::solve_consensus(int rounds) {
  for (int round = 0; round < rounds; ++round) {
    point_sums();
    std::vector<std::array<double, 3>> g(cams_);
    parallel_for_blocks(cams_, 1, [&](std::size_t c, std::size_t, std::size_t) {
      std::array<double, 3> num{0, 0, 0}, den{0, 0, 0};
      for (uint32_t k = cam_first_[c]; k < cam_first_[c + 1]; ++k) {
        const uint32_t i = pair_point_[k];
        if (!pair_in_[k] || count_[i] < 2) continue;
        for (int ch = 0; ch < 3; ++ch) {
          const double consensus = sum_[i][ch] / count_[i];
          num[ch] += pair_val_[k][ch] * consensus;
          den[ch] += static_cast<double>(pair_val_[k][ch]) * pair_val_[k][ch];
        }
      }
      for (int ch = 0; ch < 3; ++ch) {
        g[c][ch] = den[ch] > 0 && num[ch] > 0 ? num[ch] / den[ch] : gain_[c][ch];
      }
    });
    for (int ch = 0; ch < 3; ++ch) {
      double log_mean = 0;
      for (std::size_t c = 0; c < cams_; ++c) log_mean += std::log(g[c][ch]);
      const double mean = std::exp(log_mean / static_cast<double>(cams_));
      for (std::size_t c = 0; c < cams_; ++c) gain_[c][ch] = g[c][ch] / mean;
    }
  }
  point_sums();
}

// The other photos' consensus at pair k's point (leave-one-out): false when
// no other photo's sample is in it.
bool Refiner::target(uint32_t k, double t[3]) const {
  const uint32_t i = pair_point_[k];
  const uint32_t c = pair_cam_[k];
  const double own = pair_in_[k] ? 1 : 0;
  const double w = count_[i] - own;
  if (!(w >= 1)) return false;
  for (int ch = 0; ch < 3; ++ch) t[ch] = (sum_[i][ch] - own * gain_[c][ch] * pair_val_[k][ch]) / w;
  return true;
}

// Per photo: sigma = 1.4826 median of its samples' distances to their
// points' consensus (points seen twice or more; at least kMinSigma), the
// Huber threshold and truncation from it; samples past the truncation
// leave the consensus, the others get their Huber weight.
void Refiner::update_sigmas_and_weights() {
  const auto residual = [&](uint32_t k) {
    const uint32_t i = pair_point_[k], c = pair_cam_[k];
    double e2 = 0;
    for (int ch = 0; ch < 3; ++ch) {
      const double r = gain_[c][ch] * pair_val_[k][ch] - sum_[i][ch] / count_[i];
      e2 += r * r;
    }
    return std::sqrt(e2);
  };
  const auto shared = [&](uint32_t k) { return pair_ok_[k] && count_[pair_point_[k]] >= 2; };
  std::vector<double> e;
  for (std::size_t c = 0; c < cams_; ++c) {
    e.clear();
    for (uint32_t k = cam_first_[c]; k < cam_first_[c + 1]; ++k) {
      if (shared(k)) e.push_back(residual(k));
    }
    double sigma = kMinSigma;
    if (!e.empty()) {
      std::nth_element(e.begin(), e.begin() + static_cast<std::ptrdiff_t>(e.size() / 2), e.end());
      sigma = std::max(kMinSigma, 1.4826 * e[e.size() / 2]);
    }
    loss_[c] = {kHuberSigmas * sigma, kTruncationSigmas * sigma};
  }
  for (std::size_t k = 0; k < pair_w_.size(); ++k) {
    pair_w_[k] = pair_ok_[k] ? 1.0f : 0.0f;
    if (shared(static_cast<uint32_t>(k))) {
      pair_w_[k] =
          static_cast<float>(loss_[pair_cam_[k]].weight(residual(static_cast<uint32_t>(k))));
    }
  }
  for (std::size_t k = 0; k < pair_w_.size(); ++k) pair_in_[k] = pair_w_[k] > 0;
}

void Refiner::measure(int level, std::vector<double>& rms, std::vector<std::size_t>& count) {
  // A function of the poses alone (the gains solved from 1, the same
  // rounds): before and after are measured alike.
  for (std::size_t c = 0; c < cams_; ++c) sample_camera(c, level);
  gain_.assign(cams_, {1, 1, 1});
  pair_in_ = pair_ok_;
  solve_consensus(6);
  update_sigmas_and_weights();
  solve_consensus(4);
  rms.assign(cams_, 0);
  count.assign(cams_, 0);
  for (std::size_t c = 0; c < cams_; ++c) {
    double s = 0;
    std::size_t m = 0;
    for (uint32_t k = cam_first_[c]; k < cam_first_[c + 1]; ++k) {
      double t[3];
      if (!pair_ok_[k] || !target(k, t)) continue;
      for (int ch = 0; ch < 3; ++ch) {
        const double r = gain_[c][ch] * pair_val_[k][ch] - t[ch];
        s += r * r;
      }
      ++m;
    }
    rms[c] = m ? std::sqrt(s / (3.0 * static_cast<double>(m))) : 0;
    count[c] = m;
  }
}

double Refiner::joint(const std::vector<CamState>& states, int level, Eigen::MatrixXd* s,
                      Eigen::VectorXd* g) {
  const std::size_t n = points_.size();
  const int total = offsets_[cams_];
  const double scale = std::ldexp(1.0, -level);
  constexpr std::size_t kPointBlock = 4096;
  const std::size_t blocks = block_count(n, kPointBlock);
  std::vector<double> cost(blocks, 0);
  std::vector<Eigen::MatrixXd> part_s(s ? blocks : 0);
  std::vector<Eigen::VectorXd> part_g(s ? blocks : 0);
  parallel_for_blocks(n, kPointBlock, [&](std::size_t block, std::size_t begin, std::size_t end) {
    if (s) {
      part_s[block] = Eigen::MatrixXd::Zero(total, total);
      part_g[block] = Eigen::VectorXd::Zero(total);
    }
    // One point's samples: photo, gained value, weight, Jacobian (3 x its
    // parameters) of the gained value.
    std::vector<uint32_t> cam(cams_);
    std::vector<Eigen::Vector3d> val(cams_);
    std::vector<double> w(cams_);
    std::vector<Eigen::Matrix<double, 3, kMaxParams>> jac(cams_);
    Eigen::Matrix<double, 2, kMaxParams> dpix;
    Projected pr;
    double block_cost = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const uint32_t j0 = point_first_[i], j1 = point_first_[i + 1];
      if (j1 - j0 < 2) continue;
      const Vec3 x = points_[i];
      std::size_t m = 0;
      for (uint32_t j = j0; j < j1; ++j) {
        const uint32_t k = point_pairs_[j];
        if (!(pair_w_[k] > 0)) continue;
        const uint32_t c = pair_cam_[k];
        const CamState& st = states[c];
        const Lens& lens = lens_[c];
        const Pyramid& py = pyr_[c];
        const Level& l = py.levels[static_cast<std::size_t>(level)];
        double v[3], gx[3], gy[3];
        if (!(project(st, lens, {x.x, x.y, x.z}, pr) &&
              sample_level(l, pr.px * py.sx * scale - 0.5, pr.py * py.sy * scale - 0.5, v,
                           s ? gx : nullptr, s ? gy : nullptr))) {
          block_cost += loss_[c].rho(loss_[c].cap);  // left the photo: as an outlier
          continue;
        }
        cam[m] = c;
        w[m] = pair_w_[k];
        for (int ch = 0; ch < 3; ++ch) val[m][ch] = gain_[c][ch] * v[ch];
        if (s) {
          // d pixel / d parameters: the pose (omega, v) with X_cam' = exp(omega)
          // X_cam + v, then the intrinsics; then the gained image gradient.
          const int np = offsets_[c + 1] - offsets_[c];
          const double z = pr.xc.z();
          Eigen::Matrix<double, 2, 3> a;
          a << 1 / z, 0, -pr.a / z, 0, 1 / z, -pr.b / z;
          const Eigen::Matrix<double, 2, 3> ma = Eigen::Vector2d(st.fx, st.fy).asDiagonal() *
                                                 distortion_jacobian(lens, pr.a, pr.b) * a;
          Eigen::Matrix3d skew;  // -[X_cam]x
          skew << 0, pr.xc.z(), -pr.xc.y(), -pr.xc.z(), 0, pr.xc.x(), pr.xc.y(), -pr.xc.x(), 0;
          dpix.leftCols<3>() = ma * skew;
          dpix.middleCols<3>(3) = ma;
          if (np > 6) {
            int col = 6;
            if (lens.focal_params == 1) {
              dpix.col(col++) << pr.da, pr.db;
            } else {
              dpix.col(col++) << pr.da, 0;
              dpix.col(col++) << 0, pr.db;
            }
            dpix.col(col++) << 1, 0;
            dpix.col(col++) << 0, 1;
          }
          const double sx = py.sx * scale, sy = py.sy * scale;
          for (int ch = 0; ch < 3; ++ch) {
            jac[m].row(ch).head(np) = gain_[c][ch] * (gx[ch] * sx * dpix.row(0).head(np) +
                                                      gy[ch] * sy * dpix.row(1).head(np));
          }
        }
        ++m;
      }
      if (m < 2) continue;
      double total_w = 0;
      Eigen::Vector3d mean = Eigen::Vector3d::Zero();
      for (std::size_t a = 0; a < m; ++a) total_w += w[a], mean += w[a] * val[a];
      mean /= total_w;
      for (std::size_t a = 0; a < m; ++a) block_cost += loss_[cam[a]].rho((val[a] - mean).norm());
      if (!s) continue;
      // The consensus eliminated: each sample's residual is its distance to
      // the weighted mean, whose own change is the weighted mean of the
      // samples' changes (the Schur complement of the colour block).
      Eigen::MatrixXd& ps = part_s[block];
      Eigen::VectorXd& pg = part_g[block];
      for (std::size_t a = 0; a < m; ++a) {
        const int oa = offsets_[cam[a]], na = offsets_[cam[a] + 1] - oa;
        const auto ja = jac[a].leftCols(na);
        pg.segment(oa, na).noalias() += w[a] * ja.transpose() * (val[a] - mean);
        ps.block(oa, oa, na, na).noalias() += w[a] * ja.transpose() * ja;
        for (std::size_t b = 0; b < m; ++b) {
          const int ob = offsets_[cam[b]], nb = offsets_[cam[b] + 1] - ob;
          ps.block(oa, ob, na, nb).noalias() -=
              (w[a] * w[b] / total_w) * ja.transpose() * jac[b].leftCols(nb);
        }
      }
    }
    cost[block] = block_cost;
  });
  double sum = 0;
  for (double c : cost) sum += c;
  if (s) {
    *s = Eigen::MatrixXd::Zero(total, total);
    *g = Eigen::VectorXd::Zero(total);
    for (std::size_t b = 0; b < blocks; ++b) *s += part_s[b], *g += part_g[b];
  }
  return sum;
}

// Clamps s onto the bounds around the input pose; true when it had to.
bool Refiner::clamp_to_bounds(std::size_t c, CamState& s) const {
  const CamState& s0 = initial_[c];
  bool clamped = false;
  const double max_angle = options_.max_rotation_deg * std::numbers::pi / 180;
  Eigen::Vector3d centre = s.centre();
  const Eigen::AngleAxisd change(Eigen::Matrix3d(s.r * s0.r.transpose()));
  if (change.angle() > max_angle) {
    s.r = Eigen::AngleAxisd(max_angle, change.axis()).toRotationMatrix() * s0.r;
    clamped = true;
  }
  const Eigen::Vector3d c0 = s0.centre();
  const double moved = (centre - c0).norm(), max_move = options_.max_translation * size_;
  if (moved > max_move) {
    centre = c0 + (centre - c0) * (max_move / moved);
    clamped = true;
  }
  if (clamped) s.t = -s.r * centre;
  return clamped;
}

bool Refiner::joint_step(int level, double& lambda) {
  Eigen::MatrixXd s;
  Eigen::VectorXd g;
  const double cost0 = joint(state_, level, &s, &g);
  const int total = offsets_[cams_];
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    Eigen::MatrixXd damped = s;
    for (int i = 0; i < total; ++i) damped(i, i) += lambda * s(i, i) + 1e-12;
    const Eigen::VectorXd delta = damped.ldlt().solve(-g);
    std::vector<CamState> trial = state_;
    std::vector<uint8_t> clamped(cams_, 0);
    bool valid = delta.allFinite();
    for (std::size_t c = 0; c < cams_ && valid; ++c) {
      const int o = offsets_[c];
      CamState& st = trial[c];
      const Eigen::Vector3d omega = delta.segment<3>(o);
      const Eigen::Matrix3d rexp =
          omega.norm() > 0 ? Eigen::AngleAxisd(omega.norm(), omega.normalized()).toRotationMatrix()
                           : Eigen::Matrix3d::Identity();
      st.r = rexp * st.r;
      st.t = rexp * st.t + delta.segment<3>(o + 3);
      if (offsets_[c + 1] - o > 6) {
        int i = o + 6;
        if (lens_[c].focal_params == 1) {
          st.fx += delta[i++];
          st.fy = st.fx;
        } else {
          st.fx += delta[i++];
          st.fy += delta[i++];
        }
        st.cx += delta[i++];
        st.cy += delta[i++];
        const Lens& lens = lens_[c];
        valid = st.fx > 0 && st.fy > 0 && st.cx >= 0 && st.cx <= lens.width && st.cy >= 0 &&
                st.cy <= lens.height;
      }
      clamped[c] = clamp_to_bounds(c, st);
    }
    if (!valid) {
      lambda *= 5;
      continue;
    }
    const double cost = joint(trial, level, nullptr, nullptr);
    if (!(cost < cost0)) {
      lambda *= 5;
      continue;
    }
    // Accepted. Converged when no photo moved by more than about a
    // thousandth of a texel of this level (2^level photo pixels).
    const double tolerance = std::ldexp(1e-3, level);
    double largest = 0;
    for (std::size_t c = 0; c < cams_; ++c) {
      const double turned = rotation_angle(trial[c].r * state_[c].r.transpose());
      const double moved = (trial[c].centre() - state_[c].centre()).norm() / size_;
      const double f = (trial[c].fx + trial[c].fy) / 2;
      const double pixels = f * std::max(turned, moved);
      largest = std::max(largest, pixels);
      if (pixels > tolerance) ++iterations_[c];
      clamped_[c] |= clamped[c];
    }
    state_ = std::move(trial);
    lambda = std::max(lambda / 3, 1e-7);
    return largest > tolerance;
  }
  return false;
}

bool Refiner::refine_level(int level, int iterations, Progress* progress) {
  double lambda = 1e-4;
  for (int it = 0; it < iterations; ++it) {
    if (is_cancelled(progress)) return false;
    for (std::size_t c = 0; c < cams_; ++c) sample_camera(c, level);
    pair_in_ = pair_ok_;
    solve_consensus(2);
    update_sigmas_and_weights();
    solve_consensus(1);
    const bool moved = joint_step(level, lambda);
    if (progress) progress->advance(1);
    if (!moved) {
      if (progress) progress->advance(static_cast<std::size_t>(iterations - it - 1));
      break;
    }
  }
  return true;
}

// The sample points: referenced vertices with a normal, evenly
// subsampled (every (n / max)-th) to at most max_points.
void sample_points(const MeshData& mesh, std::size_t max_points, std::vector<Vec3>& points,
                   std::vector<Vec3>& normals) {
  const std::vector<Float3> vn = smooth_vertex_normals(mesh);
  std::vector<uint32_t> usable;
  for (std::size_t v = 0; v < vn.size(); ++v) {
    const Vec3 n{vn[v].x, vn[v].y, vn[v].z};
    if (length(n) > 0) usable.push_back(static_cast<uint32_t>(v));
  }
  const std::size_t m = std::min(usable.size(), max_points);
  for (std::size_t k = 0; k < m; ++k) {
    const uint32_t v = usable[k * usable.size() / m];
    const Float3 p = mesh.positions[v];
    points.push_back({p.x, p.y, p.z});
    normals.push_back(normalize(Vec3{vn[v].x, vn[v].y, vn[v].z}));
  }
}

Expected<CameraProjector> camera_of(const CameraProjector& input, const CamState& s,
                                    const Lens& lens) {
  CameraSpec spec = input.spec();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) spec.pose.r[3 * i + j] = s.r(i, j);
  }
  spec.pose.t = {s.t.x(), s.t.y(), s.t.z()};
  if (lens.focal_params == 1) {
    spec.params[0] = s.fx, spec.params[1] = s.cx, spec.params[2] = s.cy;
  } else {
    spec.params[0] = s.fx, spec.params[1] = s.fy, spec.params[2] = s.cx, spec.params[3] = s.cy;
  }
  return CameraProjector::make(std::move(spec));
}

}  // namespace

Expected<PoseRefineResult> refine_poses(const MeshData& mesh, const std::vector<Photo>& photos,
                                        const PoseRefineOptions& options, const PhotoReader& reader,
                                        Progress* progress) {
  if (!(options.max_rotation_deg > 0 && options.max_rotation_deg <= 180)) {
    return make_error(ErrorCode::kInvalidArgument, "--max-rotation must be in (0, 180] degrees");
  }
  if (!(options.max_translation > 0 && std::isfinite(options.max_translation))) {
    return make_error(ErrorCode::kInvalidArgument,
                      "--max-translation must be a positive fraction of the mesh's size");
  }
  if (options.iterations < 1 || options.iterations > 1000) {
    return make_error(ErrorCode::kInvalidArgument, "--iterations must be in 1 .. 1000");
  }
  if (options.max_points < 16) {
    return make_error(ErrorCode::kInvalidArgument, "max_points must be at least 16");
  }
  if (photos.size() < 2) {
    return make_error(ErrorCode::kInvalidArgument,
                      "cameras refine needs two photos or more: " +
                          std::string(photos.empty() ? "no photo" : "one photo") +
                          " has nothing to agree with");
  }
  const PhotoReader read = reader ? reader : PhotoReader(photo_detail::read_photo_file);
  PoseRefineResult result;
  auto start = Clock::now();
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kMedium);
  if (!scene) return scene.error();
  const double offset = visibility_offset(*scene);
  result.mesh_size = scene->diagonal();
  std::vector<Vec3> points, normals;
  sample_points(mesh, options.max_points, points, normals);
  result.points = points.size();
  result.seconds_scene = seconds_since(start);

  // Every photo, read once and kept as a pyramid (its levels in 16 bits).
  start = Clock::now();
  std::vector<std::size_t> used;  // indices into photos
  std::vector<Pyramid> pyramids;
  std::vector<Lens> lenses;
  std::vector<CamState> states;
  int levels = kMaxLevels;
  std::vector<PhotoImage> images;
  std::vector<bool> masked;  // the photo has a mask (alpha below 1 somewhere)
  for (std::size_t p = 0; p < photos.size(); ++p) {
    const Photo& photo = photos[p];
    PhotoCameraStats stats;
    bool unreadable = false;
    Expected<PhotoImage> image =
        photo_detail::load_photo(photo, read, stats, result.warnings, unreadable);
    if (!image && unreadable && !options.strict_photos) {
      photo_detail::skip_photo(photo, image.error(), result.skipped, result.warnings);
      continue;
    }
    if (!image) {
      return unreadable ? photo_detail::unreadable_photo_error(photo, image.error())
                        : image.error();
    }
    levels = std::min(levels, level_count(image->width, image->height));
    used.push_back(p);
    masked.push_back(stats.masked);
    images.push_back(std::move(*image));
  }
  if (used.empty()) return photo_detail::no_usable_photo_error(result.skipped);
  if (used.size() < 2) {
    return make_error(ErrorCode::kParse, "only the photo of " + photos[used[0]].name +
                                             " can be read: one photo has nothing to agree with");
  }
  for (std::size_t u = 0; u < used.size(); ++u) {
    const CameraProjector& camera = photos[used[u]].camera;
    const double sx = static_cast<double>(images[u].width) / camera.spec().width;
    const double sy = static_cast<double>(images[u].height) / camera.spec().height;
    pyramids.push_back(make_pyramid(images[u], masked[u], sx, sy, levels));
    images[u] = {};
    lenses.push_back(lens_of(camera));
    states.push_back(state_of(camera, lenses.back()));
  }
  images = {};
  result.levels = levels;
  result.seconds_photos = seconds_since(start);

  start = Clock::now();
  Refiner refiner(*scene, offset, result.mesh_size, std::move(points), std::move(normals),
                  std::move(pyramids), lenses, states, options);
  const std::size_t cams = used.size();
  if (progress) progress->start("refine", static_cast<std::size_t>(levels * options.iterations));
  std::vector<double> rms_before, rms_after;
  std::vector<std::size_t> n_before, n_after;
  if (refiner.build_pairs(0) == 0) {
    return make_error(ErrorCode::kParse,
                      "no point of the mesh is seen by two photos: the photos have nothing to "
                      "agree on (are the cameras in the mesh's frame? see texbake cameras check)");
  }
  refiner.measure(0, rms_before, n_before);
  if (std::accumulate(n_before.begin(), n_before.end(), std::size_t{0}) == 0) {
    // Seen by two photos, but masked out (a mask, or alpha 0) in all but one.
    return make_error(ErrorCode::kParse,
                      "no point of the mesh is seen by two photos where their masks keep the "
                      "pixels: the photos have nothing to agree on");
  }
  for (int level = levels - 1; level >= 0; --level) {
    refiner.build_pairs(level);
    if (!refiner.refine_level(level, options.iterations, progress)) return cancelled_error();
  }
  refiner.build_pairs(0);
  refiner.measure(0, rms_after, n_after);
  // Never worse than the start: when the RMS over every photo's samples at
  // the finest level did not fall, the photometric optimum the steps found
  // is not a better pose (photos too small, aliased or bare for their
  // texture to pin it) and the input poses are kept.
  const auto overall = [&](const std::vector<double>& rms, const std::vector<std::size_t>& n) {
    double sum = 0, count = 0;
    for (std::size_t u = 0; u < cams; ++u) {
      sum += rms[u] * rms[u] * static_cast<double>(n[u]);
      count += static_cast<double>(n[u]);
    }
    return count > 0 ? std::sqrt(sum / count) : 0.0;
  };
  const double overall_before = overall(rms_before, n_before);
  const double overall_after = overall(rms_after, n_after);
  if (refiner.moved() && !(overall_after < overall_before)) {
    refiner.reset();
    refiner.build_pairs(0);
    refiner.measure(0, rms_after, n_after);
    char figures[96];
    std::snprintf(figures, sizeof figures, "%.4g -> %.4g", overall_before, overall_after);
    result.warnings.push_back(
        std::string("the refinement did not make the photos agree better (RMS over every "
                    "photo's samples ") +
        figures +
        "): the input poses are kept (photos too small, blurred or aliased, or too little "
        "texture, to pin the poses)");
  }
  if (is_cancelled(progress)) return cancelled_error();
  if (progress) progress->finish();

  // The results, in the input's order.
  result.photos.resize(photos.size());
  for (std::size_t p = 0; p < photos.size(); ++p) {
    result.photos[p].name = photos[p].name;
    result.photos[p].camera = photos[p].camera;
    result.photos[p].skipped = true;
  }
  for (std::size_t u = 0; u < cams; ++u) {
    RefinedPose& out = result.photos[used[u]];
    const CamState& s = refiner.state(u);
    Expected<CameraProjector> camera = camera_of(photos[used[u]].camera, s, lenses[u]);
    if (!camera) {
      return make_error(ErrorCode::kInternal, "the refined camera of " + out.name +
                                                  " is invalid: " + camera.error().message);
    }
    out.camera = std::move(*camera);
    out.skipped = false;
    out.rotation_change_deg =
        rotation_angle(s.r * states[u].r.transpose()) * 180 / std::numbers::pi;
    out.translation_change = (s.centre() - states[u].centre()).norm() / result.mesh_size;
    const double f0 = (states[u].fx + states[u].fy) / 2, f1 = (s.fx + s.fy) / 2;
    out.focal_change = f1 / f0 - 1;
    out.residual_before = rms_before[u];
    out.residual_after = rms_after[u];
    out.samples_before = n_before[u];
    out.samples_after = n_after[u];
    out.iterations = refiner.iterations(u);
    out.clamped = refiner.clamped(u);
    out.gain = refiner.gain(u);
    if (n_before[u] == 0 && n_after[u] == 0) {
      result.warnings.push_back(out.name +
                                ": sees no point another photo sees; its pose is unchanged");
    }
    if (out.clamped) {
      result.warnings.push_back(out.name + ": the refinement reached the bound (--max-rotation " +
                                "or --max-translation); its change was clamped");
    }
  }
  result.seconds_refine = seconds_since(start);
  return result;
}

}  // namespace texbake
