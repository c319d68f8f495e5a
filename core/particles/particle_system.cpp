#include "particles/particle_system.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "common/error.h"
#include "common/option_names.h"
#include "common/hash.h"
#include "common/kd_tree.h"
#include "compute/compute_backend.h"
#include "particles/particle_order.h"
#include "particles/sampler.h"

namespace mpumesh::particles {

StepParams batch_params(const StepParams& step, const ParticleState& st) {
  StepParams p = step;
  p.sigma_cap = 0;
  for (size_t i = 0; i < st.size(); ++i) p.sigma_cap = std::max({p.sigma_cap, st.sigma[i], 2 * st.target[i]});
  return p;
}

double hash01(uint32_t index, uint32_t iteration, uint32_t seed, uint32_t salt) {
  const uint32_t h = fmix32(fmix32(index * 0x9E3779B1u + salt) ^ fmix32(iteration * 0x85ebca6bu + seed));
  return double(h >> 8) * (1.0 / 16777216.0);
}

void validate(const SampleOptions& o) {
  auto need = [&](bool ok, const char* name, const std::string& what) {
    if (!ok) throw InputError(option_ref(name) + " must be " + what);
  };
  need(o.particles >= 0 && o.particles <= 100'000'000, "particles",
       "between 1 and 10^8 (0: from " + option_ref("particle_spacing") + ")");
  need(std::isfinite(o.spacing) && o.spacing >= 0, "particle_spacing", "positive (mm)");
  need(std::isfinite(o.curvature_scale) && o.curvature_scale >= 0 && o.curvature_scale <= 5, "curvature_scale",
       "between 0 (uniform) and 5");
  need(std::isfinite(o.thickness_factor) && o.thickness_factor > 0, "thickness_factor", "positive");
  need(std::isfinite(o.spacing_grade) && o.spacing_grade >= 0 && o.spacing_grade <= 10, "spacing_grade",
       "between 0 (ungraded) and 10");
  need(o.iterations >= 1 && o.iterations <= 100000, "particle_iterations", "between 1 and 100000");
  need(o.population_every >= 1, "population_every", "at least 1");
}

std::vector<uint8_t> decide_population(const ParticleState& st, const SampleOptions& opt, int iteration,
                                       int64_t cap) {
  std::vector<uint8_t> fate(st.size(), kKeep);
  int64_t room = cap - int64_t(st.size());
  for (size_t i = 0; i < st.size(); ++i) {
    if (!std::isfinite(st.distance[i])) {
      fate[i] = kDie;
      continue;
    }
    const bool eq = st.speed[i] < opt.step.gamma * st.sigma[i];
    const bool on = std::abs(st.distance[i]) < 0.1 * st.sigma[i];
    if (!eq || !on) continue;
    if (st.sigma[i] > opt.split_ratio * st.target[i] && room > 0) {
      fate[i] = kSplit;
      --room;
    } else if (st.sigma[i] < opt.death_ratio * st.target[i]) {
      const double p = 1 - st.sigma[i] / (opt.death_ratio * st.target[i]);
      if (hash01(uint32_t(i), uint32_t(iteration), opt.seed, 2) < p) fate[i] = kDie;
    }
  }
  return fate;
}

std::vector<Eigen::Vector3d> leaf_candidates(const mpu::MpuSurface& s) {
  std::vector<Eigen::Vector3d> c;
  for (const auto& l : s.leaves)
    if (l.points > 0) c.push_back(l.centre);
  return c;
}

void check_finite(const ParticleState& st, int iteration, const std::string& device) {
  size_t bad = 0;
  for (size_t i = 0; i < st.size(); ++i)
    // Curvature is NaN only when the evaluation gave NaN (a lost particle, with ∇f = 0,
    // gets zeros there and a NaN distance, and is removed as lost).
    bad += !(st.x[i].allFinite() && std::isfinite(st.sigma[i]) && st.sigma[i] > 0 && std::isfinite(st.energy[i]) &&
             std::isfinite(st.curv[i].gauss));
  if (bad)
    throw NumericalError("particles: " + std::to_string(bad) + " of " + std::to_string(st.size()) +
                         " particles have a non-finite position, size or energy after iteration " +
                         std::to_string(iteration) + " on " + device +
                         " (the surface or a kernel produced NaN); nothing was written");
}

// Each particle's target from the sizing field where it now is.
void Sampler::update_targets() {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, st.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) st.target[i] = target_field->at(st.x[i], st.normal[i]) / kSpacingPerSigma;
  });
}

// Splits and deaths, decided on the state as it is; the next population in index order.
void Sampler::update_population(int it, PopulationRecord& rec) {
  // Decide on the state as it is, then build the next population in index order:
  // survivors (a splitting parent moved to one side), then the second children.
  std::vector<uint8_t> fate = decide_population(st, opt, it, cap);
  for (size_t i = 0; i < st.size(); ++i)
    if (fate[i] != kDie && !support->near(st.x[i])) {
      fate[i] = kDie;
      ++stats.off_data;
    }
  ParticleState next;
  auto push = [&](size_t i, const Eigen::Vector3d& x, double sigma) {
    next.x.push_back(x);
    next.sigma.push_back(sigma);
    next.target.push_back(st.target[i]);
    next.normal.push_back(st.normal[i]);
    next.distance.push_back(st.distance[i]);
    next.curv.push_back(st.curv[i]);
    next.energy.push_back(st.energy[i]);
    next.speed.push_back(st.speed[i]);
  };
  std::vector<Eigen::Vector3d> offset(st.size(), Eigen::Vector3d::Zero());
  for (size_t i = 0; i < st.size(); ++i) {
    if (fate[i] == kDie) {
      ++rec.deaths;
      continue;
    }
    const bool split = fate[i] == kSplit;
    if (split) offset[i] = 0.5 * st.sigma[i] * tangent(st.normal[i], hash01(uint32_t(i), uint32_t(it), opt.seed, 1));
    push(i, st.x[i] - offset[i], split ? st.sigma[i] / std::sqrt(2.0) : st.sigma[i]);
  }
  for (size_t i = 0; i < st.size(); ++i)
    if (fate[i] == kSplit) {
      push(i, st.x[i] + offset[i], st.sigma[i] / std::sqrt(2.0));
      ++rec.births;
    }
  st = std::move(next);
  order_spatially(st);
  stats.births += rec.births;
  stats.deaths += rec.deaths;
}

