#include "multi/material_field.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <numeric>

#include "mpu/data_box.h"
#include "mpu/mpu_eval_ref.h"

namespace mpumesh::multi {
namespace {
uint64_t next_field_id() {
  static std::atomic<uint64_t> count{0};
  return ++count;
}
}  // namespace

MaterialField::MaterialField(std::vector<int64_t> labels, std::vector<const mpu::MpuSurface*> fits,
                             const mpu::MpuSurface* outside, const RegionSupport* support)
    : labels_(std::move(labels)),
      fits_(std::move(fits)),
      outside_(outside),
      support_(support),
      id_(next_field_id()) {}

MaterialField::MaterialField(std::vector<int64_t> labels, std::vector<const mpu::MpuSurface*> fits, double contact,
                             PartUnions unions)
    : labels_(std::move(labels)),
      fits_(std::move(fits)),
      outside_(nullptr),
      support_(nullptr),
      contact_(contact),
      unions_(std::move(unions)),
      id_(next_field_id()) {}

namespace {
// A region beyond its support: never the most inside.
constexpr double kUnsupported = 1e30;

// A fit's value over its gradient's length (far outside beyond its box), with the unit
// gradient when `g` is given.
double distance_of(const mpu::MpuSurface& s, const Eigen::Vector3d& p, Eigen::Vector3d* g) {
  if (!within_data(s, p)) {
    if (g) g->setZero();
    return s.box_size;
  }
  // f over its gradient's length: a first-order signed distance, so that two regions'
  // functions compare as distances whatever their fits' slopes.
  const mpu::Sample e = mpu::evaluate_fg(s, p);
  const double len = e.g.norm();
  if (g) *g = len > 1e-9 ? Eigen::Vector3d(e.g / len) : e.g;
  return len > 1e-9 ? e.f / len : e.f;
}
}  // namespace

// A label's function or (r < 0) the union's.
double MaterialField::f_of(int r, const Eigen::Vector3d& p, Eigen::Vector3d* g) const {
  return distance_of(r < 0 ? *outside_ : *fits_[size_t(r - 1)], p, g);
}

double MaterialField::parts_background(const Eigen::Vector3d& p, const std::vector<double>& f,
                                       std::vector<Eigen::Vector3d>* g) const {
  // The two lowest units' values (and gradients), over each group's union once and each
  // part on its own; evaluated on the field's hot path, so kept without allocation.
  struct Unit {
    double f = INFINITY;
    Eigen::Vector3d g = Eigen::Vector3d::Zero();
  };
  Unit first, second;
  auto consider = [&](double value, const Eigen::Vector3d& grad) {
    if (value < first.f) {
      second = first;
      first = {value, grad};
    } else if (value < second.f) {
      second = {value, grad};
    }
  };
  for (const mpu::MpuSurface* u : unions_.fits) {
    Eigen::Vector3d ug = Eigen::Vector3d::Zero();
    const double uf = distance_of(*u, p, g ? &ug : nullptr);
    consider(uf, ug);
  }
  for (int r = 1; r < int(f.size()); ++r)
    if (unions_.group.empty() || unions_.group[size_t(r - 1)] < 0)
      consider(f[size_t(r)], g ? (*g)[size_t(r)] : Eigen::Vector3d::Zero());
  double f0 = -first.f;
  if (g) (*g)[0] = -first.g;
  const double T = (1 + std::sqrt(3.0) / 2) * contact_;
  if (contact_ > 0 && second.f < T) {
    const double gap = T - second.f;
    f0 += gap * gap / T;
    if (g) (*g)[0] -= 2 * gap / T * second.g;
  }
  return f0;
}

void MaterialField::values(const Eigen::Vector3d& p, std::vector<double>& f) const {
  f.assign(size_t(regions()), 0.0);
  for (int r = 1; r < regions(); ++r) f[size_t(r)] = f_of(r, p, nullptr);
  f[0] = outside_ ? -f_of(-1, p, nullptr) : parts_background(p, f, nullptr);
  if (support_)
    for (int r = 0; r < regions(); ++r)
      if (!support_->allows(r, p)) f[size_t(r)] = kUnsupported;
}

void MaterialField::values_and_gradients(const Eigen::Vector3d& p, std::vector<double>& f,
                                         std::vector<Eigen::Vector3d>& g) const {
  f.assign(size_t(regions()), 0.0);
  g.assign(size_t(regions()), Eigen::Vector3d::Zero());
  for (int r = 1; r < regions(); ++r) f[size_t(r)] = f_of(r, p, &g[size_t(r)]);
  if (outside_) {
    f[0] = -f_of(-1, p, &g[0]);
    g[0] = -g[0];
  } else {
    f[0] = parts_background(p, f, &g);
  }
  if (support_)
    for (int r = 0; r < regions(); ++r)
      if (!support_->allows(r, p)) f[size_t(r)] = kUnsupported;
}

int MaterialField::region_at(const Eigen::Vector3d& p) const {
  std::vector<double> f;
  values(p, f);
  return int(std::min_element(f.begin(), f.end()) - f.begin());
}

std::vector<int> MaterialField::ranked(const Eigen::Vector3d& p) const {
  std::vector<double> f;
  values(p, f);
  return ranked(f);
}

std::vector<int> MaterialField::ranked(const std::vector<double>& f) {
  std::vector<int> order(f.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return f[size_t(a)] < f[size_t(b)]; });
  return order;
}

