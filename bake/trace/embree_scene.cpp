// Embree 3 behind a move-only RAII type. The set-up follows the lifecycle of
// Embree's tutorials/minimal/minimal.cpp (device with an error callback ->
// scene -> geometry -> buffers -> commit -> attach -> release geometry ->
// commit scene; release in reverse order), without its globals.
#include "bake/trace/embree_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "bake/util/parallel.h"

namespace texbake {

namespace {

// Rays are copied into fixed-size, aligned blocks on the stack: Embree wants
// 16-byte aligned rays and writes tfar, while RayBatch's arrays are the
// caller's const data at any offset. 256 rays (12 KB) stay in L1/L2 and
// amortise the call overhead; 4096 measured no faster.
constexpr std::size_t kBlock = 256;

// Captures the first error reported through rtcSetDeviceErrorFunction, so the
// builder can check once per step instead of after every call.
struct ErrorSink {
  std::mutex mutex;
  RTCError code = RTC_ERROR_NONE;
  std::string message;
};

void on_embree_error(void* user, RTCError code, const char* str) {
  auto* sink = static_cast<ErrorSink*>(user);
  std::lock_guard<std::mutex> lock(sink->mutex);
  if (sink->code == RTC_ERROR_NONE) {
    sink->code = code;
    sink->message = str ? str : "unknown Embree error";
  }
}

const char* error_name(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_UNKNOWN:
      return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
  }
  return "unknown error";
}

}  // namespace

struct EmbreeScene::Impl {
  ErrorSink errors;  // must outlive the device: its address is the callback's user pointer
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  // Shared with Embree (rtcSetSharedGeometryBuffer): x, y, z per vertex plus one
  // trailing float, because Embree may read the last vertex with a 16-byte load
  // (Embree docs, buffer padding; RenderKit/embree#124).
  // Both are written whole by the parallel copies in build(), so they are
  // allocated without the zero-fill a std::vector would do on one thread
  // (the pages' first touch, dear on a virtual machine, is then spread over
  // the threads).
  std::unique_ptr<float[]> vertices;
  std::unique_ptr<uint32_t[]> indices;  // kept to compute geometric normals of hits
  double diagonal = 0;
  double max_abs_coordinate = 0;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  Status check(const char* step) {
    std::lock_guard<std::mutex> lock(errors.mutex);
    if (errors.code == RTC_ERROR_NONE) return ok_status();
    return make_error(ErrorCode::kInternal,
                      std::string("Embree failed while ") + step + ": " + errors.message);
  }
};

namespace {

// Fills the fields every ray needs (Embree docs, rtcOccluded1/rtcIntersect1):
// tnear/tfar, time, mask = all ones (Debian's Embree is built with ray masks:
// any other mask silently hits nothing), flags = 0.
struct AlignedRayBlock {
  alignas(64) float org_x[kBlock];
  alignas(64) float org_y[kBlock];
  alignas(64) float org_z[kBlock];
  alignas(64) float tnear[kBlock];
  alignas(64) float dir_x[kBlock];
  alignas(64) float dir_y[kBlock];
  alignas(64) float dir_z[kBlock];
  alignas(64) float time[kBlock];
  alignas(64) float tfar[kBlock];
  alignas(64) unsigned mask[kBlock];
  alignas(64) unsigned id[kBlock];
  alignas(64) unsigned flags[kBlock];

  void load(const RayBatch& rays, std::size_t begin, std::size_t n) {
    std::memcpy(org_x, rays.org_x + begin, n * sizeof(float));
    std::memcpy(org_y, rays.org_y + begin, n * sizeof(float));
    std::memcpy(org_z, rays.org_z + begin, n * sizeof(float));
    std::memcpy(dir_x, rays.dir_x + begin, n * sizeof(float));
    std::memcpy(dir_y, rays.dir_y + begin, n * sizeof(float));
    std::memcpy(dir_z, rays.dir_z + begin, n * sizeof(float));
    if (rays.tnear) {
      std::memcpy(tnear, rays.tnear + begin, n * sizeof(float));
    } else {
      std::fill_n(tnear, n, 0.0f);
    }
    if (rays.tfar) {
      std::memcpy(tfar, rays.tfar + begin, n * sizeof(float));
    } else {
      std::fill_n(tfar, n, std::numeric_limits<float>::infinity());
    }
    std::fill_n(time, n, 0.0f);
    std::fill_n(mask, n, 0xFFFFFFFFu);
    for (std::size_t i = 0; i < n; ++i) id[i] = static_cast<unsigned>(i);
    std::fill_n(flags, n, 0u);
  }

