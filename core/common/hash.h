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

// Its 64-bit finalizer: the slot of a key in the open-addressing tables.
inline uint64_t fmix64(uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  return h ^ (h >> 33);
}

}  // namespace mpumesh
