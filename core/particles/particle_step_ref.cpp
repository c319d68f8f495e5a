#include "particles/particle_step_ref.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "particles/pair_filter.h"
#include "particles/pair_sums.h"

namespace mpumesh::particles {

void ParticleState::resize(size_t n) {
  x.resize(n, Eigen::Vector3d::Zero());
  sigma.resize(n, 1.0);
  target.resize(n, 1.0);
  normal.resize(n, Eigen::Vector3d::UnitZ());
  distance.resize(n, 0.0);
  curv.resize(n);
  energy.resize(n, 0.0);
  speed.resize(n, 0.0);
}

ParticleGrid build_particle_grid(const std::vector<Eigen::Vector3d>& x, double cell,
                                 const std::vector<uint8_t>* member) {
  MPUMESH_ASSERT(cell > 0 && std::isfinite(cell), "particle grid cell must be positive");
  auto in = [&](size_t i) { return !member || (*member)[i]; };
  ParticleGrid g;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = Eigen::Vector3d::Constant(-INFINITY);
  size_t count = 0;
  for (size_t i = 0; i < x.size(); ++i)
    if (in(i)) {
      lo = lo.cwiseMin(x[i]);
      hi = hi.cwiseMax(x[i]);
      ++count;
    }
  if (count == 0) lo = hi = Eigen::Vector3d::Zero();
  g.origin = lo;
  // At most 1024 cells a side: a wider cell only costs extra distance tests.
  cell = std::max(cell, (hi - lo).maxCoeff() / 1023.0);
  g.cell = cell;
  uint64_t cells = 1;
  for (int d = 0; d < 3; ++d) {
    g.dims[size_t(d)] = uint32_t(std::floor((hi[d] - lo[d]) / cell) + 1);
    cells *= g.dims[size_t(d)];
  }
  g.start.assign(cells + 1, 0);
  g.cell_of.assign(x.size(), UINT32_MAX);
  for (size_t i = 0; i < x.size(); ++i) {
    if (!in(i)) continue;
    uint32_t c[3];
    for (int d = 0; d < 3; ++d)
      c[d] = uint32_t(std::clamp((x[i][d] - lo[d]) / cell, 0.0, double(g.dims[size_t(d)] - 1)));
    g.cell_of[i] = c[0] + g.dims[0] * (c[1] + g.dims[1] * c[2]);
    ++g.start[g.cell_of[i] + 1];
  }
  for (uint64_t c = 0; c < cells; ++c) g.start[c + 1] += g.start[c];
  g.order.resize(count);
  std::vector<uint32_t> fill(g.start.begin(), g.start.end() - 1);
  for (size_t i = 0; i < x.size(); ++i)
    if (in(i)) g.order[fill[g.cell_of[i]]++] = uint32_t(i);
  return g;
}

ParticleGrids build_particle_grids(const ParticleState& st, const StepParams& p) {
  ParticleGrids g;
  const size_t n = st.size();
  std::vector<double> sig(st.sigma);
  double smax = 0;
  for (double v : sig) smax = std::max(smax, v);
  if (n == 0) {
    g.small = build_particle_grid(st.x, 1.0);
    g.large = g.small;
    return g;
  }
  const size_t q = std::min(n - 1, size_t(0.95 * double(n)));
  std::nth_element(sig.begin(), sig.begin() + ptrdiff_t(q), sig.end());
  g.sigma_split = sig[q];
  std::vector<uint8_t> small(n), large(n);
  for (size_t i = 0; i < n; ++i) {
    small[i] = st.sigma[i] <= g.sigma_split;
    large[i] = !small[i];
  }
  g.small = build_particle_grid(st.x, p.cutoff * g.sigma_split, &small);
  g.large = build_particle_grid(st.x, p.cutoff * std::max(smax, g.sigma_split), &large);
  return g;
}

namespace {

// The particles as pair_sums reads them; `inv_s2` holds 1 / σ² of each.
PairView pair_view(const ParticleState& st, const std::vector<double>& inv_s2, const StepParams& p) {
  static_assert(sizeof(Eigen::Vector3d) == 3 * sizeof(double), "positions must be packed");
  return {st.x.empty() ? nullptr : st.x[0].data(), st.sigma.data(), inv_s2.data(), p.mu, p.cutoff * p.cutoff};
}

// Particle i's new position and σ from its sums, and its energy and speed.
void finish_particle(ParticleState& st, uint32_t i, PairTotals s, const StepParams& p,
                     std::vector<Eigen::Vector3d>& x_new, std::vector<double>& sigma_new) {
  const double si = st.sigma[i];
  s.E -= 2 * p.mu;
  const Eigen::Vector3d D = si * si * Eigen::Vector3d(s.D[0], s.D[1], s.D[2]);
  const Eigen::Vector3d& nrm = st.normal[i];
  const double dist = std::isfinite(st.distance[i]) ? st.distance[i] : 0.0;
  const Eigen::Vector3d v = D - (nrm.dot(D) + p.phi * dist) * nrm;
  // Linearly implicit Euler steps: the explicit step Δt ṗ with the paper's Δt = 0.3
  // overshoots (Δt times the stiffness of six neighbours at equilibrium is about 3)
  // and the particles jitter instead of settling; dividing by 1 + Δt k, k the
  // diagonal of -∂ṗ/∂x averaged over the tangent plane, damps it and leaves Δt
  // as it is where the stiffness is small.
  const double k = 0.5 * si * si * s.stiff;
  Eigen::Vector3d step = p.dt / (1 + p.dt * k) * v;
  const double len = step.norm(), cap = p.max_move * si;
  if (len > cap) step *= cap / len;
  x_new[i] = st.x[i] + step;
  // The same for σ: σ̇ = -ρ (E - Ê) / (∂E/∂σ + β), with ∂σ̇/∂σ ≈ -ρ ∂E/∂σ / (∂E/∂σ + β).
  const double dsigma = -p.dt * p.rho * (s.E - p.desired_energy) / (s.dE + p.beta + p.dt * p.rho * s.dE);
  sigma_new[i] = std::min(std::clamp(si + dsigma, si / p.sigma_change, si * p.sigma_change), p.sigma_cap);
  st.energy[i] = s.E;
  st.speed[i] = v.norm();
}

// 1 / σ² of every particle.
std::vector<double> inverse_squares(const std::vector<double>& sigma) {
  std::vector<double> v(sigma.size());
  for (size_t i = 0; i < sigma.size(); ++i) v[i] = 1.0 / (sigma[i] * sigma[i]);
  return v;
}

// A grid's particles in its order, coordinates and σ apart, for the vector filter.
CandidateSoa candidate_soa(const ParticleGrid& g, const ParticleState& st) {
  CandidateSoa a;
  const size_t m = g.order.size();
  a.x.resize(m), a.y.resize(m), a.z.resize(m), a.sigma.resize(m);
  for (size_t k = 0; k < m; ++k) {
    const uint32_t j = g.order[k];
    a.x[k] = st.x[j].x(), a.y[k] = st.x[j].y(), a.z[k] = st.x[j].z(), a.sigma[k] = st.sigma[j];
  }
  return a;
}

// Appends to `out` every particle j of grid g (candidates `a`) in the cells within `reach`
// of xi whose pair with i is not beyond both cutoffs, !(r² >= c2 max(si², σ_j²)), in the
// grid's order. `kept` is scratch.
void gather(const ParticleGrid& g, const CandidateSoa& a, const Eigen::Vector3d& xi, double si, double reach,
            double c2, SimdLevel level, std::vector<uint32_t>& kept, std::vector<uint32_t>& out) {
  int64_t lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    const double u = (xi[d] - g.origin[d]) / g.cell, span = reach / g.cell;
    lo[d] = std::max<int64_t>(int64_t(std::floor(u - span)), 0);
    hi[d] = std::min<int64_t>(int64_t(std::floor(u + span)), int64_t(g.dims[size_t(d)]) - 1);
    if (lo[d] > hi[d]) return;
  }
  for (int64_t z = lo[2]; z <= hi[2]; ++z)
    for (int64_t y = lo[1]; y <= hi[1]; ++y) {
      const int64_t row = int64_t(g.dims[0]) * (y + int64_t(g.dims[1]) * z);
      const uint32_t k0 = g.start[size_t(row + lo[0])], k1 = g.start[size_t(row + hi[0] + 1)];
      // Most candidates (about 200 a particle on the sample CT, 9 of them kept) lie
      // beyond both cutoffs; the filter drops them, 8 at a time, before the
      // exponentials (pair_filter.h). (`kept` only grows: no zeros written per row.)
      if (kept.size() < k1 - k0 + 8) kept.resize(k1 - k0 + 8);
      const uint32_t m = pairs_within(a, k0, k1, xi.data(), si * si, c2, kept.data(), level);
      for (uint32_t t = 0; t < m; ++t) out.push_back(g.order[kept[t]]);
    }
}

}  // namespace

