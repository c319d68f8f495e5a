#include "segment/chan_vese_ref.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "common/error.h"
#include "common/option_names.h"
#include "shared/chan_vese_abi.h"

namespace mpumesh::seg {

void validate(const ChanVeseParams& p) {
  auto need = [](bool ok, const char* name, const std::string& what) {
    if (!ok) throw InputError("Chan-Vese: " + option_ref(name) + " must be " + what);
  };
  need(std::isfinite(p.lambda1) && p.lambda1 > 0, "lambda1", "a positive number");
  need(std::isfinite(p.lambda2) && p.lambda2 > 0, "lambda2", "a positive number");
  need(std::isfinite(p.mu) && p.mu >= 0, "mu", "zero or positive");
  need(std::isfinite(p.nu) && p.nu >= 0, "nu", "zero or positive");
  need(std::isfinite(p.dt) && p.dt > 0, "dt", "a positive number");
  need(std::isfinite(p.epsilon) && p.epsilon > 0, "epsilon", "a positive number");
  need(std::isfinite(p.eta) && p.eta > 0, "eta", "a positive number");
  need(p.iterations >= 1 && p.iterations <= 100000, "iterations", "between 1 and 100000 (" + option_ref("method") + " threshold for none)");
}

template <class Real>
SliceMeans slice_means(const float* u, const Real* phi, int64_t pixels) {
  // u holds integers 0..255, so the sums are exact in 64-bit integers on both backends.
  uint64_t sum_in = 0, sum_all = 0;
  int64_t count_in = 0;
  for (int64_t p = 0; p < pixels; ++p) {
    const uint64_t v = uint64_t(u[p]);
    const uint64_t in = phi[p] >= Real(0) ? 1 : 0;
    sum_in += v * in;
    sum_all += v;
    count_in += int64_t(in);
  }
  const int64_t count_out = pixels - count_in;
  SliceMeans m;
  m.c1 = count_in ? double(sum_in) / double(count_in) : CV_EMPTY_C1;
  m.c2 = count_out ? double(sum_all - sum_in) / double(count_out) : CV_EMPTY_C2;
  m.inside = count_in;
  return m;
}

template <class Real>
void chan_vese_step(const float* u, const Real* phi_in, Real* phi_out, int64_t nx, int64_t ny, SliceMeans means,
                    const ChanVeseParams& p) {
  // A copy with one ghost pixel on every side (edge values replicated: the Neumann border,
  // the same as clamping the indices in the shader), so the row loops have no branches.
  const int64_t gx = nx + 2;
  std::vector<Real> g(size_t(gx * (ny + 2)));
  for (int64_t j = -1; j <= ny; ++j) {
    const Real* src = phi_in + nx * std::clamp<int64_t>(j, 0, ny - 1);
    Real* dst = g.data() + gx * (j + 1);
    dst[0] = src[0];
    std::copy(src, src + nx, dst + 1);
    dst[nx + 1] = src[nx - 1];
  }
  auto G = [&](int64_t j) { return g.data() + gx * (j + 1) + 1; };  // row j, column 0

  const Real eta2 = Real(p.eta * p.eta), eps = Real(p.epsilon), eps2 = eps * eps;
  const Real dt = Real(p.dt), mu = Real(p.mu), nu = Real(p.nu), l1 = Real(p.lambda1), l2 = Real(p.lambda2);
  const Real c1 = Real(means.c1), c2 = Real(means.c2), inv_pi = Real(std::numbers::inv_pi);
  const Real half = Real(0.5), one = Real(1);

  // cx[i + 1] is C1 at column i (so C2 at column i is cx[i]); cy_prev holds C3 of the row
  // below, which is this row's C4.
  std::vector<Real> cx(static_cast<size_t>(nx + 1)), cy(static_cast<size_t>(nx)), cy_prev(static_cast<size_t>(nx));
  auto row_cy = [&](int64_t j, Real* out) {  // C3 of row j (j may be -1: the ghost row)
    const Real *r = G(j), *up = G(j + 1);
    for (int64_t i = 0; i < nx; ++i) {
      const Real dx = (r[i + 1] - r[i - 1]) * half, dy = up[i] - r[i];
      out[i] = one / std::sqrt(eta2 + dx * dx + dy * dy);
    }
  };
  row_cy(-1, cy_prev.data());
  for (int64_t j = 0; j < ny; ++j) {
    const Real *r = G(j), *dn = G(j - 1), *up = G(j + 1);
    for (int64_t i = -1; i < nx; ++i) {
      const Real dx = r[i + 1] - r[i], dy = (up[i] - dn[i]) * half;
      cx[size_t(i + 1)] = one / std::sqrt(eta2 + dx * dx + dy * dy);
    }
    row_cy(j, cy.data());
    const float* ur = u + nx * j;
    Real* out = phi_out + nx * j;
    for (int64_t i = 0; i < nx; ++i) {
      const Real phi = r[i];
      const Real delta = eps * inv_pi / (eps2 + phi * phi);
      const Real m = dt * delta * mu;
      const Real C1 = cx[size_t(i + 1)], C2 = cx[size_t(i)], C3 = cy[size_t(i)], C4 = cy_prev[size_t(i)];
      const Real uv = Real(ur[i]);
      const Real force = -nu - l1 * (uv - c1) * (uv - c1) + l2 * (uv - c2) * (uv - c2);
      const Real num = phi + m * (C1 * r[i + 1] + C2 * r[i - 1] + C3 * up[i] + C4 * dn[i]) + dt * delta * force;
      out[i] = num / (one + m * (C1 + C2 + C3 + C4));
    }
    std::swap(cy, cy_prev);
  }
}

template SliceMeans slice_means<float>(const float*, const float*, int64_t);
template SliceMeans slice_means<double>(const float*, const double*, int64_t);
template void chan_vese_step<float>(const float*, const float*, float*, int64_t, int64_t, SliceMeans,
                                    const ChanVeseParams&);
template void chan_vese_step<double>(const float*, const double*, double*, int64_t, int64_t, SliceMeans,
                                     const ChanVeseParams&);

ChanVeseResult chan_vese_ref(const ChanVeseStack& s, const ChanVeseParams& p) {
  validate(p);
  const int64_t n = s.slice_pixels();
  MPUMESH_ASSERT(int64_t(s.u.size()) == n * s.nz && s.phi.size() == s.u.size(), "Chan-Vese stack sizes");
  ChanVeseResult r;
  r.phi.resize(s.phi.size());
  r.c1.assign(size_t(s.nz), CV_EMPTY_C1);
  r.c2.assign(size_t(s.nz), CV_EMPTY_C2);
  // Slices are independent: each task runs all iterations of one slice in its cache.
  tbb::parallel_for(int64_t(0), s.nz, [&](int64_t k) {
    const float* u = s.u.data() + n * k;
    std::vector<double> a(s.phi.begin() + n * k, s.phi.begin() + n * (k + 1)), b(static_cast<size_t>(n));
    for (int it = 0; it < p.iterations; ++it) {
      const SliceMeans m = slice_means(u, a.data(), n);
      chan_vese_step(u, a.data(), b.data(), s.nx, s.ny, m, p);
      std::swap(a, b);
      r.c1[size_t(k)] = m.c1;
      r.c2[size_t(k)] = m.c2;
    }
    std::transform(a.begin(), a.end(), r.phi.begin() + n * k, [](double v) { return float(v); });
  });
  return r;
}

}  // namespace mpumesh::seg
