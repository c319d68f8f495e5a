#include "particles/spacing_stats.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>

#include "common/error.h"
#include "common/kd_tree.h"

namespace mpumesh::particles {
namespace {

std::vector<double> ranks(const std::vector<double>& v) {
  std::vector<size_t> o(v.size());
  std::iota(o.begin(), o.end(), size_t(0));
  std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return v[a] < v[b]; });
  std::vector<double> r(v.size());
  for (size_t i = 0; i < o.size();) {
    size_t j = i;
    while (j + 1 < o.size() && v[o[j + 1]] == v[o[i]]) ++j;
    for (size_t k = i; k <= j; ++k) r[o[k]] = 0.5 * double(i + j);
    i = j + 1;
  }
  return r;
}

double median_of(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

}  // namespace

std::vector<double> local_spacing(const std::vector<Eigen::Vector3d>& x, size_t stride, const KdTree* index) {
  MPUMESH_ASSERT(stride >= 1, "local_spacing: stride must be at least 1");
  std::vector<double> out((x.size() + stride - 1) / stride, 0.0);
  if (x.size() < 7) return out;
  std::unique_ptr<PointIndex> own;
  const KdTree& tree = given_or_built(index, x, own);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, out.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const size_t i = k * stride;
      uint32_t idx[7];
      double d2[7];
      nanoflann::KNNResultSet<double, uint32_t> rs(7);
      rs.init(idx, d2);
      tree.findNeighbors(rs, x[i].data(), nanoflann::SearchParams());
      double s = 0;
      for (int k = 1; k < 7; ++k) s += std::sqrt(d2[k]);
      out[k] = s / 6;
    }
  });
  return out;
}

double rank_correlation(const std::vector<double>& a, const std::vector<double>& b) {
  MPUMESH_ASSERT(a.size() == b.size(), "rank_correlation of unequal lengths");
  if (a.size() < 2) return 0;
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double m = 0.5 * double(a.size() - 1);
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    sab += (ra[i] - m) * (rb[i] - m);
    saa += (ra[i] - m) * (ra[i] - m);
    sbb += (rb[i] - m) * (rb[i] - m);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : 0;
}

SpacingStats spacing_stats(const std::vector<double>& spacing, const std::vector<double>& abs_gauss) {
  MPUMESH_ASSERT(spacing.size() == abs_gauss.size(), "spacing_stats of unequal lengths");
  SpacingStats s;
  const size_t n = spacing.size();
  if (n < 10) return s;
  double sum = 0, sum2 = 0;
  for (double v : spacing) {
    sum += v;
    sum2 += v * v;
  }
  s.mean = sum / double(n);
  s.cv = std::sqrt(std::max(sum2 / double(n) - s.mean * s.mean, 0.0)) / s.mean;
  std::vector<size_t> o(n);
  std::iota(o.begin(), o.end(), size_t(0));
  std::sort(o.begin(), o.end(), [&](size_t a, size_t b) { return abs_gauss[a] < abs_gauss[b]; });
  const size_t tenth = std::max<size_t>(1, n / 10);
  std::vector<double> lo, hi;
  for (size_t k = 0; k < tenth; ++k) {
    lo.push_back(spacing[o[k]]);
    hi.push_back(spacing[o[n - 1 - k]]);
  }
  s.low_k_median = median_of(lo);
  s.high_k_median = median_of(hi);
  s.ratio = s.low_k_median > 0 ? s.high_k_median / s.low_k_median : 0;
  s.rank_correlation = rank_correlation(spacing, abs_gauss);
  return s;
}

SpacingSummary spacing_summary(const SampleStats& st, const ParticleState& ps) {
  std::vector<double> absk(ps.size());
  for (size_t i = 0; i < ps.size(); ++i)
    absk[i] = std::abs(i < st.gauss_at_scale.size() ? st.gauss_at_scale[i] : ps.curv[i].gauss);
  const std::vector<double> spacing = local_spacing(ps.x);
  SpacingSummary out;
  out.all = spacing_stats(spacing, absk);
  std::vector<double> curved_spacing, curved_absk;
  for (size_t i = 0; i < ps.size(); ++i)
    if (i < st.spacing_by_thickness.size() && !st.spacing_by_thickness[i])
      curved_spacing.push_back(spacing[i]), curved_absk.push_back(absk[i]);
  out.curved = spacing_stats(curved_spacing, curved_absk);
  out.curved_particles = int64_t(curved_spacing.size());
  return out;
}

}  // namespace mpumesh::particles