  RTCRayNp np() {
    return RTCRayNp{org_x, org_y, org_z, tnear, dir_x, dir_y, dir_z, time, tfar, mask, id, flags};
  }
};

struct AlignedHitBlock {
  alignas(64) float ng_x[kBlock];
  alignas(64) float ng_y[kBlock];
  alignas(64) float ng_z[kBlock];
  alignas(64) float u[kBlock];
  alignas(64) float v[kBlock];
  alignas(64) unsigned prim_id[kBlock];
  alignas(64) unsigned geom_id[kBlock];
  alignas(64) unsigned inst_id[kBlock];

  RTCHitNp np(std::size_t n) {
    std::fill_n(geom_id, n, RTC_INVALID_GEOMETRY_ID);
    std::fill_n(inst_id, n, RTC_INVALID_GEOMETRY_ID);
    return RTCHitNp{ng_x, ng_y, ng_z, u, v, prim_id, geom_id, {inst_id}};
  }
};

RTCIntersectContext make_context() {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // Our batches are rays from neighbouring surface points (vertex order,
  // texel order) towards one projector, but their directions spread (sphere,
  // cylinder, renders). Measured with bench/bake_bench.cpp (visibility rays
  // of the bunny and the 832k armadillo, one thread): the coherent mode was
  // 1.25-1.6x slower.
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

}  // namespace

EmbreeScene::EmbreeScene(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
EmbreeScene::EmbreeScene(EmbreeScene&&) noexcept = default;
EmbreeScene& EmbreeScene::operator=(EmbreeScene&&) noexcept = default;
EmbreeScene::~EmbreeScene() = default;

Expected<EmbreeScene> EmbreeScene::build(const MeshData& mesh, BuildQuality quality) {
  auto impl = std::make_unique<Impl>();

  impl->device = rtcNewDevice(nullptr);
  if (!impl->device) {
    return make_error(ErrorCode::kInternal, std::string("cannot create the Embree device: ") +
                                                error_name(rtcGetDeviceError(nullptr)));
  }
  rtcSetDeviceErrorFunction(impl->device, on_embree_error, &impl->errors);

  // Bounding box of the referenced vertices (those of non-degenerate
  // triangles): the scale of ray offsets (SPEC section 3).
  const std::size_t vertex_count = mesh.positions.size();
  impl->vertices.reset(new float[3 * vertex_count + 1]);
  impl->vertices[3 * vertex_count] = 0.0f;
  parallel_for_chunks(vertex_count, 1 << 16, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) {
      impl->vertices[3 * i + 0] = mesh.positions[i].x;
      impl->vertices[3 * i + 1] = mesh.positions[i].y;
      impl->vertices[3 * i + 2] = mesh.positions[i].z;
    }
  });
  // The indices copied and the box grown per fixed block of triangles, in
  // parallel; the blocks' boxes are then merged (min and max are exact, so
  // the box does not depend on the thread count).
  constexpr std::size_t kTriangleBlock = 1 << 16;
  const std::size_t triangle_count = mesh.triangles.size();
  impl->indices.reset(new uint32_t[3 * triangle_count]);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  using Box = std::array<double, 6>;  // lo x, y, z, hi x, y, z
  std::vector<Box> block_box(block_count(triangle_count, kTriangleBlock),
                             Box{kInf, kInf, kInf, -kInf, -kInf, -kInf});
  parallel_for_blocks(triangle_count, kTriangleBlock,
                      [&](std::size_t block, std::size_t begin, std::size_t end) {
                        Box box = block_box[block];
                        for (std::size_t t = begin; t < end; ++t) {
                          for (int k = 0; k < 3; ++k) {
                            const uint32_t v = mesh.triangles[t][k];
                            impl->indices[3 * t + k] = v;
                            for (int a = 0; a < 3; ++a) {
                              box[a] = std::min<double>(box[a], impl->vertices[3 * v + a]);
                              box[3 + a] = std::max<double>(box[3 + a], impl->vertices[3 * v + a]);
                            }
                          }
                        }
                        block_box[block] = box;
                      });
  double lo[3] = {kInf, kInf, kInf};
  double hi[3] = {-kInf, -kInf, -kInf};
  for (const Box& box : block_box) {
    for (int a = 0; a < 3; ++a)
      lo[a] = std::min(lo[a], box[a]), hi[a] = std::max(hi[a], box[3 + a]);
  }
  if (!mesh.triangles.empty()) {
    impl->diagonal =
        std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                  (hi[2] - lo[2]) * (hi[2] - lo[2]));
    for (int a = 0; a < 3; ++a) {
      impl->max_abs_coordinate =
          std::max({impl->max_abs_coordinate, std::abs(lo[a]), std::abs(hi[a])});
    }
  }

  impl->scene = rtcNewScene(impl->device);
  if (Status s = impl->check("creating the scene"); !s) return s.error();
  const RTCBuildQuality rtc_quality =
      quality == BuildQuality::kLow ? RTC_BUILD_QUALITY_LOW : RTC_BUILD_QUALITY_MEDIUM;
  rtcSetSceneBuildQuality(impl->scene, rtc_quality);
  // Robust traversal and intersection: visibility rays from mesh points
  // often pass exactly through shared edges (grid-aligned meshes under a
  // plane projector, rays through a sphere's centre), and without it they
  // slip through the cracks (tests/bake: RaysThroughSharedEdgesHit misses 85
  // of 1104 interior edges without it, none with it). Exact vertex hits can
  // still leak in rare cases (RenderKit/embree#188, #387).
  rtcSetSceneFlags(impl->scene,
                   static_cast<RTCSceneFlags>(RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_COMPACT));

  // An empty mesh gets an empty scene: every ray is free.
  if (!mesh.triangles.empty()) {
    RTCGeometry geometry = rtcNewGeometry(impl->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    rtcSetGeometryBuildQuality(geometry, rtc_quality);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                               impl->vertices.get(), 0, 3 * sizeof(float), vertex_count);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                               impl->indices.get(), 0, 3 * sizeof(uint32_t), mesh.triangles.size());
    rtcCommitGeometry(geometry);
    // The scene takes a reference to the geometry; ours is released at once.
    rtcAttachGeometry(impl->scene, geometry);
    rtcReleaseGeometry(geometry);
    if (Status s = impl->check("setting up the triangles"); !s) return s.error();
  }
  rtcCommitScene(impl->scene);
  if (Status s = impl->check("building the scene"); !s) return s.error();
  return EmbreeScene(std::move(impl));
}

