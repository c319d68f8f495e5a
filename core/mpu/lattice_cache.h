// The fit's cache of values at octree lattice points (the auxiliary points' signed
// distances), shared by the threads that fit one level's cells: a fixed table of slots,
// open addressing, no locks and no allocation per entry. A value depends on its key
// alone (the point is computed from its integer index), so two threads that miss on one
// key both compute it and store the same bits; a full neighbourhood of slots only means
// the value is computed again instead of cached.
#pragma once

#include <tbb/parallel_for.h>

#include <atomic>
#include <bit>
#include <cstdint>
#include <cstring>
#include <memory>

#include "common/hash.h"

namespace mpumesh::mpu {

class LatticeCache {
 public:
  // Empties the table and sizes it for about `keys` keys (a power of two, at least twice).
  void reset(size_t keys) {
    const size_t want = std::bit_ceil(std::max<size_t>(2 * keys, 1024));
    if (want != size_) {
      slots_ = std::make_unique<Slot[]>(want);
      size_ = want;
    }
    tbb::parallel_for(tbb::blocked_range<size_t>(0, size_, 1 << 14), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        slots_[i].key.store(kEmpty, std::memory_order_relaxed);
        slots_[i].bits.store(kPending, std::memory_order_relaxed);
      }
    });
  }

  // The value at `key` when the table holds it (and no thread is still computing it).
  bool find(uint64_t key, double& v) const {
    if (size_ == 0) return false;
    const size_t mask = size_ - 1;
    size_t at = size_t(fmix64(key)) & mask;
    for (int probe = 0; probe < kMaxProbe; ++probe, at = (at + 1) & mask) {
      const Slot& s = slots_[at];
      const uint64_t k = s.key.load(std::memory_order_acquire);
      if (k == kEmpty) return false;
      if (k == key) {
        const uint64_t b = s.bits.load(std::memory_order_acquire);
        if (b == kPending) return false;
        v = from_bits(b);
        return true;
      }
    }
    return false;
  }

  // The value at `key` (any number but UINT64_MAX), computed by `compute()` on a miss.
  template <class Compute>
  double get(uint64_t key, Compute&& compute) {
    const size_t mask = size_ - 1;
    size_t at = size_t(fmix64(key)) & mask;
    for (int probe = 0; probe < kMaxProbe; ++probe, at = (at + 1) & mask) {
      Slot& s = slots_[at];
      uint64_t k = s.key.load(std::memory_order_acquire);
      if (k == kEmpty && s.key.compare_exchange_strong(k, key, std::memory_order_acq_rel)) {
        const double v = compute();
        s.bits.store(to_bits(v), std::memory_order_release);
        return v;
      }
      if (k == key) {
        const uint64_t b = s.bits.load(std::memory_order_acquire);
        return b != kPending ? from_bits(b) : compute();  // pending: another thread is on it
      }
    }
    return compute();
  }

 private:
  static constexpr uint64_t kEmpty = UINT64_MAX;
  // Not a value compute() can return: NaN with a payload no arithmetic makes.
  static constexpr uint64_t kPending = 0x7ff4'0000'dead'beefull;
  static constexpr int kMaxProbe = 64;
  struct Slot {
    std::atomic<uint64_t> key{kEmpty};
    std::atomic<uint64_t> bits{kPending};
  };
  static uint64_t to_bits(double v) {
    uint64_t b;
    std::memcpy(&b, &v, sizeof b);
    return b;
  }
  static double from_bits(uint64_t b) {
    double v;
    std::memcpy(&v, &b, sizeof v);
    return v;
  }
  std::unique_ptr<Slot[]> slots_;
  size_t size_ = 0;
};

}  // namespace mpumesh::mpu
