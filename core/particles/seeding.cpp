// The seeding of the particle system (particles/particle_system.h): the pool of surface
// points with their area, curvature and thickness, the spacing targets and the flat
// spacing that asks for the count, and the seeds drawn at the targets' density.
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <cmath>

#include "common/error.h"
#include "particles/particle_order.h"
#include "particles/poisson_disk.h"
#include "particles/sampler.h"
#include "particles/spacing_stats.h"

namespace mpumesh::particles {

void Sampler::make_pool() {
  extent = (s.data_max - s.data_min).maxCoeff();
  // 1. A pool: a Poisson-disk subset of the candidates at about their largest sampling
  //    gap (so that it covers the surface without holes between CT slices), on f = 0.
  std::unique_ptr<PointIndex> own;
  const KdTree& tree = given_or_built(candidate_index, candidates, own);
  gap = source.candidate_gap > 0        ? source.candidate_gap
        : candidates.size() > 13 ? median_spacing(candidates, tree, 12)
                                 : extent / 50;
  r_pool = std::max(gap, extent / 400);
  bend_floor = source.voxel_size > 0 ? kMinBendVoxels * source.voxel_size : gap;
  if (opt.spacing > 0) r_pool = std::min(r_pool, std::max(opt.spacing * kDiskPerSpacing, extent / 400));
  // Three independent serial steps over the candidates, run side by side: the pool's
  // Poisson disk; the finer one the
  // seeds are drawn from (see seed); the data support, which removes particles farther
  // than 4 r_pool from every candidate, off the data on a spurious sheet of f
  // (particles/data_support.h).
  std::vector<size_t> keep;
  tbb::parallel_invoke(
      [&] {
        keep = poisson_disk(candidates, std::vector<double>(candidates.size(), r_pool),
                            hashed_order(candidates.size(), opt.seed));
      },
      [&] {
        fine_keep = poisson_disk(candidates, std::vector<double>(candidates.size(), 0.5 * r_pool),
                                 hashed_order(candidates.size(), opt.seed + 2));
      },
      [&] { support = std::make_unique<DataSupport>(candidates, 4 * r_pool); });
  {
    {  // in space order, for the cache (see order_spatially)
      std::vector<Eigen::Vector3d> at(keep.size());
      for (size_t k = 0; k < keep.size(); ++k) at[k] = candidates[keep[k]];
      const std::vector<size_t> order = morton_order(at);
      std::vector<size_t> sorted(keep.size());
      for (size_t k = 0; k < keep.size(); ++k) sorted[k] = keep[order[k]];
      keep.swap(sorted);
    }
    pool.resize(keep.size());
    for (size_t k = 0; k < keep.size(); ++k) {
      pool.x[k] = candidates[keep[k]];
      pool.sigma[k] = r_pool;
    }
    StepParams proj = opt.step;
    proj.newton_steps = 8;
    backend.particle_project(s, pool, proj, false);
    check_finite(pool, 0, backend.device() + " (seeding)");
    // Keep those that reached the surface near where they started.
    std::vector<size_t> reached;
    for (size_t k = 0; k < pool.size(); ++k)
      if (reached_surface(pool, k, candidates[keep[k]])) reached.push_back(k);
    keep_rows(pool, reached);
  }
  if (pool.size() < 4) throw InputError("sample: the candidate points do not lie on the surface (fewer than 4 reached f = 0)");
  stats.pool = int64_t(pool.size());
  pool_index = std::make_unique<PointIndex>(pool.x);
}

void Sampler::measure_area() {
  // Area: each pool point stands for the hexagon of its local spacing d6 (mean distance
  // to 6 neighbours), divided by 1.067: on the fitted sphere and ellipsoid Σ 0.866 d6²
  // came out 6.6% and 6.7% above the true area. (With that, 5,025 vs 5,027 mm² and
  // 4,892 vs 4,896 mm².)
  const std::vector<double> pool_d6 = local_spacing(pool.x, 1, &pool_index->tree);
  cell_area.resize(pool.size());
  for (size_t i = 0; i < pool.size(); ++i) {
    cell_area[i] = kHexArea / 1.067 * pool_d6[i] * pool_d6[i];
    stats.area += cell_area[i];
  }
  if (opt.spacing == 0) stats.asked = opt.particles;
}

// The pool's curvature from the blended Hessian (the surface's own curvature, which the
// mesh carries): the Hessian of f that the particles' steps measure adds the weights'
// derivatives times the leaves' disagreement.
void Sampler::pool_curvature() {
  const std::vector<mpu::EvalRow> rows = backend.mpu_eval(s, pool.x);
  gauss.resize(pool.size());
  kappa.resize(pool.size());
  for (size_t i = 0; i < pool.size(); ++i) {
    gauss[i] = std::isfinite(rows[i].gauss) ? rows[i].gauss : 0.0;
    kappa[i] = std::isfinite(rows[i].k1) && std::isfinite(rows[i].k2) ? std::max(std::abs(rows[i].k1), std::abs(rows[i].k2)) : 0.0;
  }
}

void Sampler::measure_thickness(const std::vector<double>* weights, double reach) {
  thick = thicknesses(backend, s, pool, weights ? *weights : std::vector<double>(pool.size(), 1.0), reach);
  thick_reach = weights ? 0.0 : reach;
}

// The flat spacing h whose targets ask for opt.particles (bisection; the count falls as h
// grows, the bend bound scaled by h / h_ref with it), with the thickness measured up to the
// largest h tried; or opt.spacing; or, by default from a volume, h_ref.
double Sampler::solve_flat_spacing(const std::vector<double>& kappa_bound) {
  auto count_for = [&](double hh) {
    const Targets t = spacing_targets(lambda, thick, kappa_bound, hh, bend_floor, hh / h_ref, opt);
    double n = 0;
    for (size_t i = 0; i < pool.size(); ++i) n += cell_area[i] / (kHexArea * t.spacing[i] * t.spacing[i]);
    return n;
  };
  const double fixed = opt.spacing > 0                     ? opt.spacing
                       : by_default && source.voxel_size > 0 ? kDefaultFlatVoxels * source.voxel_size
                                                          : 0.0;
  if (fixed > 0) {
    measure_thickness(&lambda, fixed / opt.thickness_factor);
    return fixed;
  }
  double inv = 0;
  for (size_t i = 0; i < pool.size(); ++i) inv += cell_area[i] / (lambda[i] * lambda[i]);
  const double h0 = std::sqrt(inv / (kHexArea * double(opt.particles)));
  // count_for(h0) >= particles; without the bend bound at most exp(2S) times that (the
  // floor), with it more; bisect.
  double hmax = h0 * std::exp(opt.curvature_scale);
  // A thickness measured as far already serves: one beyond hmax never bounds a target
  // (spacing_targets). The second solve's hmax is the first's within a fraction of a
  // percent (the curvature averaged over patches moves h0 little), so the search runs
  // once.
  if (!(thick_reach >= hmax / opt.thickness_factor)) measure_thickness(nullptr, hmax / opt.thickness_factor);
  for (int grow = 0; grow < 20 && count_for(hmax) > double(opt.particles); ++grow) hmax *= 2;
  double a = h0, b = hmax;
  if (count_for(b) > double(opt.particles)) a = b;
  for (int it = 0; it < 40 && b > a * (1 + 1e-6); ++it) {
    const double m = 0.5 * (a + b);
    (count_for(m) > double(opt.particles) ? a : b) = m;
  }
  double hh = a == b ? a : 0.5 * (a + b);
  // The default count never asks for a flat spacing finer than half the input's
  // sampling gap: that would only add particles on detail the data do not hold.
  if (by_default && hh < 0.5 * gap) {
    hh = 0.5 * gap;
    measure_thickness(&lambda, hh / opt.thickness_factor);
  }
  return hh;
}

void Sampler::solve_spacing() {
  // 2. Curvature, weights, thickness and the flat spacing h (from --spacing, or solved so
  //    that the pool's area elements add up to the wanted count): first from the
  //    curvature at each pool point, then again from the curvature averaged over the
  //    patch that one sample of the spacing so found stands for (sizing_field.h).
  pool_curvature();
  const std::vector<double> no_bound(pool.size(), 0.0);
  lambda = curvature_weights(gauss, opt.curvature_scale, stats.kappa_lo, stats.kappa_hi);
  h_ref = source.voxel_size > 0 ? kDefaultFlatVoxels * source.voxel_size : 1.0;
  h = solve_flat_spacing(no_bound);
  if (!(source.voxel_size > 0)) h_ref = h;
  {
    const Targets first = spacing_targets(lambda, thick, no_bound, h, bend_floor, 1.0, opt);
    std::vector<double> patch(pool.size());
    for (size_t i = 0; i < pool.size(); ++i) patch[i] = std::max(first.spacing[i], r_pool);
    average_over_patches(pool.x, pool.normal, cell_area, patch, gauss, kappa);
  }
  lambda = curvature_weights(gauss, opt.curvature_scale, stats.kappa_lo, stats.kappa_hi);
  // The bend bound asks for particles wherever the surface bends; a count asked for has
  // none to spare (the bound would take them from a bone's thin plates, which the
  // triangulation then repairs with poor triangles), so it holds where the count follows
  // the spacing: by default from a volume, and with a spacing given.
  if (opt.particles > 0 && !(by_default && source.voxel_size > 0)) std::fill(kappa.begin(), kappa.end(), 0.0);
  h = solve_flat_spacing(kappa);
}

// 3. Seeds, drawn at the targets' density from the candidates themselves: the pool, at
//    the input's largest sampling gap, is coarser than the targets where they are fine,
//    and seeded from it the particles would start far below their count and take many
//    iterations to fill it. A Poisson-disk subset of the candidates at half the pool's
//    radius ("fine"), each point taking the target and thickness of its nearest pool
//    point, is thinned to a Poisson-disk subset at each point's target spacing. The
//    disk-to-spacing factor of an ideal sample (1 / 1.29) is only a start (the points are
//    discrete), so it is corrected a few times until the seeds are as many as the
//    targets ask for: the particles start at their count, and fission and death only
//    adapt them. Only the seeds are then pulled onto f = 0.
void Sampler::seed() {
  seed_targets();
  fine_candidates();
  draw_seeds();
  stats.spacing = h;
  place_seeds();
  order_spatially(st);
  stats.seeds = int64_t(st.size());
  check_finite(st, 0, "the CPU (seeding)");
  // Fission stops at 5% above the count the targets ask for: the population settles
  // anywhere between death (σ under 0.7 of its target) and fission (over 1.25 of it), and
  // fission fills the seeds' holes with pairs, so without a cap it drifts above that count.
  cap = opt.max_particles > 0 ? opt.max_particles : std::llround(kCountSlack * field_count);
  stats.seconds_seed = seconds_since(t_seed);
}

// The targets, graded over the pool (whose neighbours are linked within two pool
// spacings), the count they ask for, and the fields the particles read.
void Sampler::seed_targets() {
  tg = spacing_targets(lambda, thick, kappa, h, bend_floor, h / h_ref, opt);
  grade_targets(pool.x, cell_area, tg, opt, 2 * r_pool);
  double n = 0;
  for (size_t i = 0; i < pool.size(); ++i) n += cell_area[i] / (kHexArea * tg.spacing[i] * tg.spacing[i]);
  field_count = n;
  if (by_default && source.voxel_size > 0) stats.asked = std::llround(n);
  target_field = std::make_unique<SizingField>(pool.x, pool.normal, tg.spacing, &pool_index->tree);
  gauss_field = std::make_unique<SizingField>(pool.x, pool.normal, gauss, &pool_index->tree);
  thickness_field = std::make_unique<SizingField>(pool.x, pool.normal, tg.by_thickness, &pool_index->tree);
}

// The fine candidates (make_pool's second Poisson disk) and each one's nearest pool point.
void Sampler::fine_candidates() {
  const std::vector<size_t>& keep = fine_keep;
  fine.resize(keep.size());
  fine_pool.resize(keep.size());
  const KdTree& pool_tree = pool_index->tree;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, keep.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      fine[k] = candidates[keep[k]];
      uint32_t idx = 0;
      double d2 = 0;
      nanoflann::KNNResultSet<double, uint32_t> rs(1);
      rs.init(&idx, &d2);
      pool_tree.findNeighbors(rs, fine[k].data(), nanoflann::SearchParams());
      fine_pool[k] = idx;
    }
  });
}