void Sampler::iterate() {
  // 4. Iterate; between batches update the weights and targets, split and kill.
  int it = 0, quiet_updates = 0;
  bool final_batch = false;  // settled: one more batch to relax, without population changes
  while (it < opt.iterations) {
    const int batch = std::min(opt.population_every, opt.iterations - it);
    final_batch = final_batch || it + batch >= opt.iterations;
    const auto t_iter = Clock::now();
    backend.particle_iterations(s, st, batch_params(opt.step, st), batch);
    it += batch;
    tell(progress, double(it) / opt.iterations);
    check_finite(st, it, backend.device());
    stats.seconds_iterate += seconds_since(t_iter);
    const auto t_pop = Clock::now();
    // New targets for the next batch where the particles moved (none follows the final
    // one); children take their parent's (below).
    if (!final_batch) update_targets();

    PopulationRecord rec;
    rec.iteration = it;
    double move = 0, energy = 0;
    for (size_t i = 0; i < st.size(); ++i) {
      move += std::min(opt.step.dt * st.speed[i] / st.sigma[i], opt.step.max_move);
      energy += st.energy[i];
    }
    rec.mean_energy = energy / double(std::max<size_t>(st.size(), 1));
    rec.mean_move = move / double(std::max<size_t>(st.size(), 1));
    if (!final_batch) {
      update_population(it, rec);
    }
    rec.count = int64_t(st.size());
    stats.history.push_back(rec);
    stats.seconds_population += seconds_since(t_pop);
    if (st.size() == 0) throw InputError("sample: every particle left the surface");
    // Settled: for two updates in a row the population's size changed by at most 1.5%
    // and the particles moved less than 12% of their radius per iteration on average.
    // (Births and deaths need not stop: the seeds' Poisson-disk sample leaves holes of up
    // to twice its radius, which fission fills slowly, by about 1% of the count per
    // update on the sample CT.) The mesh optimisation finishes what the particles leave,
    // so the bounds are set where more iterations no longer improve the final mesh's
    // shapes by more than a few thousandths of radius ratio.
    const double change = double(std::abs(rec.births - rec.deaths));
    const bool settled = change <= std::max(1.0, kSettledCount * double(st.size())) && rec.mean_move < kSettledMove;
    if (final_batch) break;
    quiet_updates = settled ? quiet_updates + 1 : 0;
    if (it >= opt.min_iterations && quiet_updates >= 2) {
      stats.converged = true;
      final_batch = true;
    }
  }
  stats.iterations = it;
}

void Sampler::finish() {
  // Those that left the data in the final batch go; for the others, which bound sets
  // their spacing: the local thickness or the curvature (the thickness field, above half).
  // (Both loops in parallel, and the two fields read from one search.)
  std::vector<uint8_t> near(st.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, st.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) near[i] = support->near(st.x[i]);
  });
  std::vector<size_t> rows;
  for (size_t i = 0; i < st.size(); ++i)
    if (near[i]) rows.push_back(i);
  stats.off_data += int64_t(st.size() - rows.size());
  if (rows.size() < st.size()) keep_rows(st, rows);
  stats.spacing_by_thickness.resize(st.size());
  stats.gauss_at_scale.resize(st.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, st.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const auto [by_thickness, gauss] = thickness_field->at_with(*gauss_field, st.x[i], st.normal[i]);
      stats.spacing_by_thickness[i] = by_thickness > 0.5;
      stats.gauss_at_scale[i] = gauss;
    }
  });
  stats.thickness_bound = std::count(stats.spacing_by_thickness.begin(), stats.spacing_by_thickness.end(), uint8_t(1));
  stats.particles = int64_t(st.size());
}


ParticleState sample_surface(const mpu::MpuSurface& s, const std::vector<Eigen::Vector3d>& candidates,
                             const SampleOptions& opt_in, ComputeBackend& backend, SampleStats* stats_out,
                             const KdTree* candidate_index, const SampleSource& source,
                             const ProgressFn& progress) {
  validate(opt_in);
  SampleStats st_local;
  SampleStats& stats = stats_out ? *stats_out : st_local;
  stats = SampleStats{};
  Sampler sampler(s, candidates, candidate_index, opt_in, source, backend, stats);
  sampler.progress = progress;
  SampleOptions& opt = sampler.opt;
  sampler.by_default = opt.particles == 0 && opt.spacing == 0;
  if (sampler.by_default) opt.particles = kDefaultParticles;
  sampler.t_seed = Clock::now();
  if (candidates.size() < 4) throw InputError("sample: fewer than 4 candidate points to seed the particles from");
  stats.candidates = int64_t(candidates.size());
  sampler.make_pool();
  sampler.measure_area();
  sampler.solve_spacing();
  sampler.seed();
  sampler.iterate();
  sampler.finish();
  tell(progress, 1);
  return std::move(sampler.st);
}

}  // namespace mpumesh::particles

