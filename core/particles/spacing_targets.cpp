#include "particles/spacing_targets.h"

#include <algorithm>
#include <cmath>

#include "compute/compute_backend.h"
#include "particles/spacing_gradation.h"

namespace mpumesh::particles {

std::vector<double> curvature_weights(const std::vector<double>& gauss, double scale, double& lo, double& hi) {
  std::vector<double> k;
  k.reserve(gauss.size());
  for (double g : gauss)
    if (std::isfinite(g)) k.push_back(std::sqrt(std::abs(g)));
  double mean = 0, sd = 0;
  if (!k.empty()) {
    const size_t p99 = std::min(k.size() - 1, size_t(0.99 * double(k.size())));
    std::nth_element(k.begin(), k.begin() + ptrdiff_t(p99), k.end());
    const double cut = k[p99];
    double sum = 0, sum2 = 0;
    int64_t n = 0;
    for (double v : k)
      if (v <= cut) {
        sum += v;
        sum2 += v * v;
        ++n;
      }
    mean = sum / double(n);
    sd = std::sqrt(std::max(sum2 / double(n) - mean * mean, 0.0));
  }
  lo = std::max(mean - 2 * sd, 0.0);
  hi = mean + 2 * sd;
  const double range = std::max({hi - lo, mean, 1e-12});
  std::vector<double> w(gauss.size(), 1.0);
  for (size_t i = 0; i < gauss.size(); ++i) {
    const double g = std::isfinite(gauss[i]) ? std::abs(gauss[i]) : 0.0;
    w[i] = std::exp(-scale * (std::clamp(std::sqrt(g), lo, hi) - lo) / range);
  }
  return w;
}

// A plate's thickness makes its spacing no finer than this fraction of the base spacing.
constexpr double kThicknessFloor = 0.22;
Targets spacing_targets(const std::vector<double>& lambda, const std::vector<double>& thickness,
                        const std::vector<double>& kappa, double h, double bend_floor, double scale,
                        const SampleOptions& opt) {
  Targets t;
  t.spacing.resize(lambda.size());
  t.by_thickness.resize(lambda.size());
  const double turn = scale * opt.normal_turn, bend_min = scale * bend_floor;
  for (size_t i = 0; i < lambda.size(); ++i) {
    const double base = turn > 0 && kappa[i] > 0 ? std::min(h, std::max(bend_min, turn / kappa[i])) : h;
    const double floor = base * kThicknessFloor;
    const double by_curv = base * lambda[i];
    const double by_thick = std::max(opt.thickness_factor * thickness[i], floor);
    t.spacing[i] = std::min(by_curv, by_thick);
    t.by_thickness[i] = by_thick < 0.999 * by_curv;
    t.thickness_bound += by_thick < 0.999 * by_curv;
  }
  return t;
}

void grade_targets(const std::vector<Eigen::Vector3d>& x, const std::vector<double>& w, Targets& t,
                   const SampleOptions& opt, double max_reach) {
  if (!(opt.spacing_grade > 0) || x.empty()) return;
  auto count = [&] {
    double n = 0;
    for (size_t i = 0; i < x.size(); ++i) n += w[i] / (t.spacing[i] * t.spacing[i]);
    return n;
  };
  const double before = count();
  limit_spacing_gradient(x, t.spacing, opt.spacing_grade, max_reach);
  const double after = count();
  if (!(after > 0) || !(before > 0)) return;
  const double k = std::sqrt(after / before);
  for (double& v : t.spacing) v *= k;
}

std::vector<double> thicknesses(ComputeBackend& backend, const mpu::MpuSurface& s, const ParticleState& st,
                                const std::vector<double>& lambda, double reach) {
  std::vector<double> max_dist(st.size());
  for (size_t i = 0; i < st.size(); ++i) max_dist[i] = std::isfinite(st.distance[i]) ? reach * lambda[i] : NAN;
  return backend.thickness(s, st.x, st.normal, max_dist);
}


}  // namespace mpumesh::particles
