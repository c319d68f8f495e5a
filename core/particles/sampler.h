// One sampling's state, private to the files of the particle system
// (particles/particle_system.cpp, particles/seeding.cpp): the pool and its area, the
// weights and the flat spacing, the seeds, the iterations, the final checks.
#pragma once

#include <chrono>
#include <memory>
#include <vector>

#include "common/kd_tree.h"
#include "common/progress_fn.h"
#include "compute/compute_backend.h"
#include "particles/data_support.h"
#include "particles/particle_system.h"
#include "particles/sizing_field.h"
#include "particles/spacing_targets.h"

namespace mpumesh::particles {

using Clock = std::chrono::steady_clock;
inline double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

inline const double kSpacingPerSigma = spacing_per_sigma();
// Area per point of a maximal Poisson-disk sample of radius r (random order, 2D): 1.436 r²;
// of a hexagonal sample of spacing s: 0.866 s². So a Poisson-disk radius of s / 1.29
// gives about the density of spacing s.
constexpr double kHexArea = 0.8660254, kDiskPerSpacing = 0.7766;


// The population's cap over the count the targets ask for (Sampler::seed).
constexpr double kCountSlack = 1.05;
// Settled below this mean move per iteration, in particle radii (Sampler::iterate).
constexpr double kSettledMove = 0.12;
// Settled when the count also changed by at most this fraction per update.
constexpr double kSettledCount = 0.015;

// One sampling's state, built up by its steps in order: the pool and its area, the
// weights and the flat spacing, the seeds, the iterations, the final checks.
struct Sampler {
  Sampler(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& candidates, const KdTree* candidate_index,
          const SampleOptions& opt, const SampleSource& source, ComputeBackend& backend, SampleStats& stats)
      : s(s),
        candidates(candidates),
        candidate_index(candidate_index),
        opt(opt),
        source(source),
        backend(backend),
        stats(stats) {}
  const mpu::MpuSurface& s;
  const std::vector<Eigen::Vector3d>& candidates;
  const KdTree* candidate_index;  // or null
  SampleOptions opt;
  SampleSource source;
  ComputeBackend& backend;
  SampleStats& stats;
  ProgressFn progress;  // told the iterations done over the cap after each batch
  bool by_default = false;
  Clock::time_point t_seed;
  double extent = 0, gap = 0, r_pool = 0;
  double bend_floor = 0;  // the bend bound's floor (SampleOptions::normal_turn)
  std::unique_ptr<DataSupport> support;
  ParticleState pool;
  // Per pool point: its area, its K and larger principal |κ| (from the blended Hessian,
  // then at the sampling's scale: sizing_field.h), weight, thickness and target.
  std::vector<double> cell_area, gauss, kappa, lambda, thick;
  // The reach `thick` was measured to, the same at every pool point (0: per point).
  double thick_reach = 0;
  double h = 0;
  Targets tg;
  // The targets (and where the thickness sets them) as fields over the surface, for the
  // particles (sizing_field.h).
  // Over pool.x, which stays as make_pool leaves it: for the area, the three fields and
  // the seeds' nearest pool points.
  std::unique_ptr<PointIndex> pool_index;
  std::unique_ptr<SizingField> target_field, thickness_field, gauss_field;
  std::vector<size_t> fine_keep;  // the candidates in the seeds' Poisson disk (make_pool)
  std::vector<Eigen::Vector3d> fine;
  std::vector<uint32_t> fine_pool;  // nearest pool point
  std::vector<double> radius;
  std::vector<size_t> seeds;
  ParticleState st;
  int64_t cap = 0;
  double field_count = 0;  // the particles the targets ask for over the pool's area

  // A point pulled onto f = 0 counts when it got there (within 1e-3 r_pool) near where it
  // started (within 2 r_pool).
  bool reached_surface(const ParticleState& p, size_t k, const Eigen::Vector3d& start) const {
    return std::abs(p.distance[k]) < 1e-3 * r_pool && (p.x[k] - start).norm() <= 2 * r_pool;
  }
  void make_pool();
  void measure_area();
  void pool_curvature();
  // The flat spacing h (below); h_ref, the flat spacing at which the bend bound holds as
  // set (SampleOptions::normal_turn): kDefaultFlatVoxels voxels, or for a surface not
  // from a volume the flat spacing its count asks for without the bound.
  double solve_flat_spacing(const std::vector<double>& kappa_bound);
  // `thick` measured out to reach × λ_i at each pool point (`weights` λ), or out to
  // reach at every one (null); `thick_reach` follows.
  void measure_thickness(const std::vector<double>* weights, double reach);
  double h_ref = 0;
  void solve_spacing();
  void seed();
  void seed_targets();
  void fine_candidates();
  void draw_seeds();
  void place_seeds();
  void iterate();
  void update_targets();
  void update_population(int it, PopulationRecord& rec);
  void finish();
};

}  // namespace mpumesh::particles
