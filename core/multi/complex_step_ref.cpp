#include "multi/complex_step_ref.h"

#include <tbb/parallel_for.h>

#include <algorithm>

#include "common/kd_tree.h"

namespace mpumesh::multi {
namespace {

// A third region this near (in spacings of f) makes a seed a junction candidate.
constexpr double kJunctionBand = 1.0;
// A fourth region this near (in spacings) at a junction point makes it a corner.
constexpr double kCornerBand = 0.15;

std::array<int, 2> sorted_pair(int a, int b) { return {std::min(a, b), std::max(a, b)}; }

// p onto the interface of its two most inside regions (which may change as it moves).
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

bool seed_onto_interface(const MaterialField& field, const ComplexParticle& in, ComplexParticle& out) {
  std::array<int, 2> pair;
  if (!onto_interface(field, out.p, kComplexReach * in.spacing, pair)) return false;
  out.kind = ParticleKind::kInterface;
  out.regions = {pair[0], pair[1], -1, -1};
  return true;
}

// The junction (or corner) point nearest an interface particle whose third region is
// within the band.
bool junction_candidate(const MaterialField& field, const ComplexParticle& q, ComplexParticle& c) {
  if (field.regions() < 3) return false;
  std::vector<double> f;
  field.values(q.p, f);
  const std::vector<int> r = MaterialField::ranked(f);
  const double s = q.spacing;
  if (f[size_t(r[2])] - f[size_t(r[0])] > kJunctionBand * s) return false;
  std::array<int, 3> abc = {r[0], r[1], r[2]};
  std::sort(abc.begin(), abc.end());
  Eigen::Vector3d p = q.p;
  if (!field.project_junction(p, abc, kComplexReach * s)) return false;
  field.values(p, f);
  const std::vector<int> at = MaterialField::ranked(f);
  std::array<int, 3> top = {at[0], at[1], at[2]};
  std::sort(top.begin(), top.end());
  if (top != abc) return false;
  c.p = p;
  c.kind = ParticleKind::kJunction;
  c.regions = {abc[0], abc[1], abc[2], -1};
  if (at.size() > 3 && f[size_t(at[3])] - f[size_t(at[0])] < kCornerBand * s) {
    std::array<int, 4> r4 = {at[0], at[1], at[2], at[3]};
    std::sort(r4.begin(), r4.end());
    Eigen::Vector3d pc = p;
    if (onto_corner(field, pc, r4, kComplexReach * s)) {
      c.p = pc;
      c.kind = ParticleKind::kCorner;
      c.regions = r4;
    }
  }
  return true;
}

// A junction particle along its curve's tangent, pushed by its neighbours within the
// reach, then back onto the curve.
bool relax_junction(const MaterialField& field, const ComplexBatch& b, size_t i, ComplexParticle& out) {
  const ComplexParticle& q = b.in[i];
  if (q.kind != ParticleKind::kJunction) return false;
  const std::array<int, 3> abc = {q.regions[0], q.regions[1], q.regions[2]};
  const Eigen::Vector3d t = field.junction_tangent(q.p, abc);
  const double s = q.spacing, reach = kRelaxReach * s;
  double push = 0;
  for (uint32_t k = b.first[i]; k < b.first[i + 1]; ++k) {
    const uint32_t j = b.neighbours[k];
    if (j == i) continue;
    const double d = (q.p - b.in[j].p).norm();
    if (d < 1e-12 || d >= reach) continue;
    push += (1 - d / reach) * (q.p - b.in[j].p).dot(t) / d;
  }
  const double step = std::clamp(0.5 * s * push, -kRelaxStepCap * s, kRelaxStepCap * s);
  Eigen::Vector3d p = q.p + step * t;
  if (!field.project_junction(p, abc, kComplexReach * s)) return false;
  out.p = p;
  return true;
}

// An interface particle pushed in its tangent plane by its neighbours (each pair within
// their mean reach), then onto the interface of its two most inside regions.
bool relax_interface(const MaterialField& field, const ComplexBatch& b, size_t i, ComplexParticle& out) {
  const ComplexParticle& q = b.in[i];
  if (q.kind != ParticleKind::kInterface) return false;
  const double s = q.spacing;
  Eigen::Vector3d push = Eigen::Vector3d::Zero();
  for (uint32_t k = b.first[i]; k < b.first[i + 1]; ++k) {
    const uint32_t j = b.neighbours[k];
    if (j == i) continue;
    const double reach = kRelaxReach * 0.5 * (s + b.in[j].spacing), d = (q.p - b.in[j].p).norm();
    if (d < 1e-12 || d >= reach) continue;
    push += (1 - d / reach) * (q.p - b.in[j].p) / d;
  }
  const Eigen::Vector3d n = field.interface_normal(q.p, q.regions[0], q.regions[1]);
  Eigen::Vector3d step = 0.5 * s * (push - n * n.dot(push));
  const double len = step.norm();
  if (len > kRelaxStepCap * s) step *= kRelaxStepCap * s / len;
  Eigen::Vector3d p = q.p + step;
  std::array<int, 2> pair;
  if (!onto_interface(field, p, kComplexReach * s, pair)) return false;
  out.p = p;
  out.regions = {pair[0], pair[1], -1, -1};
  return true;
}

}  // namespace

void find_neighbours(ComplexBatch& batch) {
  const size_t n = batch.in.size();
  batch.first.assign(n + 1, 0);
  batch.neighbours.clear();
  if (n == 0) return;
  std::vector<Eigen::Vector3d> pos(n);
  for (size_t i = 0; i < n; ++i) pos[i] = batch.in[i].p;
  const PointIndex index(pos);
  const double reach = complex_reach(batch.step);
  std::vector<std::vector<uint32_t>> lists(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& rg) {
    std::vector<std::pair<uint32_t, double>> m;
    for (size_t i = rg.begin(); i != rg.end(); ++i) {
      const double r = reach * batch.in[i].spacing;
      m.clear();
      index.tree.radiusSearch(pos[i].data(), r * r, m, nanoflann::SearchParams(32, 0, false));
      lists[i].reserve(m.size());
      for (const auto& [j, d2] : m) lists[i].push_back(j);
    }
  });
  for (size_t i = 0; i < n; ++i) batch.first[i + 1] = batch.first[i] + uint32_t(lists[i].size());
  batch.neighbours.reserve(batch.first[n]);
  for (const auto& l : lists) batch.neighbours.insert(batch.neighbours.end(), l.begin(), l.end());
}

bool complex_step(const MaterialField& field, const ComplexBatch& batch, size_t i, ComplexParticle& out) {
  out = batch.in[i];
  switch (batch.step) {
    case ComplexStep::kOntoInterface: return seed_onto_interface(field, batch.in[i], out);
    case ComplexStep::kJunctionCandidate: return junction_candidate(field, batch.in[i], out);
    case ComplexStep::kRelaxJunction: return relax_junction(field, batch, i, out);
    case ComplexStep::kRelaxInterface: return relax_interface(field, batch, i, out);
  }
  return false;
}

void complex_steps_ref(const MaterialField& field, ComplexBatch& batch) {
  const size_t n = batch.in.size();
  batch.out.resize(n);
  batch.ok.assign(n, 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 64), [&](const tbb::blocked_range<size_t>& rg) {
    for (size_t i = rg.begin(); i != rg.end(); ++i) {
      ComplexParticle out;
      const bool ok = complex_step(field, batch, i, out);
      batch.out[i] = ok ? out : batch.in[i];
      batch.ok[i] = ok;
    }
  });
}

}  // namespace mpumesh::multi
