#include "segment/label_map.h"

#include <fmt/format.h>

#include <cmath>

#include "common/error.h"
#include "common/option_names.h"

namespace mpumesh::seg {
namespace {

void require_whole(float x, const std::string& source) {
  if (!(std::nearbyint(x) == x))
    throw InputError(fmt::format("{}: not a label map: a voxel holds {}, not a whole number", source, x));
}

}  // namespace

std::string too_small_to_mesh(int64_t voxels) {
  if (voxels >= kMinLabelVoxels) return "";
  return fmt::format("{} voxel{}, too small to mesh (a label needs at least {})", voxels, voxels == 1 ? "" : "s",
                     kMinLabelVoxels);
}

std::string label_name(const std::string& source, int64_t label) { return fmt::format("{} (label {})", source, label); }

Volume label_indicator(const Volume& labels, int64_t label, float others) {
  Volume v = labels;
  v.source = label_name(labels.source, label);
  const float l = float(label);
  int64_t n = 0;
  for (float& x : v.voxels) {
    require_whole(x, labels.source);
    n += x == l;
    x = x == l ? 1.0f : x == 0.0f ? 0.0f : others;
  }
  if (n == 0) throw InputError(v.source + ": no voxel holds this label");
  const std::string small = too_small_to_mesh(n);
  if (!small.empty()) throw InputError(v.source + ": " + small);
  return v;
}

std::map<int64_t, int64_t> label_voxel_counts(const Volume& labels) {
  std::map<int64_t, int64_t> counts;
  for (const float x : labels.voxels) {
    require_whole(x, labels.source);
    if (x != 0.0f && ++counts[int64_t(x)] == 1 && counts.size() > kMaxLabels)
      throw InputError(fmt::format("{}: more than {} different labels: this looks like an intensity image, not a "
                                   "label map (name the labels with {} L1,L2,... to mesh them anyway)",
                                   labels.source, kMaxLabels, option_ref("labels")));
  }
  return counts;
}

std::vector<int64_t> parse_label_list(const std::string& text) {
  std::vector<int64_t> out;
  if (text == "all") return out;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    size_t used = 0;
    long long v = 0;
    try {
      v = std::stoll(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || v <= 0)
      throw InputError(fmt::format("{}: '{}' is not a label (a whole number above 0); give 'all' or a list "
                                   "such as 3,7,12",
                                   option_ref("labels"), item));
    for (const int64_t seen : out)
      if (seen == v) throw InputError(fmt::format("{}: label {} is named twice", option_ref("labels"), v));
    out.push_back(v);
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

}  // namespace mpumesh::seg
