#include "multi/complex_sampling.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <numeric>

#include "common/kd_tree.h"

namespace mpumesh::multi {
namespace {

// A seed goes at most this many spacings onto its interface or junction.
constexpr double kReach = 2.0;
// A third region this near (in spacings of f) makes a seed a junction candidate.
constexpr double kJunctionBand = 1.0;
// A fourth region this near (in spacings) at a junction point makes it a corner.
constexpr double kCornerBand = 0.15;
// Junction points are thinned to this many spacings; interface seeds dropped this near a
// junction point or another sampling's seed.
constexpr double kJunctionThin = 0.75;
constexpr double kMergeRadius = 0.6;
// The repulsion reaches this many spacings; a step moves at most this fraction of one.
constexpr double kReachRelax = 1.3;
constexpr double kStepCap = 0.25;

using Matches = std::vector<std::pair<uint32_t, double>>;

void within(const KdTree& tree, const Eigen::Vector3d& q, double r, Matches& out) {
  out.clear();
  tree.radiusSearch(q.data(), r * r, out, nanoflann::SearchParams(32, 0, false));
}

std::array<int, 2> sorted_pair(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// The region whose sampling covers interface (a, b), a < b: the label's own for the
// background's interfaces, the lower label's between two labels.
int covering_source(int a, int b) { return a == 0 ? b : a; }

// A seed onto the interface of its two lowest regions (which may change as it moves).
bool onto_interface(const MaterialField& field, Eigen::Vector3d& p, double reach, std::array<int, 2>& pair) {
  for (int round = 0; round < 3; ++round) {
    const std::vector<int> r = field.ranked(p);
    pair = sorted_pair(r[0], r[1]);
    Eigen::Vector3d q = p;
    if (!field.project_interface(q, pair[0], pair[1], reach)) return false;
    p = q;
    const std::vector<int> after = field.ranked(p);
    if (sorted_pair(after[0], after[1]) == pair) return true;
  }
  return false;
}

// p onto the point where four regions meet (three differences, a 3 x 3 Newton system).
bool onto_corner(const MaterialField& field, Eigen::Vector3d& p, const std::array<int, 4>& r, double reach) {
  const Eigen::Vector3d start = p;
  std::vector<double> f;
  std::vector<Eigen::Vector3d> g;
  for (int it = 0; it < 12; ++it) {
    field.values_and_gradients(p, f, g);
    Eigen::Matrix3d J;
    Eigen::Vector3d d;
    for (int k = 0; k < 3; ++k) {
      J.row(k) = (g[size_t(r[0])] - g[size_t(r[size_t(k) + 1])]).transpose();
      d[k] = f[size_t(r[0])] - f[size_t(r[size_t(k) + 1])];
    }
    if (!(std::abs(J.determinant()) > 1e-12)) return false;
    const Eigen::Vector3d step = J.partialPivLu().solve(d);
    p -= step;
    if ((p - start).norm() > reach) return false;
    if (step.norm() < 1e-7 * reach) return true;
  }
  return false;
}

struct Projected {
  ComplexParticle particle;
  int source = 0;
};

// Step 1: every seed onto its interface; those of an interface another sampling covers
// are left out.
std::vector<Projected> project_seeds(const MaterialField& field, const std::vector<Seed>& seeds,
                                     ComplexSampleStats& st) {
  std::vector<Projected> out(seeds.size());
  std::vector<char> state(seeds.size(), 0);  // 0 off, 1 other source, 2 kept
  tbb::parallel_for(tbb::blocked_range<size_t>(0, seeds.size(), 256), [&](const tbb::blocked_range<size_t>& rg) {
    for (size_t i = rg.begin(); i != rg.end(); ++i) {
      Eigen::Vector3d p = seeds[i].p;
      std::array<int, 2> pair;
      if (!onto_interface(field, p, kReach * seeds[i].spacing, pair)) continue;
      if (covering_source(pair[0], pair[1]) != seeds[i].source) {
        state[i] = 1;
        continue;
      }
      out[i].particle.p = p;
      out[i].particle.spacing = seeds[i].spacing;
      out[i].particle.regions = {pair[0], pair[1], -1, -1};
      out[i].source = seeds[i].source;
      state[i] = 2;
    }
  });
  std::vector<Projected> kept;
  for (size_t i = 0; i < seeds.size(); ++i) {
    if (state[i] == 0) ++st.off_interface;
    if (state[i] == 1) ++st.other_source;
    if (state[i] == 2) kept.push_back(out[i]);
  }
  return kept;
}

// Step 2a: the junction (or corner) point nearest each interface particle whose third
// region is within the band.
std::vector<ComplexParticle> junction_candidates(const MaterialField& field, const std::vector<Projected>& in) {
  std::vector<ComplexParticle> cand(in.size());
  std::vector<char> ok(in.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, in.size(), 256), [&](const tbb::blocked_range<size_t>& rg) {
    std::vector<double> f;
    for (size_t i = rg.begin(); i != rg.end(); ++i) {
      const ComplexParticle& q = in[i].particle;
      if (field.regions() < 3) continue;
      field.values(q.p, f);
      const std::vector<int> r = MaterialField::ranked(f);
      const double s = q.spacing;
      if (f[size_t(r[2])] - f[size_t(r[0])] > kJunctionBand * s) continue;
      std::array<int, 3> abc = {r[0], r[1], r[2]};
      std::sort(abc.begin(), abc.end());
      Eigen::Vector3d p = q.p;
      if (!field.project_junction(p, abc, kReach * s)) continue;
      field.values(p, f);
      const std::vector<int> at = MaterialField::ranked(f);
      std::array<int, 3> top = {at[0], at[1], at[2]};
      std::sort(top.begin(), top.end());
      if (top != abc) continue;
      ComplexParticle c;
      c.spacing = s;
      c.p = p;
      c.kind = ParticleKind::kJunction;
      c.regions = {abc[0], abc[1], abc[2], -1};
      if (at.size() > 3 && f[size_t(at[3])] - f[size_t(at[0])] < kCornerBand * s) {
        std::array<int, 4> r4 = {at[0], at[1], at[2], at[3]};
        std::sort(r4.begin(), r4.end());
        Eigen::Vector3d pc = p;
        if (onto_corner(field, pc, r4, kReach * s)) {
          c.p = pc;
          c.kind = ParticleKind::kCorner;
          c.regions = r4;
        }
      }
      cand[i] = c;
      ok[i] = 1;
    }
  });
  std::vector<ComplexParticle> out;
  for (size_t i = 0; i < in.size(); ++i)
    if (ok[i]) out.push_back(cand[i]);
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
  std::vector<Eigen::Vector3d> pos(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) pos[i] = pts[i].p;
  if (pts.empty()) return pts;
  const PointIndex index(pos);
  std::vector<char> kept(pts.size(), 0);
  Matches m;
  std::vector<ComplexParticle> out;
  for (size_t i = 0; i < pts.size(); ++i) {
    within(index.tree, pos[i], radius * pts[i].spacing, m);
    bool clash = false;
    for (const auto& [j, d2] : m) clash = clash || kept[j];
    if (clash) continue;
    kept[i] = 1;
    out.push_back(pts[i]);
  }
  return out;
}

// Step 2b: junction points spread along their curves, corners held.
void relax_junctions(const MaterialField& field, std::vector<ComplexParticle>& jp, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    std::vector<Eigen::Vector3d> pos(jp.size());
    for (size_t i = 0; i < jp.size(); ++i) pos[i] = jp[i].p;
    if (pos.empty()) return;
    const PointIndex index(pos);
    std::vector<Eigen::Vector3d> next = pos;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, jp.size(), 64), [&](const tbb::blocked_range<size_t>& rg) {
      Matches m;
      for (size_t i = rg.begin(); i != rg.end(); ++i) {
        if (jp[i].kind != ParticleKind::kJunction) continue;
        const std::array<int, 3> abc = {jp[i].regions[0], jp[i].regions[1], jp[i].regions[2]};
        const Eigen::Vector3d t = field.junction_tangent(pos[i], abc);
        const double s = jp[i].spacing, reach = kReachRelax * s;
        within(index.tree, pos[i], reach, m);
        double push = 0;
        for (const auto& [j, d2] : m) {
          if (j == i) continue;
          const double d = std::sqrt(d2);
          if (d < 1e-12) continue;
          push += (1 - d / reach) * (pos[i] - pos[j]).dot(t) / d;
        }
        const double step = std::clamp(0.5 * s * push, -kStepCap * s, kStepCap * s);
        Eigen::Vector3d p = pos[i] + step * t;
        if (field.project_junction(p, abc, kReach * s)) next[i] = p;
      }
    });
    for (size_t i = 0; i < jp.size(); ++i) jp[i].p = next[i];
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
void relax_interfaces(const MaterialField& field, std::vector<ComplexParticle>& pts, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    std::vector<Eigen::Vector3d> pos(pts.size());
    for (size_t i = 0; i < pts.size(); ++i) pos[i] = pts[i].p;
    if (pos.empty()) return;
    const PointIndex index(pos);
    std::vector<ComplexParticle> next = pts;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, pts.size(), 64), [&](const tbb::blocked_range<size_t>& rg) {
      Matches m;
      for (size_t i = rg.begin(); i != rg.end(); ++i) {
        if (pts[i].kind != ParticleKind::kInterface) continue;
        const double s = pts[i].spacing;
        within(index.tree, pos[i], kReachRelax * 1.5 * s, m);
        Eigen::Vector3d push = Eigen::Vector3d::Zero();
        for (const auto& [j, d2] : m) {
          if (j == i) continue;
          const double reach = kReachRelax * 0.5 * (s + pts[j].spacing), d = std::sqrt(d2);
          if (d < 1e-12 || d >= reach) continue;
          push += (1 - d / reach) * (pos[i] - pos[j]) / d;
        }
        const Eigen::Vector3d n = field.interface_normal(pos[i], pts[i].regions[0], pts[i].regions[1]);
        Eigen::Vector3d step = 0.5 * s * (push - n * n.dot(push));
        const double len = step.norm();
        if (len > kStepCap * s) step *= kStepCap * s / len;
        Eigen::Vector3d p = pos[i] + step;
        std::array<int, 2> pair;
        if (!onto_interface(field, p, kReach * s, pair)) continue;
        next[i].p = p;
        next[i].regions = {pair[0], pair[1], -1, -1};
      }
    });
    pts = std::move(next);
  }
}

}  // namespace

std::vector<ComplexParticle> sample_complex(const MaterialField& field, const std::vector<Seed>& seeds,
                                            const ComplexSampleOptions& options, ComplexSampleStats* stats) {
  const auto t0 = std::chrono::steady_clock::now();
  ComplexSampleStats st;
  st.seeds = int64_t(seeds.size());
  std::vector<Projected> iface = project_seeds(field, seeds, st);
  std::vector<ComplexParticle> junctions = thin(junction_candidates(field, iface), kJunctionThin);
  relax_junctions(field, junctions, options.junction_iterations);
  junctions = thin(std::move(junctions), 0.5 * kJunctionThin);  // those the spreading brought together
  std::vector<ComplexParticle> all = merge(junctions, std::move(iface), st);
  relax_interfaces(field, all, options.relax_iterations);
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
