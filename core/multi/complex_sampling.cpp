#include "multi/complex_sampling.h"

#include <algorithm>
#include <chrono>
#include <numeric>

#include "common/kd_tree.h"
#include "compute/compute_backend.h"

namespace mpumesh::multi {
namespace {

// Junction points are thinned to this many spacings, and their curves' gaps filled to
// about as many (below about 0.6 of the interface particles' distance from them, the
// restricted Delaunay triangulation's junction edges run through the interface particles
// beside the curve instead); interface seeds dropped this near a junction point or
// another sampling's seed.
constexpr double kJunctionThin = 0.6;
// The spacing along a junction curve its gaps are filled to, and the most rounds of it.
constexpr double kJunctionSpacing = 0.6;
constexpr int kFillRounds = 6;
constexpr double kMergeRadius = 0.6;

using Matches = std::vector<std::pair<uint32_t, double>>;

void within(const KdTree& tree, const Eigen::Vector3d& q, double r, Matches& out) {
  out.clear();
  tree.radiusSearch(q.data(), r * r, out, nanoflann::SearchParams(32, 0, false));
}

// The region whose sampling covers interface (a, b), a < b: the label's own for the
// background's interfaces, the lower label's between two labels.
int covering_source(int a, int b) { return a == 0 ? b : a; }

// One step for every particle of `in` on the backend (the relaxations with their
// neighbours found first).
ComplexBatch run_step(ComputeBackend& backend, const MaterialField& field, ComplexStep step,
                      std::vector<ComplexParticle> in) {
  ComplexBatch b;
  b.step = step;
  b.in = std::move(in);
  if (step == ComplexStep::kRelaxJunction || step == ComplexStep::kRelaxInterface) find_neighbours(b);
  backend.complex_steps(field, b);
  return b;
}

struct Projected {
  ComplexParticle particle;
  int source = 0;
};

// Step 1: every seed onto its interface; those of an interface another sampling covers
// are left out.
std::vector<Projected> project_seeds(ComputeBackend& backend, const MaterialField& field,
                                     const std::vector<Seed>& seeds, ComplexSampleStats& st) {
  std::vector<ComplexParticle> in(seeds.size());
  for (size_t i = 0; i < seeds.size(); ++i) {
    in[i].p = seeds[i].p;
    in[i].spacing = seeds[i].spacing;
  }
  const ComplexBatch b = run_step(backend, field, ComplexStep::kOntoInterface, std::move(in));
  std::vector<Projected> kept;
  for (size_t i = 0; i < seeds.size(); ++i) {
    if (!b.ok[i]) {
      ++st.off_interface;
    } else if (covering_source(b.out[i].regions[0], b.out[i].regions[1]) != seeds[i].source) {
      ++st.other_source;
    } else {
      kept.push_back({b.out[i], seeds[i].source});
    }
  }
  return kept;
}

// Step 2a: the junction (or corner) point nearest each interface particle whose third
// region is within the band.
std::vector<ComplexParticle> junction_candidates(ComputeBackend& backend, const MaterialField& field,
                                                 const std::vector<Projected>& iface) {
  if (field.regions() < 3) return {};
  std::vector<ComplexParticle> in;
  for (const Projected& q : iface) in.push_back(q.particle);
  const ComplexBatch b = run_step(backend, field, ComplexStep::kJunctionCandidate, std::move(in));
  std::vector<ComplexParticle> out;
  for (size_t i = 0; i < b.out.size(); ++i)
    if (b.ok[i]) out.push_back(b.out[i]);
  return out;
}

// The first `held` of `pts` and, in order, each other with none kept within `radius`
// spacings.
std::vector<ComplexParticle> keep_apart(std::vector<ComplexParticle> pts, size_t held, double radius) {
  std::vector<Eigen::Vector3d> pos(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) pos[i] = pts[i].p;
  if (pts.empty()) return pts;
  const PointIndex index(pos);
  std::vector<char> kept(pts.size(), 0);
  std::fill(kept.begin(), kept.begin() + ptrdiff_t(held), 1);
  std::vector<ComplexParticle> out(pts.begin(), pts.begin() + ptrdiff_t(held));
  Matches m;
  for (size_t i = held; i < pts.size(); ++i) {
    within(index.tree, pos[i], radius * pts[i].spacing, m);
    bool clash = false;
    for (const auto& [j, d2] : m) clash = clash || kept[j];
    if (clash) continue;
    kept[i] = 1;
    out.push_back(pts[i]);
  }
  return out;
}

// Keeps, in order, each particle with no kept one within `radius` spacings (corners
// before junction points).
std::vector<ComplexParticle> thin(std::vector<ComplexParticle> pts, double radius) {
  std::stable_sort(pts.begin(), pts.end(), [](const ComplexParticle& a, const ComplexParticle& b) {
    if (a.kind != b.kind) return a.kind > b.kind;
    if (a.regions != b.regions) return a.regions < b.regions;
    return std::lexicographical_compare(a.p.data(), a.p.data() + 3, b.p.data(), b.p.data() + 3);
  });
  return keep_apart(std::move(pts), 0, radius);
}

// Step 2b: junction points spread along their curves, corners held.
void relax_junctions(ComputeBackend& backend, const MaterialField& field, std::vector<ComplexParticle>& jp,
                     int iterations) {
  for (int it = 0; it < iterations && !jp.empty(); ++it)
    jp = run_step(backend, field, ComplexStep::kRelaxJunction, std::move(jp)).out;
}

// Where a junction particle's curve runs on with no other of its particles within two
// junction spacings: one junction spacing along it, the direction taken from its nearest
// particle on the curve (towards it where that one is farther than two spacings, and
// away from it where no particle lies within two spacings on the other side). None for
// a particle alone on its curve or a corner.
std::vector<ComplexParticle> gap_candidates(const std::vector<ComplexParticle>& jp) {
  std::vector<ComplexParticle> out;
  if (jp.size() < 2) return out;
  std::vector<Eigen::Vector3d> pos(jp.size());
  for (size_t i = 0; i < jp.size(); ++i) pos[i] = jp[i].p;
  const PointIndex index(pos);
  Matches m;
  for (size_t i = 0; i < jp.size(); ++i) {
    const ComplexParticle& q = jp[i];
    if (q.kind != ParticleKind::kJunction) continue;
    const double h = kJunctionSpacing * q.spacing;
    within(index.tree, q.p, 4 * h, m);
    // The nearest particle of the same curve, and whether one lies within two spacings
    // on each side of q along the direction to it.
    size_t nearest = i;
    double best = INFINITY;
    for (const auto& [j, d2] : m)
      if (j != i && jp[j].regions == q.regions && d2 < best) best = d2, nearest = j;
    if (nearest == i) continue;
    const Eigen::Vector3d t = (jp[nearest].p - q.p).normalized();
    bool ahead = false, behind = false;
    for (const auto& [j, d2] : m) {
      if (j == i || jp[j].regions != q.regions || d2 > 4 * h * h) continue;
      (t.dot(jp[j].p - q.p) > 0 ? ahead : behind) = true;
    }
    for (const double side : {1.0, -1.0}) {
      if (side > 0 ? ahead : behind) continue;
      ComplexParticle c = q;
      c.p = q.p + side * h * t;
      c.kind = ParticleKind::kInterface;
      out.push_back(c);
    }
  }
  return out;
}

// Step 2c: the junction curves' gaps filled, in rounds: each gap's candidates
// (gap_candidates) taken onto their curve by the junction step, kept where no junction
// particle is within the thinning radius, then all spread along their curves again.
void fill_junction_gaps(ComputeBackend& backend, const MaterialField& field, std::vector<ComplexParticle>& jp,
                        int relax_iterations) {
  for (int round = 0; round < kFillRounds; ++round) {
    std::vector<ComplexParticle> cand = gap_candidates(jp);
    if (cand.empty()) return;
    const ComplexBatch b = run_step(backend, field, ComplexStep::kJunctionCandidate, std::move(cand));
    const size_t before = jp.size();
    std::vector<ComplexParticle> grown = jp;
    for (size_t i = 0; i < b.out.size(); ++i)
      if (b.ok[i] && b.out[i].kind == ParticleKind::kJunction) grown.push_back(b.out[i]);
    jp = keep_apart(std::move(grown), before, kJunctionThin);
    if (jp.size() == before) return;
    relax_junctions(backend, field, jp, relax_iterations);
  }
}

// Step 3a: interface particles near a junction point or another sampling's kept particle
// dropped, in order (the samplings in source order).
std::vector<ComplexParticle> merge(const std::vector<ComplexParticle>& held, std::vector<Projected> iface,
                                   ComplexSampleStats& st) {
  std::stable_sort(iface.begin(), iface.end(), [](const Projected& a, const Projected& b) { return a.source < b.source; });
  std::vector<Eigen::Vector3d> pos;
  std::vector<int> source;
  for (const ComplexParticle& h : held) {
    pos.push_back(h.p);
    source.push_back(-1);
  }
  for (const Projected& q : iface) {
    pos.push_back(q.particle.p);
    source.push_back(q.source);
  }
  std::vector<ComplexParticle> out = held;
  if (pos.empty()) return out;
  const PointIndex index(pos);
  std::vector<char> kept(pos.size(), 0);
  std::fill(kept.begin(), kept.begin() + ptrdiff_t(held.size()), 1);
  Matches m;
  for (size_t k = 0; k < iface.size(); ++k) {
    const size_t i = held.size() + k;
    within(index.tree, pos[i], kMergeRadius * iface[k].particle.spacing, m);
    bool clash = false;
    for (const auto& [j, d2] : m) clash = clash || (kept[j] && source[j] != source[i]);
    if (clash) {
      ++st.merged;
      continue;
    }
    kept[i] = 1;
    out.push_back(iface[k].particle);
  }
  return out;
}

// Step 3b: the interface particles relaxed in their tangent planes, the others held.
void relax_interfaces(ComputeBackend& backend, const MaterialField& field, std::vector<ComplexParticle>& pts,
                      int iterations) {
  for (int it = 0; it < iterations && !pts.empty(); ++it)
    pts = run_step(backend, field, ComplexStep::kRelaxInterface, std::move(pts)).out;
}

}  // namespace

std::vector<ComplexParticle> sample_complex(const MaterialField& field, const std::vector<Seed>& seeds,
                                            const ComplexSampleOptions& options, ComputeBackend& backend,
                                            ComplexSampleStats* stats) {
  const auto t0 = std::chrono::steady_clock::now();
  ComplexSampleStats st;
  st.seeds = int64_t(seeds.size());
  std::vector<Projected> iface = project_seeds(backend, field, seeds, st);
  std::vector<ComplexParticle> junctions = thin(junction_candidates(backend, field, iface), kJunctionThin);
  relax_junctions(backend, field, junctions, options.junction_iterations);
  fill_junction_gaps(backend, field, junctions, options.junction_iterations / 2);
  junctions = thin(std::move(junctions), 0.5 * kJunctionThin);  // those the spreading brought together
  std::vector<ComplexParticle> all = merge(junctions, std::move(iface), st);
  relax_interfaces(backend, field, all, options.relax_iterations);
  st.iterations = options.relax_iterations;
  for (const ComplexParticle& p : all) {
    if (p.kind == ParticleKind::kInterface) ++st.interface_particles;
    if (p.kind == ParticleKind::kJunction) ++st.junction_particles;
    if (p.kind == ParticleKind::kCorner) ++st.corners;
  }
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats) *stats = st;
  return all;
}

}  // namespace mpumesh::multi
