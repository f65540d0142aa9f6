#include "bake/photo/photo_bake.h"

#include <Eigen/Dense>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>

#include "bake/photo/photo_view.h"
#include "bake/photo/segments.h"
#include "bake/trace/embree_scene.h"
#include "bake/trace/visibility.h"
#include "bake/util/parallel.h"
#include "bake/util/timing.h"
#include "mapping/image_view.h"
#include "mesh_io/vertex_normals.h"

namespace texbake {

namespace {

constexpr std::size_t kGrain = 4096;  // vertices per parallel chunk

using photo_detail::blend_weight;
using photo_detail::CameraLook;

// One camera's view of one vertex.
struct Sample {
  uint32_t camera = 0;
  float quality = 0;
  std::array<float, 3> rgb{};  // linear light, before the gain
  float mask = 1;              // the photo's mask value there, in (0, 1]
};

// Exposure gains of one channel, solved in the log domain so that they are
// exactly scale-invariant: with l = log g and y = log x, minimise over the
// vertices and the pairs (a, b) of photos seeing it
//   sum (l_a + y_a - l_b - y_b)^2 + lambda sum l_k^2,  subject to sum l_k = 0
// (the gains' geometric mean is 1; without it the data term leaves a
// common factor free). A photo scaled by s then gets exactly 1 / s times
// its gain (up to the common factor), whatever its overlap with the others;
// the linear form (g_a x_a - g_b x_b)^2 weighed pairs by their brightness
// and biased weakly connected photos. Pairs where either value is below
// kMinGainSample (near black: 8-bit noise dominates the ratio) are left out.
// lambda is weak (1e-4 of the mean diagonal): it only decides photos that
// share no vertex with another. Solved through the KKT system, of the size
// of the photo count. A pair weighs the product of its two mask values (1
// for photos without masks). Only the photos that see some vertex take
// part (`index`: a camera's unknown, -1 for the others, which keep gain 1):
// a photo masked out wholly changes no other photo's gain.
constexpr double kMinGainSample = 0.003;  // linear light (about 8-bit level 15 of sRGB)

Expected<std::vector<double>> solve_gains(const std::vector<uint32_t>& start,
                                          const std::vector<Sample>& samples,
                                          const std::vector<int>& index, int channel) {
  const auto k = static_cast<Eigen::Index>(
      std::count_if(index.begin(), index.end(), [](int i) { return i >= 0; }));
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(k + 1, k + 1);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(k + 1);
  for (std::size_t v = 0; v + 1 < start.size(); ++v) {
    for (uint32_t i = start[v]; i < start[v + 1]; ++i) {
      const double xa = samples[i].rgb[channel];
      if (!(xa >= kMinGainSample)) continue;
      for (uint32_t j = i + 1; j < start[v + 1]; ++j) {
        const double xb = samples[j].rgb[channel];
        if (!(xb >= kMinGainSample)) continue;
        const double d = std::log(xa) - std::log(xb);
        const double w = static_cast<double>(samples[i].mask) * samples[j].mask;
        const Eigen::Index a = index[samples[i].camera], b = index[samples[j].camera];
        m(a, a) += w, m(b, b) += w;
        m(a, b) -= w, m(b, a) -= w;
        rhs[a] -= w * d, rhs[b] += w * d;
      }
    }
  }
  const double lambda =
      1e-4 * std::max(m.topLeftCorner(k, k).trace() / static_cast<double>(k), 1.0);
  for (Eigen::Index a = 0; a < k; ++a) {
    m(a, a) += lambda;
    m(a, k) = m(k, a) = 1;
  }
  rhs[k] = 0;
  const Eigen::VectorXd l = m.fullPivLu().solve(rhs);
  std::vector<double> gains(index.size(), 1.0);
  for (std::size_t c = 0; c < index.size(); ++c) {
    if (index[c] < 0) continue;
    const double g = std::exp(l[index[c]]);
    if (!(std::isfinite(g) && g > 0)) {
      return make_error(ErrorCode::kInternal, "exposure gains: the least-squares solve failed");
    }
    gains[c] = g;
  }
  return gains;
}

// PhotoConsistency (photo_bake.h) over the per-vertex sample lists.
// Per-block sums, added in block order: the figures do not depend on the
// thread count.
PhotoConsistency measure_consistency(const std::vector<uint32_t>& first,
                                     const std::vector<Sample>& samples,
                                     const std::vector<std::array<double, 3>>& gains,
                                     std::vector<PhotoCameraStats>& stats) {
  constexpr double kLuma[3] = {0.2126, 0.7152, 0.0722};
  constexpr double kDarkFloor = 0.05;  // linear luminance: below it deviations are absolute
  const std::size_t n = first.size() - 1, cameras = gains.size();
  const std::size_t blocks = block_count(n, kGrain);
  std::vector<float> deviation(n, -1.f);  // -1: seen by fewer than two photos
  std::vector<double> camera_sum(blocks * cameras, 0.0);
  std::vector<std::size_t> camera_count(blocks * cameras, 0);
  parallel_for_blocks(n, kGrain, [&](std::size_t block, std::size_t begin, std::size_t end) {
    std::vector<double> y, sorted;
    for (std::size_t v = begin; v < end; ++v) {
      const uint32_t s0 = first[v], s1 = first[v + 1];
      if (s1 - s0 < 2) continue;
      y.clear();
      for (uint32_t i = s0; i < s1; ++i) {
        const Sample& s = samples[i];
        double luma = 0;
        for (int ch = 0; ch < 3; ++ch) luma += kLuma[ch] * gains[s.camera][ch] * s.rgb[ch];
        y.push_back(luma);
      }
      sorted = y;
      std::sort(sorted.begin(), sorted.end());
      const std::size_t k = sorted.size();
      const double median = k % 2 ? sorted[k / 2] : (sorted[k / 2 - 1] + sorted[k / 2]) / 2;
      const double scale = std::max(median, kDarkFloor);
      double sum = 0;
      for (uint32_t i = s0; i < s1; ++i) {
        const double d = std::abs(y[i - s0] - median) / scale;
        sum += d;
        camera_sum[block * cameras + samples[i].camera] += d;
        ++camera_count[block * cameras + samples[i].camera];
      }
      deviation[v] = static_cast<float>(sum / static_cast<double>(k));
    }
  });
  PhotoConsistency c;
  for (std::size_t cam = 0; cam < cameras; ++cam) {
    double sum = 0;
    std::size_t count = 0;
    for (std::size_t b = 0; b < blocks; ++b) {
      sum += camera_sum[b * cameras + cam];
      count += camera_count[b * cameras + cam];
    }
    stats[cam].shared = count;
    stats[cam].deviation = count ? sum / static_cast<double>(count) : 0;
  }
  std::vector<float> multi;
  for (float d : deviation) {
    if (d >= 0) multi.push_back(d);
  }
  c.vertices = multi.size();
  if (!multi.empty()) {
    const auto agree =
        std::count_if(multi.begin(), multi.end(), [](float d) { return d <= kAgreeDeviation; });
    c.agreeing = static_cast<double>(agree) / static_cast<double>(multi.size());
    const auto mid = multi.begin() + static_cast<std::ptrdiff_t>(multi.size() / 2);
    std::nth_element(multi.begin(), mid, multi.end());
    c.median_deviation = *mid;
  }
  double lo = INFINITY, hi = 0;
  for (const auto& g : gains) {
    for (double x : g) lo = std::min(lo, x), hi = std::max(hi, x);
  }
  c.gain_ratio = lo > 0 && std::isfinite(lo) ? hi / lo : 1;
  return c;
}

using SeenBy = std::vector<std::vector<std::pair<uint32_t, Sample>>>;

// Per photo, read one at a time (one that cannot be read is left out, unless
// strict_photos): the cull, the segments to the camera, and for each vertex
// it sees its quality, linear colour and mask value, into seen_by[c] in
// vertex order (c: the photo's place among those used, `used`); the
// cameras' stats in result.cameras, the vertices' states in result.points.
Status sample_photos(const MeshData& mesh, const std::vector<Float3>& normals,
                     const EmbreeScene& scene, const std::vector<Photo>& photos,
                     const PhotoReader& read, const PhotoBakeOptions& options, SeenBy& seen_by,
                     std::vector<const Photo*>& used, PhotoBakeResult& result) {
  const std::size_t n = mesh.positions.size();
  const double offset = visibility_offset(scene);
  std::vector<float> quality(n);
  std::vector<std::array<float, 3>> rgb(n);
  std::vector<float> mask_value;  // n, once a photo has a mask
  PhotoPoints& points = result.points;
  for (std::size_t p = 0; p < photos.size(); ++p) {
    const Photo& photo = photos[p];
    const CameraProjector& camera = photo.camera;
    PhotoCameraStats loaded;
    loaded.name = photo.name;
    bool unreadable = false;
    Expected<PhotoImage> image =
        photo_detail::load_photo(photo, read, loaded, result.warnings, unreadable);
    if (!image && unreadable && !options.strict_photos) {
      photo_detail::skip_photo(photo, image.error(), result.skipped, result.warnings);
      continue;
    }
    if (!image) {
      return unreadable ? photo_detail::unreadable_photo_error(photo, image.error())
                        : image.error();
    }
    const std::size_t c = used.size();
    used.push_back(&photo);
    result.cameras.push_back(std::move(loaded));
    PhotoCameraStats& stats = result.cameras.back();
    if (options.on_photo) options.on_photo(c, *image, stats.masked);
    const ImageView view{image->width, image->height, image->pixels.data()};
    const bool masked = stats.masked;
    if (masked && mask_value.empty()) mask_value.assign(n, 1.f);
    const CameraLook look(camera, options.max_view_angle_deg);
    const Vec3 centre = look.centre();
    std::vector<std::size_t> in_view_chunk(block_count(n, kGrain), 0),
        visible_chunk(in_view_chunk.size(), 0);
    parallel_for_blocks(n, kGrain, [&](std::size_t block, std::size_t begin, std::size_t end) {
      // Cull first, then trace only the candidates' segments.
      std::vector<uint32_t> candidates;
      std::vector<CameraProjection> projections;
      SegmentScratch scratch;
      std::vector<uint8_t> occluded;
      for (std::size_t v = begin; v < end; ++v) {
        quality[v] = 0;
        const Vec3 p{mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z};
        const Vec3 nrm{normals[v].x, normals[v].y, normals[v].z};
        CameraProjection proj;
        if (!look.candidate(p, nrm, proj)) continue;
        // Masked out: as if outside the photo (no segment traced).
        if (masked && !(photo_detail::mask_at(view, true, proj.uv) > 0)) continue;
        points.state[v] = PhotoPoints::kInView;
        candidates.push_back(static_cast<uint32_t>(v));
        projections.push_back(proj);
      }
      const std::size_t m = candidates.size();
      occluded.assign(m, 0);
      occluded_segments(scene, offset, mesh, candidates, centre, scratch, occluded.data());
      std::size_t visible = 0;
      for (std::size_t i = 0; i < m; ++i) {
        if (occluded[i]) continue;
        ++visible;
        const uint32_t v = candidates[i];
        const CameraProjection& proj = projections[i];
        const Vec3 nrm{normals[v].x, normals[v].y, normals[v].z};
        const Vec3 p{mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z};
        const float q = look.quality(p, nrm, proj);
        const Rgba s = photo_detail::sample_masked(view, masked, proj.uv);
        quality[v] = q;
        rgb[v] = {s[0], s[1], s[2]};
        if (masked) mask_value[v] = s[3];
      }
      in_view_chunk[block] = m;
      visible_chunk[block] = visible;
    });
    for (std::size_t k = 0; k < in_view_chunk.size(); ++k) {
      stats.in_view += in_view_chunk[k];
      stats.visible += visible_chunk[k];
    }
    auto& list = seen_by[c];
    list.reserve(stats.visible);
    for (std::size_t v = 0; v < n; ++v) {
      if (quality[v] > 0)
        list.push_back({static_cast<uint32_t>(v), Sample{static_cast<uint32_t>(c), quality[v],
                                                         rgb[v], masked ? mask_value[v] : 1.f}});
    }
  }
  return ok_status();
}

// The per-vertex lists of samples, cameras in order (a counting sort):
// vertex v's samples are samples[first[v] .. first[v + 1]). Frees seen_by.
void gather_samples(SeenBy& seen_by, std::size_t n, std::vector<uint32_t>& first,
                    std::vector<Sample>& samples) {
  first.assign(n + 1, 0);
  for (const auto& list : seen_by) {
    for (const auto& [v, s] : list) ++first[v + 1];
  }
  for (std::size_t v = 0; v < n; ++v) first[v + 1] += first[v];
  samples.resize(first[n]);
  {
    std::vector<uint32_t> next(first.begin(), first.end() - 1);
    for (auto& list : seen_by) {
      for (const auto& [v, s] : list) samples[next[v]++] = s;
      list = {};
    }
  }
}

// The exposure gains (over the photos that see some vertex), into
// result.cameras and `gains`, and the photos' consistency (with its
// warning).
Status solve_exposure(const std::vector<uint32_t>& first, const std::vector<Sample>& samples,
                      const PhotoBakeOptions& options, std::vector<std::array<double, 3>>& gains,
                      PhotoBakeResult& result) {
  const std::size_t cameras = result.cameras.size();
  gains.assign(cameras, {1, 1, 1});
  std::vector<int> index(cameras, -1);
  int active = 0;
  for (std::size_t c = 0; c < cameras; ++c) {
    if (result.cameras[c].visible > 0) index[c] = active++;
  }
  if (options.exposure == ExposureMode::kGain && active > 1) {
    for (int ch = 0; ch < 3; ++ch) {
      Expected<std::vector<double>> g = solve_gains(first, samples, index, ch);
      if (!g) return g.error();
      for (std::size_t c = 0; c < cameras; ++c) gains[c][ch] = (*g)[c];
    }
  }
  for (std::size_t c = 0; c < cameras; ++c) result.cameras[c].gain = gains[c];
  result.consistency = measure_consistency(first, samples, gains, result.cameras);
  if (options.consistency_warning) {
    std::string doubt = photo_consistency_warning(result.consistency);
    if (!doubt.empty()) result.warnings.push_back(std::move(doubt));
  }

  return ok_status();
}

// The blend per vertex, in linear light (result.points: states, colours,
// cosines with keep_points), the vertices seen and the cameras' weight
// shares.
void blend_points(const MeshData& mesh, const std::vector<Float3>& normals,
                  const std::vector<uint32_t>& first, const std::vector<Sample>& samples,
                  const std::vector<std::array<double, 3>>& gains,
                  const std::vector<const Photo*>& used, const PhotoBakeOptions& options,
                  PhotoBakeResult& result) {
  const std::size_t n = mesh.positions.size(), cameras = used.size();
  PhotoPoints& points = result.points;
  points.rgb.assign(n, {0.f, 0.f, 0.f});
  points.cosine.assign(n, 1.f);
  std::vector<std::size_t> seen_chunk(block_count(n, kGrain), 0);
  std::vector<std::vector<double>> share_chunk(block_count(n, kGrain),
                                               std::vector<double>(cameras, 0.0));
  parallel_for_blocks(n, kGrain, [&](std::size_t block, std::size_t begin, std::size_t end) {
    std::vector<double>& share = share_chunk[block];
    std::vector<double> weight;
    for (std::size_t v = begin; v < end; ++v) {
      const uint32_t s0 = first[v], s1 = first[v + 1];
      if (s0 == s1) continue;
      ++seen_chunk[block];
      double q_max = 0;
      uint32_t best = s0;
      for (uint32_t i = s0; i < s1; ++i) {
        if (samples[i].quality > q_max) q_max = samples[i].quality, best = i;
      }
      weight.assign(s1 - s0, 0.0);
      for (uint32_t i = s0; i < s1; ++i) {
        weight[i - s0] =
            blend_weight(options.blend, samples[i].quality, static_cast<float>(q_max), i == best) *
            samples[i].mask;
      }
      double total = 0;
      std::array<double, 3> sum{0, 0, 0};
      for (uint32_t i = s0; i < s1; ++i) {
        const double wt = weight[i - s0];
        total += wt;
        for (int ch = 0; ch < 3; ++ch)
          sum[ch] += wt * gains[samples[i].camera][ch] * samples[i].rgb[ch];
      }
      for (uint32_t i = s0; i < s1; ++i) share[samples[i].camera] += weight[i - s0] / total;
      points.state[v] = PhotoPoints::kSeen;
      points.rgb[v] = {static_cast<float>(sum[0] / total), static_cast<float>(sum[1] / total),
                       static_cast<float>(sum[2] / total)};
      if (options.keep_points) {
        const Vec3 p{mesh.positions[v].x, mesh.positions[v].y, mesh.positions[v].z};
        const Vec3 nrm{normals[v].x, normals[v].y, normals[v].z};
        double cosine = 0;
        for (uint32_t i = s0; i < s1; ++i) {
          const Vec3 d = normalize(used[samples[i].camera]->camera.centre() - p);
          cosine += weight[i - s0] * dot(nrm, d) / length(nrm);
        }
        points.cosine[v] = static_cast<float>(cosine / total);
      }
    }
  });
  for (std::size_t c : seen_chunk) result.seen += c;
  std::vector<double> share(cameras, 0.0);
  for (const auto& s : share_chunk) {
    for (std::size_t c = 0; c < cameras; ++c) share[c] += s[c];
  }
  for (std::size_t c = 0; c < cameras; ++c) {
    result.cameras[c].weight_share = result.seen ? share[c] / static_cast<double>(result.seen) : 0;
  }
}

}  // namespace

Expected<PhotoBakeResult> blend_vertex_photos(const MeshData& mesh,
                                              const std::vector<Photo>& photos,
                                              const PhotoBakeOptions& options,
                                              const PhotoReader& reader) {
  if (photos.empty()) return make_error(ErrorCode::kInvalidArgument, "no photos to bake from");
  // The next photo decoded while this one is baked.
  const PhotoReader read = photo_detail::prefetching_reader(
      reader ? reader : PhotoReader(photo_detail::read_photo_file), photos);
  const std::size_t n = mesh.positions.size();
  PhotoBakeResult result;

  auto start = Clock::now();
  Expected<EmbreeScene> scene = EmbreeScene::build(mesh, BuildQuality::kLow);
  if (!scene) return scene.error();
  const std::vector<Float3> normals = smooth_vertex_normals(mesh);
  result.seconds_scene = seconds_since(start);

  // Per camera, per vertex: quality (0 = not seen) and the linear colour;
  // gathered afterwards into per-vertex lists in camera order.
  start = Clock::now();
  SeenBy seen_by(photos.size());
  result.points.state.assign(n, PhotoPoints::kNoView);
  // The photos used (readable), in order: samples and stats are numbered
  // by their place here.
  std::vector<const Photo*> used;
  if (Status s = sample_photos(mesh, normals, *scene, photos, read, options, seen_by, used, result);
      !s) {
    return s.error();
  }
  result.seconds_photos = seconds_since(start);
  if (used.empty()) return photo_detail::no_usable_photo_error(result.skipped);
  seen_by.resize(used.size());

  start = Clock::now();
  std::vector<uint32_t> first;
  std::vector<Sample> samples;
  gather_samples(seen_by, n, first, samples);
  std::vector<std::array<double, 3>> gains;
  if (Status s = solve_exposure(first, samples, options, gains, result); !s) return s.error();
  blend_points(mesh, normals, first, samples, gains, used, options, result);
  result.seconds_blend = seconds_since(start);
  return result;
}

std::string consistency_figures(const PhotoConsistency& c) {
  char buf[200];
  std::snprintf(buf, sizeof buf,
                "%.0f %% of %zu vertices seen by several photos agree within %.0f %%, median "
                "deviation %.1f %%, gains within %.2gx",
                100 * c.agreeing, c.vertices, 100 * kAgreeDeviation, 100 * c.median_deviation,
                c.gain_ratio);
  return buf;
}

std::string photo_consistency_warning(const PhotoConsistency& c) {
  const bool disagree = c.vertices >= kConsistencyMinVertices && c.agreeing < kConsistencyDoubtful;
  const bool gains = c.gain_ratio > kGainRatioDoubtful;
  if (!disagree && !gains) return {};
  return std::string("the photos disagree on the mesh (") + consistency_figures(c) +
         "): are the cameras in the mesh's frame and their poses right? (texbake cameras "
         "align, --no-alignment-check: no check)";
}

}  // namespace texbake