namespace {
// Newton converges to this fraction of the largest move.
constexpr double kTolerance = 1e-7;
constexpr int kSteps = 12;
}  // namespace

bool MaterialField::project_interface(Eigen::Vector3d& p, int a, int b, double max_move) const {
  const Eigen::Vector3d start = p;
  std::vector<double> f;
  std::vector<Eigen::Vector3d> g;
  for (int it = 0; it < kSteps; ++it) {
    values_and_gradients(p, f, g);
    const double d = f[size_t(a)] - f[size_t(b)];
    const Eigen::Vector3d grad = g[size_t(a)] - g[size_t(b)];
    const double g2 = grad.squaredNorm();
    if (!(g2 > 1e-12)) return false;
    const Eigen::Vector3d step = d / g2 * grad;
    p -= step;
    if ((p - start).norm() > max_move) return false;
    if (step.norm() < kTolerance * max_move) return true;
  }
  return false;
}

bool MaterialField::project_junction(Eigen::Vector3d& p, const std::array<int, 3>& abc, double max_move) const {
  const Eigen::Vector3d start = p;
  std::vector<double> f;
  std::vector<Eigen::Vector3d> g;
  for (int it = 0; it < kSteps; ++it) {
    values_and_gradients(p, f, g);
    Eigen::Matrix<double, 2, 3> J;
    J.row(0) = (g[size_t(abc[0])] - g[size_t(abc[1])]).transpose();
    J.row(1) = (g[size_t(abc[0])] - g[size_t(abc[2])]).transpose();
    const Eigen::Vector2d r(f[size_t(abc[0])] - f[size_t(abc[1])], f[size_t(abc[0])] - f[size_t(abc[2])]);
    const Eigen::Matrix2d JJ = J * J.transpose();
    if (!(std::abs(JJ.determinant()) > 1e-10)) return false;
    const Eigen::Vector3d step = J.transpose() * JJ.ldlt().solve(r);
    p -= step;
    if ((p - start).norm() > max_move) return false;
    if (step.norm() < kTolerance * max_move) return true;
  }
  return false;
}

Eigen::Vector3d MaterialField::junction_tangent(const Eigen::Vector3d& p, const std::array<int, 3>& abc) const {
  std::vector<double> f;
  std::vector<Eigen::Vector3d> g;
  values_and_gradients(p, f, g);
  const Eigen::Vector3d t = (g[size_t(abc[0])] - g[size_t(abc[1])]).cross(g[size_t(abc[0])] - g[size_t(abc[2])]);
  const double n = t.norm();
  return n > 1e-12 ? Eigen::Vector3d(t / n) : Eigen::Vector3d::Zero();
}

Eigen::Vector3d MaterialField::interface_normal(const Eigen::Vector3d& p, int a, int b) const {
  std::vector<double> f;
  std::vector<Eigen::Vector3d> g;
  values_and_gradients(p, f, g);
  // f_a rises and f_b falls going from a into b.
  const Eigen::Vector3d n = g[size_t(a)] - g[size_t(b)];
  const double len = n.norm();
  return len > 1e-12 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

}  // namespace mpumesh::multi