double EmbreeScene::diagonal() const {
  return impl_->diagonal;
}
double EmbreeScene::max_abs_coordinate() const {
  return impl_->max_abs_coordinate;
}

// rtcOccluded1M on an AoS block: measured (bench/bake_bench.cpp, one thread)
// as fast as rtcOccludedNp and faster than rtcOccluded1 calls or
// rtcOccluded16 packets on our visibility rays.
void EmbreeScene::occluded(const RayBatch& rays, uint8_t* occluded) const {
  RTCIntersectContext context = make_context();
  alignas(64) RTCRay block[kBlock];
  for (std::size_t begin = 0; begin < rays.count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, rays.count - begin);
    for (std::size_t i = 0; i < n; ++i) {
      RTCRay& r = block[i];
      const std::size_t k = begin + i;
      r.org_x = rays.org_x[k], r.org_y = rays.org_y[k], r.org_z = rays.org_z[k];
      r.dir_x = rays.dir_x[k], r.dir_y = rays.dir_y[k], r.dir_z = rays.dir_z[k];
      r.tnear = rays.tnear ? rays.tnear[k] : 0.0f;
      r.tfar = rays.tfar ? rays.tfar[k] : std::numeric_limits<float>::infinity();
      r.time = 0;
      r.mask = 0xFFFFFFFFu;
      r.id = static_cast<unsigned>(i);
      r.flags = 0;
    }
    rtcOccluded1M(impl_->scene, &context, block, static_cast<unsigned>(n), sizeof(RTCRay));
    // A hit sets tfar to -inf (Embree docs, rtcOccluded1).
    for (std::size_t i = 0; i < n; ++i) occluded[begin + i] = block[i].tfar < 0.0f ? 1 : 0;
  }
}

void EmbreeScene::intersect(const RayBatch& rays, Hit* hits) const {
  AlignedRayBlock block;
  AlignedHitBlock hit_block;
  RTCIntersectContext context = make_context();
  const float* vertices = impl_->vertices.get();
  const uint32_t* indices = impl_->indices.get();
  for (std::size_t begin = 0; begin < rays.count; begin += kBlock) {
    const std::size_t n = std::min(kBlock, rays.count - begin);
    block.load(rays, begin, n);
    RTCRayHitNp np{block.np(), hit_block.np(n)};
    rtcIntersectNp(impl_->scene, &context, &np, static_cast<unsigned>(n));
    for (std::size_t i = 0; i < n; ++i) {
      Hit& hit = hits[begin + i];
      if (hit_block.geom_id[i] == RTC_INVALID_GEOMETRY_ID) {
        hit = Hit{};
        continue;
      }
      const uint32_t t = hit_block.prim_id[i];
      hit.triangle = t;
      hit.t = block.tfar[i];
      hit.b1 = hit_block.u[i];
      hit.b2 = hit_block.v[i];
      // Computed here rather than taken from Embree's Ng, whose sign
      // convention is Embree's: the header promises (v1 - v0) x (v2 - v0).
      const float* p0 = vertices + 3 * indices[3 * t + 0];
      const float* p1 = vertices + 3 * indices[3 * t + 1];
      const float* p2 = vertices + 3 * indices[3 * t + 2];
      const float e1[3] = {p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2]};
      const float e2[3] = {p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2]};
      hit.normal = Float3{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                          e1[0] * e2[1] - e1[1] * e2[0]};
    }
  }
}

}  // namespace texbake
