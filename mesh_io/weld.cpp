#include "mesh_io/weld.h"

#include <bit>

namespace texbake {

namespace {

uint32_t bits(float f) {
  if (f == 0.f) f = 0.f;  // -0 and +0 are one position
  return std::bit_cast<uint32_t>(f);
}

bool same(const Float3& a, const Float3& b) {
  return a.x == b.x && a.y == b.y && a.z == b.z;
}

uint64_t hash(const Float3& p) {
  // splitmix64's finaliser over the three coordinates' bits.
  uint64_t h =
      (uint64_t{bits(p.x)} << 32 | bits(p.y)) ^ (uint64_t{bits(p.z)} * 0x9E3779B97F4A7C15u);
  h ^= h >> 30;
  h *= 0xBF58476D1CE4E5B9u;
  h ^= h >> 27;
  h *= 0x94D049BB133111EBu;
  h ^= h >> 31;
  return h;
}

}  // namespace

std::vector<uint32_t> weld_by_position(const MeshData& mesh) {
  const std::size_t n = mesh.vertex_count();
  if (n < 2) return {};
  constexpr uint32_t kEmpty = 0xFFFFFFFFu;
  // Load at most 2/3: linear probing stays short.
  const std::size_t size = std::bit_ceil(n + n / 2);
  const std::size_t mask = size - 1;
  std::vector<uint32_t> table(size, kEmpty);
  std::vector<uint32_t> rep(n);
  bool any = false;
  for (std::size_t v = 0; v < n; ++v) {
    const Float3& p = mesh.positions[v];
    std::size_t slot = hash(p) & mask;
    while (table[slot] != kEmpty && !same(mesh.positions[table[slot]], p)) slot = (slot + 1) & mask;
    if (table[slot] == kEmpty) {
      table[slot] = static_cast<uint32_t>(v);
      rep[v] = static_cast<uint32_t>(v);
    } else {
      rep[v] = table[slot];
      any = true;
    }
  }
  if (!any) return {};
  return rep;
}

}  // namespace texbake