// The seeds: a Poisson-disk subset of the fine candidates at their targets, its
// disk-to-spacing factor corrected until they are as many as the targets ask for.
void Sampler::draw_seeds() {
  radius.resize(fine.size());
  const std::vector<uint32_t> seed_order = hashed_order(fine.size(), opt.seed + 1);
  auto seed_with = [&](double c) {
    for (size_t k = 0; k < fine.size(); ++k) radius[k] = c * tg.spacing[fine_pool[k]];
    return poisson_disk(fine, radius, seed_order);
  };
  double c = kDiskPerSpacing;
  seeds = seed_with(c);
  for (int round = 0; round < 5 && seeds.size() >= 7; ++round) {
    const double f = std::sqrt(double(seeds.size()) / field_count);
    if (std::abs(f - 1) < 0.01) break;
    c *= f;
    seeds = seed_with(c);
  }
}

// The seeds as particles on f = 0: pulled there, those that reached the surface near where
// they started kept (as the pool's), and of those a Poisson-disk subset at the same radii
// on the surface: candidates off the surface (leaf centres) or on CT slices' contours only
// land close together there.
void Sampler::place_seeds() {
  st.resize(seeds.size());
  std::vector<Eigen::Vector3d> start(seeds.size());
  for (size_t k = 0; k < seeds.size(); ++k) {
    start[k] = fine[seeds[k]];
    if (source.slice_spacing > 0)
      start[k] += (hash01(uint32_t(k), 0, opt.seed, 4) - 0.5) * source.slice_spacing * source.slice_axis;
    st.x[k] = start[k];
    st.target[k] = tg.spacing[fine_pool[seeds[k]]] / kSpacingPerSigma;
    st.sigma[k] = st.target[k];
  }
  StepParams proj = opt.step;
  proj.newton_steps = 8;
  backend.particle_project(s, st, proj, false);
  check_finite(st, 0, backend.device() + " (seeding)");
  std::vector<size_t> reached;
  std::vector<Eigen::Vector3d> at;
  std::vector<double> r;
  for (size_t k = 0; k < st.size(); ++k) {
    if (!reached_surface(st, k, start[k])) continue;
    reached.push_back(k);
    at.push_back(st.x[k]);
    r.push_back(radius[seeds[k]]);
  }
  std::vector<size_t> rows;
  if (!at.empty())
    for (size_t j : poisson_disk(at, r, hashed_order(at.size(), opt.seed + 3))) rows.push_back(reached[j]);
  keep_rows(st, rows);
  if (st.size() < 4) throw InputError("sample: fewer than 4 seeds reached the surface f = 0");
}

}  // namespace mpumesh::particles
