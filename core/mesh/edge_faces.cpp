#include "mesh/edge_faces.h"

#include <tbb/parallel_sort.h>

#include "common/error.h"
#include "common/hash.h"

namespace mpumesh {

void EdgeFaces::build(std::vector<std::pair<uint64_t, uint32_t>> pairs, bool lookup) {
  tbb::parallel_sort(pairs.begin(), pairs.end());  // the pairs are distinct: one order
  faces_.reserve(pairs.size());
  for (size_t a = 0, b; a < pairs.size(); a = b) {
    for (b = a + 1; b < pairs.size() && pairs[b].first == pairs[a].first;) ++b;
    keys_.push_back(pairs[a].first);
    first_.push_back(uint32_t(faces_.size()));
    for (size_t k = a; k < b; ++k) faces_.push_back(pairs[k].second);
  }
  first_.push_back(uint32_t(faces_.size()));
  if (!lookup) return;
  MPUMESH_ASSERT(keys_.size() < UINT32_MAX, "EdgeFaces: too many edges");
  size_t slots = 16;
  while (slots < 2 * keys_.size()) slots *= 2;
  mask_ = slots - 1;
  index_.assign(slots, UINT32_MAX);
  for (uint32_t i = 0; i < keys_.size(); ++i) {
    size_t at = slot(keys_[i]);
    while (index_[at] != UINT32_MAX) at = (at + 1) & mask_;
    index_[at] = i;
  }
}

size_t EdgeFaces::slot(uint64_t key) const { return size_t(fmix64(key)) & mask_; }

size_t EdgeFaces::find(uint64_t key) const {
  MPUMESH_ASSERT(!index_.empty(), "EdgeFaces: built without the lookup");
  for (size_t at = slot(key);; at = (at + 1) & mask_) {
    if (index_[at] == UINT32_MAX) return npos;
    if (keys_[index_[at]] == key) return index_[at];
  }
}

}  // namespace mpumesh
