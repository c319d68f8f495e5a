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
                             const mpu::MpuSurface* outside, const RegionSupport* support, double depth)
    : labels_(std::move(labels)),
      fits_(std::move(fits)),
      outside_(outside),
      support_(support),
      depth_(depth),
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
// The notch lift grows from none to the whole as the labels' soft minimum at p rises over
// this fraction of the depth (material_field.h), the soft minimum's scale this fraction.
constexpr double kNotchRamp = 0.5, kNotchSoftness = 0.1;

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

void MaterialField::evaluate(const Eigen::Vector3d& p, std::vector<double>& f, std::vector<Eigen::Vector3d>* g) const {
  f.assign(size_t(regions()), 0.0);
  if (g) g->assign(size_t(regions()), Eigen::Vector3d::Zero());
  if (outside_) {
    evaluate_under_union(p, f, g);
    return;
  }
  for (int r = 1; r < regions(); ++r) f[size_t(r)] = f_of(r, p, g ? &(*g)[size_t(r)] : nullptr);
  f[0] = parts_background(p, f, g);
  mask_unsupported(p, f);
}

void MaterialField::evaluate_under_union(const Eigen::Vector3d& p, std::vector<double>& f,
                                         std::vector<Eigen::Vector3d>* g) const {
  auto gradient = [&](int r) { return g ? &(*g)[size_t(r)] : nullptr; };
  Eigen::Vector3d gu;
  const double fu = f_of(-1, p, &gu);
  for (int r = 1; r < regions(); ++r) f[size_t(r)] = f_of(r, p, gradient(r));
  f[0] = -fu / 2;
  if (g) (*g)[0] = -gu / 2;
  mask_unsupported(p, f);
  // In a rims' notch the labels again, at q.
  const Lift lift = notch_lift(fu, f, g);
  if (lift.length > 0) {
    const Eigen::Vector3d q = p - lift.length * gu;
    // The lift's gradient: w grad f_U + (f_U + depth) grad w (the offset's curvature left
    // out).
    const Eigen::Vector3d grad_lift = lift.w * gu + (fu + depth_) * lift.grad_w;
    for (int r = 1; r < regions(); ++r) {
      if (!(f[size_t(r)] < kUnsupported)) continue;
      f[size_t(r)] = f_of(r, q, gradient(r));
      // f_r(q(p)), dq = dp - grad f_U (grad_lift . dp): the chain rule.
      if (g) (*g)[size_t(r)] -= grad_lift * gu.dot((*g)[size_t(r)]);
    }
  }
  // The labels shifted so that the most inside holds half the union's value.
  int m = 0;
  for (int r = 1; r < regions(); ++r)
    if (f[size_t(r)] < kUnsupported && (m == 0 || f[size_t(r)] < f[size_t(m)])) m = r;
  if (m == 0) return;
  const double shift = fu / 2 - f[size_t(m)];
  const Eigen::Vector3d shift_g = g ? Eigen::Vector3d(gu / 2 - (*g)[size_t(m)]) : Eigen::Vector3d::Zero();
  for (int r = 1; r < regions(); ++r) {
    if (!(f[size_t(r)] < kUnsupported)) continue;
    f[size_t(r)] += shift;
    if (g) (*g)[size_t(r)] += shift_g;
  }
}

MaterialField::Lift MaterialField::notch_lift(double fu, const std::vector<double>& f,
                                              const std::vector<Eigen::Vector3d>* g) const {
  Lift out;
  if (!(depth_ > 0 && fu > -depth_)) return out;
  // The labels' soft minimum o = lo - eps log sum_r exp(-(f_r - lo) / eps), summed as the
  // labels come (lo the lowest so far, the sum rescaled when it falls), and its gradient,
  // the labels' gradients weighted as their terms: smooth across an interface between
  // two labels, where the plain minimum's gradient jumps from one label's to the other's.
  const double eps = kNotchSoftness * depth_;
  double lo = INFINITY, sum = 0;
  Eigen::Vector3d grad = Eigen::Vector3d::Zero();
  for (int r = 1; r < regions(); ++r) {
    const double v = f[size_t(r)];
    if (!(v < kUnsupported)) continue;
    const Eigen::Vector3d gr = g ? (*g)[size_t(r)] : Eigen::Vector3d::Zero();
    if (v < lo) {
      const double scale = lo < INFINITY ? std::exp(-(lo - v) / eps) : 0.0;
      sum = sum * scale + 1;
      grad = grad * scale + gr;
      lo = v;
    } else {
      const double e = std::exp(-(v - lo) / eps);
      sum += e;
      grad += e * gr;
    }
  }
  if (!(sum > 0)) return out;
  const double ramp = kNotchRamp * depth_, outside = lo - eps * std::log(sum);
  if (!(outside > 0)) return out;
  out.w = std::min(outside / ramp, 1.0);
  out.length = out.w * (fu + depth_);
  if (outside < ramp) out.grad_w = grad / (sum * ramp);
  return out;
}

void MaterialField::mask_unsupported(const Eigen::Vector3d& p, std::vector<double>& f) const {
  if (support_)
    for (int r = 0; r < regions(); ++r)
      if (!support_->allows(r, p)) f[size_t(r)] = kUnsupported;
}

void MaterialField::values(const Eigen::Vector3d& p, std::vector<double>& f) const { evaluate(p, f, nullptr); }

void MaterialField::values_and_gradients(const Eigen::Vector3d& p, std::vector<double>& f,
                                         std::vector<Eigen::Vector3d>& g) const {
  evaluate(p, f, &g);
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
