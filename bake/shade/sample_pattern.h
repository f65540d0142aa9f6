// Deterministic sample patterns: the hash and the low-discrepancy sequence
// behind the vertex area filter's jitter, the atlas supersample offsets and the
// render's pixel jitter. Each value depends on its arguments only (no
// generator state), so results never depend on the thread count.
#pragma once

#include <cstdint>

namespace texbake {

// SplitMix64's output function (Steele, Lea, Flood 2014): a statistically good
// 64-bit mixer.
constexpr uint64_t splitmix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// A hash of (item, index), e.g. (vertex, sample): splitmix64(splitmix64(item) ^ index).
constexpr uint64_t hash_pair(uint64_t item, uint64_t index) {
  return splitmix64(splitmix64(item) ^ index);
}

// The top 53 bits of `bits` as a double in [0, 1).
constexpr double unit_double(uint64_t bits) {
  return static_cast<double>(bits >> 11) * 0x1.0p-53;
}

// Van der Corput sequence in base 2 (the bits of i reversed, over 2^32): the
// second coordinate of a Hammersley set, in [0, 1).
constexpr double radical_inverse2(uint32_t i) {
  i = (i << 16) | (i >> 16);
  i = ((i & 0x00FF00FFu) << 8) | ((i & 0xFF00FF00u) >> 8);
  i = ((i & 0x0F0F0F0Fu) << 4) | ((i & 0xF0F0F0F0u) >> 4);
  i = ((i & 0x33333333u) << 2) | ((i & 0xCCCCCCCCu) >> 2);
  i = ((i & 0x55555555u) << 1) | ((i & 0xAAAAAAAAu) >> 1);
  return static_cast<double>(i) * 0x1.0p-32;
}

}  // namespace texbake
