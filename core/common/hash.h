// MurmurHash3's 32-bit finalizer: the repeatable "random" numbers of the particle system
// (seeding orders, fission directions, deaths) are hashes, not a generator's stream, so
// that any particle's decision can be recomputed from its index alone.
#pragma once

#include <cstdint>

namespace mpumesh {

inline uint32_t fmix32(uint32_t h) {
  h ^= h >> 16;
  h *= 0x85ebca6bu;
  h ^= h >> 13;
  h *= 0xc2b2ae35u;
  h ^= h >> 16;
  return h;
}

}  // namespace mpumesh