void repulsion_step(ParticleState& st, const ParticleGrids& grids, const StepParams& p,
                    std::vector<Eigen::Vector3d>& x_new, std::vector<double>& sigma_new) {
  const size_t n = st.size();
  x_new.resize(n);
  sigma_new.resize(n);
  st.energy.resize(n);
  st.speed.resize(n);
  const double c2 = p.cutoff * p.cutoff;
  // Visit particles in cell order, for the cache: the small ones, then the large.
  std::vector<uint32_t> visit(grids.small.order);
  visit.insert(visit.end(), grids.large.order.begin(), grids.large.order.end());
  MPUMESH_ASSERT(visit.size() == n, "particle grids must hold every particle once");
  const CandidateSoa small = candidate_soa(grids.small, st), large = candidate_soa(grids.large, st);
  const std::vector<double> inv_s2 = inverse_squares(st.sigma);
  const PairView view = pair_view(st, inv_s2, p);
  const SimdLevel level = simd_level();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    thread_local std::vector<uint32_t> kept, pairs;
    for (size_t o = r.begin(); o != r.end(); ++o) {
      const uint32_t i = visit[o];
      const double si = st.sigma[i];
      pairs.clear();
      // A small j interacts within cutoff·max(σ_i, σ_split), a large one within its own
      // cutoff·σ_j, which the large grid's cells cover.
      gather(grids.small, small, st.x[i], si, p.cutoff * std::max(si, grids.sigma_split), c2, level, kept, pairs);
      gather(grids.large, large, st.x[i], si, grids.large.cell, c2, level, kept, pairs);
      finish_particle(st, i, pair_sums(view, i, pairs.data(), uint32_t(pairs.size()), level), p, x_new, sigma_new);
    }
  });
}

