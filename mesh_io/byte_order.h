// Byte swapping for binary mesh files (std::byteswap is C++23).
#pragma once

#include <cstdint>

namespace texbake {

inline uint16_t byte_swap(uint16_t v) {
  return __builtin_bswap16(v);
}
inline uint32_t byte_swap(uint32_t v) {
  return __builtin_bswap32(v);
}
inline uint64_t byte_swap(uint64_t v) {
  return __builtin_bswap64(v);
}

}  // namespace texbake