bool newton_project(const mpu::MpuSurface& s, Eigen::Vector3d& x, int steps, double max_move) {
  for (int k = 0; k < steps; ++k) {
    const mpu::Sample e = mpu::evaluate_fg(s, x);
    const double g2 = e.g.squaredNorm();
    if (!(g2 > 0) || e.leaves == 0) return false;
    Eigen::Vector3d step = -e.f / g2 * e.g;
    const double len = step.norm();
    if (len > max_move) step *= max_move / len;
    x += step;
    if (len < 1e-9) break;  // converged (1 pm): the remaining steps would not move it
  }
  return true;
}

void project_step(const mpu::MpuSurface& s, ParticleState& st, const StepParams& p, bool with_curvature) {
  const size_t n = st.size();
  st.normal.resize(n);
  st.distance.resize(n);
  st.curv.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Eigen::Vector3d x = st.x[i];
      const double cap = st.sigma[i];
      const bool ok = newton_project(s, x, p.newton_steps - 1, cap);
      // The last Newton step takes its f and ∇f from the evaluation that also gives the
      // normal (and the Hessian of f, for the curvature weights, when asked): one
      // evaluation per particle and iteration by default.
      const mpu::Sample e = with_curvature ? mpu::evaluate_hessian(s, x) : mpu::evaluate_fg(s, x);
      const double g2 = e.g.squaredNorm(), g = std::sqrt(g2);
      if (!ok || !(g > 0) || e.leaves == 0) {
        st.x[i] = x;
        st.distance[i] = NAN;  // lost: no surface here; the population step removes it
        // NaN curvature marks a NaN evaluation (a broken surface), zeros a vanished gradient.
        st.curv[i] = std::isnan(e.f) || !e.g.allFinite() ? mpu::Curvature{NAN, NAN, NAN, NAN} : mpu::Curvature{};
        continue;
      }
      Eigen::Vector3d step = -e.f / g2 * e.g;
      const double len = step.norm();
      if (len > cap) step *= cap / len;
      st.x[i] = x + step;
      st.normal[i] = e.g / g;
      // The linearised f / |∇f| after the step: 0 unless the step was capped.
      st.distance[i] = (e.f + e.g.dot(step)) / g;
      if (with_curvature) st.curv[i] = mpu::curvature(e.g, e.H);
    }
  });
}

double local_thickness(const mpu::MpuSurface& s, const Eigen::Vector3d& x, const Eigen::Vector3d& n, double max_dist) {
  double best = INFINITY;
  if (!(max_dist > 0) || !std::isfinite(max_dist)) return best;
  for (const double dir : {-1.0, 1.0}) {
    const double step = std::min(best, max_dist) / kThicknessSteps;
    // Inward (dir < 0) f is negative until the opposite sheet; outward positive until the
    // next one.
    auto crossed = [&](double t) { return dir * mpu::evaluate_f(s, x + dir * t * n) < 0; };
    for (int k = 1; k <= kThicknessSteps; ++k) {
      const double t = k * step;
      if (!crossed(t)) continue;
      double a = (k - 1) * step, b = t;
      for (int it = 0; it < kThicknessBisections; ++it) {
        const double m = 0.5 * (a + b);
        (crossed(m) ? b : a) = m;
      }
      best = std::min(best, 0.5 * (a + b));
      break;
    }
  }
  return best;
}

std::vector<double> thickness_step(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& x,
                                   const std::vector<Eigen::Vector3d>& n, const std::vector<double>& max_dist) {
  std::vector<double> t(x.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, x.size(), 128), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) t[i] = local_thickness(s, x[i], n[i], max_dist[i]);
  });
  return t;
}

void particle_iterations(const mpu::MpuSurface& s, ParticleState& st, const StepParams& p, int iterations) {
  std::vector<Eigen::Vector3d> x_new;
  std::vector<double> sigma_new;
  for (int it = 0; it < iterations; ++it) {
    const ParticleGrids grids = build_particle_grids(st, p);
    repulsion_step(st, grids, p, x_new, sigma_new);
    st.x.swap(x_new);
    st.sigma.swap(sigma_new);
    project_step(s, st, p, it + 1 == iterations);
  }
}

}  // namespace mpumesh::particles
