#include "mpu/local_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace mpumesh::mpu {
namespace {

double bspline(double r, double R) {
  double w, dw, d2w;
  bspline_weight(r, R, w, dw, d2w);
  return w;
}

// The points of the ball in the scaled local frame, with their weights. One per thread,
// reused from ball to ball (the fit makes about a quarter of a million of them).
struct Local {
  std::vector<double> u, v, w, weight;
  std::vector<double> tolerance;  // the points' (PointCloud::tolerance); empty: 1
};

Local& to_local(const Ball& ball, const PointCloud& cloud, const Eigen::Matrix3d& frame) {
  thread_local Local l;
  const size_t n = ball.ids.size();
  l.u.resize(n);
  l.v.resize(n);
  l.w.resize(n);
  l.weight.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d d = cloud.positions[ball.ids[i]] - ball.centre;
    const Eigen::Vector3d y = frame * d / ball.radius;
    l.u[i] = y.x();
    l.v[i] = y.y();
    l.w[i] = y.z();
    // A floor keeps points on the rim of a grown ball from vanishing from the fit.
    l.weight[i] = std::max(bspline(d.norm(), ball.radius), 1e-3);
  }
  // Weighted least squares: a point's weight falls with its tolerance squared, scaled so
  // that the ball's points weigh as much in all as they would at tolerance 1 (the general
  // quadric's auxiliary points keep their share).
  l.tolerance.clear();
  if (!cloud.tolerance.empty() && n > 0) {
    double inverse_sum = 0;
    for (size_t i = 0; i < n; ++i) {
      l.tolerance.push_back(cloud.tolerance[ball.ids[i]]);
      inverse_sum += 1.0 / (l.tolerance[i] * l.tolerance[i]);
    }
    const double scale = double(n) / inverse_sum;
    for (size_t i = 0; i < n; ++i) l.weight[i] *= scale / (l.tolerance[i] * l.tolerance[i]);
  }
  return l;
}

Leaf make_leaf(const Ball& ball, const Eigen::Matrix3d& frame, FitKind kind) {
  Leaf leaf;
  leaf.centre = ball.centre;
  leaf.radius = ball.radius;
  leaf.frame = frame;
  leaf.kind = kind;
  leaf.points = uint32_t(ball.ids.size());
  return leaf;
}

// Σ w_i x_i y_i, summed in order. Out of line: inlined into the Gram-Schmidt loops, GCC
// kept the running sum in memory (a store and a load on its critical path per term).
__attribute__((noinline)) double weighted_dot(const double* w, const double* x, const double* y, size_t n) {
  double s = 0;
  for (size_t i = 0; i < n; ++i) s += w[i] * x[i] * y[i];
  return s;
}

// p[j] = Σ_i x_i basis[j][i] for j < count, four rows at a time (independent sums).
void projections(const double* x, const double* basis, int count, size_t n, double* p) {
  int j = 0;
  for (; j + 4 <= count; j += 4) {
    const double *b0 = basis + size_t(j) * n, *b1 = b0 + n, *b2 = b1 + n, *b3 = b2 + n;
    double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
    for (size_t i = 0; i < n; ++i) {
      s0 += x[i] * b0[i];
      s1 += x[i] * b1[i];
      s2 += x[i] * b2[i];
      s3 += x[i] * b3[i];
    }
    p[j] = s0, p[j + 1] = s1, p[j + 2] = s2, p[j + 3] = s3;
  }
  for (; j < count; ++j) {
    const double* bj = basis + size_t(j) * n;
    double s = 0;
    for (size_t i = 0; i < n; ++i) s += x[i] * bj[i];
    p[j] = s;
  }
}

// taubin_error on the ball's points already in the leaf's frame (to_local computes them
// with the same operations). Where the points have tolerances, a general quadric's mean
// signed distance over them counts kBiasWeight times against ε0: held to the auxiliary
// points' distances as well as to the points, it can lie to one side of them all by less
// than their tolerances (a small label's single quadric swelled it by 0.4 mm), which a
// height field fitted to the points alone cannot. The error comes from the terms the leaf
// can have: a height field of degree d the first bivariate_terms(d) and w (coefficient
// 1), a general quadric terms 0-5 and 15-18. The other terms only add ±0 to local_poly's
// sums, so |q| and |∇q|, hence the error, are its to the bit; the sums below are in its
// order.
constexpr double kBiasWeight = 2;
double taubin_error_local(const Leaf& leaf, const Local& l) {
  if (leaf.kind == FitKind::kTwoSheets) {  // every term: local_poly itself
    double worst = 0;
    for (size_t i = 0; i < l.u.size(); ++i) {
      double q, g[3], h[6];
      local_poly(leaf.coeffs.data(), l.u[i], l.v[i], l.w[i], q, g, h);
      const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
      double e = gn > 0 ? leaf.radius * std::abs(q) / gn : std::numeric_limits<double>::infinity();
      if (!l.tolerance.empty()) e /= l.tolerance[i];
      worst = std::max(worst, std::isfinite(e) ? e : std::numeric_limits<double>::infinity());
    }
    return worst;
  }
  const double* c = leaf.coeffs.data();
  const bool general = leaf.kind == FitKind::kGeneralQuadric;
  const int degree = general ? 2 : std::clamp<int>(leaf.degree, 1, 4);
  double worst = 0, signed_sum = 0, weight_sum = 0;
  for (size_t i = 0; i < l.u.size(); ++i) {
    const double u = l.u[i], v = l.v[i], w = l.w[i];
    const double u2 = u * u, v2 = v * v, uv = u * v;
    double q = c[0] + c[1] * u + c[2] * v, g0 = c[1], g1 = c[2], g2;
    if (degree >= 2) {
      q = q + c[3] * u2 + c[4] * uv + c[5] * v2;
      g0 = g0 + 2 * c[3] * u + c[4] * v;
      g1 = g1 + c[4] * u + 2 * c[5] * v;
    }
    if (degree >= 3) {
      q = q + c[6] * u2 * u + c[7] * u2 * v + c[8] * u * v2 + c[9] * v2 * v;
      g0 = g0 + 3 * c[6] * u2 + 2 * c[7] * uv + c[8] * v2;
      g1 = g1 + c[7] * u2 + 2 * c[8] * uv + 3 * c[9] * v2;
    }
    if (degree >= 4) {
      q = q + c[10] * u2 * u2 + c[11] * u2 * uv + c[12] * u2 * v2 + c[13] * uv * v2 + c[14] * v2 * v2;
      g0 = g0 + 4 * c[10] * u2 * u + 3 * c[11] * u2 * v + 2 * c[12] * u * v2 + c[13] * v2 * v;
      g1 = g1 + c[11] * u2 * u + 2 * c[12] * u2 * v + 3 * c[13] * u * v2 + 4 * c[14] * v2 * v;
    }
    if (general) {
      q = q + c[15] * w + c[16] * w * w + c[17] * u * w + c[18] * v * w;
      g0 = g0 + c[17] * w;
      g1 = g1 + c[18] * w;
      g2 = c[15] + 2 * c[16] * w + c[17] * u + c[18] * v;
    } else {
      q = q + c[15] * w;
      g2 = c[15];
    }
    const double gn = std::sqrt(g0 * g0 + g1 * g1 + g2 * g2);
    double e = gn > 0 ? leaf.radius * std::abs(q) / gn : std::numeric_limits<double>::infinity();
    if (general && !l.tolerance.empty()) {
      signed_sum += gn > 0 ? l.weight[i] * leaf.radius * q / gn : 0;
      weight_sum += l.weight[i];
    }
    if (!l.tolerance.empty()) e /= l.tolerance[i];
    worst = std::max(worst, std::isfinite(e) ? e : std::numeric_limits<double>::infinity());
  }
  if (weight_sum > 0) worst = std::max(worst, kBiasWeight * std::abs(signed_sum) / weight_sum);
  return worst;
}

}  // namespace

double taubin_error(const Leaf& leaf, const Ball& ball, const PointCloud& cloud) {
  double worst = 0;
  for (uint32_t id : ball.ids) {
    const Eigen::Vector3d y = leaf.frame * (cloud.positions[id] - leaf.centre) / leaf.radius;
    double q, g[3], h[6];
    local_poly(leaf.coeffs.data(), y.x(), y.y(), y.z(), q, g, h);
    const double gn = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    double e = gn > 0 ? leaf.radius * std::abs(q) / gn : std::numeric_limits<double>::infinity();
    if (!cloud.tolerance.empty()) e /= cloud.tolerance[id];
    worst = std::max(worst, std::isfinite(e) ? e : std::numeric_limits<double>::infinity());
  }
  return worst;
}

Eigen::Vector3d mean_normal(const Ball& ball, const PointCloud& cloud) {
  Eigen::Vector3d n = Eigen::Vector3d::Zero();
  for (uint32_t id : ball.ids)
    n += std::max(bspline((cloud.positions[id] - ball.centre).norm(), ball.radius), 1e-3) * cloud.normals[id];
  return n;
}

Eigen::Matrix3d frame_from_normal(const Eigen::Vector3d& n) {
  const Eigen::Vector3d a = std::abs(n.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  const Eigen::Vector3d u = (a - a.dot(n) * n).normalized();
  const Eigen::Vector3d v = n.cross(u);
  Eigen::Matrix3d m;
  m.row(0) = u;
  m.row(1) = v;
  m.row(2) = n;
  return m;
}

namespace {

constexpr int kMaxTerms = bivariate_terms(4);

// The least-squares rows of a height-field fit: h at each point, and with slope_length > 0
// also its slopes ∂h/∂u, ∂h/∂v against the point's normal (n_u, n_v, n_w in the frame:
// -n_u / n_w, -n_v / n_w), weighted by (slope_length / R)² (a slope off by s is a height
// off by s over slope_length), for normals within 60° of the frame's w. Row k of `mono`
// is monomial k at the rows (kMaxTerms rows of n); one flat buffer per thread.
struct HeightRows {
  size_t points = 0, n = 0;
  double* mono = nullptr;
  const double* wt = nullptr;      // the rows' weights
  const double* target = nullptr;  // the rows' values
};

HeightRows height_rows(const Ball& ball, const PointCloud& cloud, const Eigen::Matrix3d& frame, const Local& l,
                       double slope_length) {
  thread_local std::vector<double> mono_buf, wt_buf, target_buf;
  HeightRows r;
  r.points = l.u.size();
  const bool slopes = slope_length > 0;
  r.n = slopes ? 3 * r.points : r.points;
  const size_t points = r.points, n = r.n;
  mono_buf.resize(size_t(kMaxTerms) * n);
  r.mono = mono_buf.data();
  r.wt = l.weight.data();
  r.target = l.w.data();
  for (size_t i = 0; i < points; ++i) {
    double m[15];
    bivariate_monomials(l.u[i], l.v[i], m);
    for (int k = 0; k < kMaxTerms; ++k) r.mono[size_t(k) * n + i] = m[k];
  }
  if (!slopes) return r;
  wt_buf.resize(n);
  target_buf.resize(n);
  const double beta = (slope_length / ball.radius) * (slope_length / ball.radius);
  for (size_t i = 0; i < points; ++i) {
    const Eigen::Vector3d nl = frame * cloud.normals[ball.ids[i]];
    const bool steep = !(nl.z() > 0.5);
    wt_buf[i] = l.weight[i];
    wt_buf[points + i] = wt_buf[2 * points + i] = steep ? 0.0 : beta * l.weight[i];
    target_buf[i] = l.w[i];
    target_buf[points + i] = steep ? 0.0 : -nl.x() / nl.z();
    target_buf[2 * points + i] = steep ? 0.0 : -nl.y() / nl.z();
    const double u = l.u[i], v = l.v[i], u2 = u * u, v2 = v * v, uv = u * v;
    // ∂/∂u and ∂/∂v of the monomials of bivariate_monomials
    const double du[15] = {0, 1, 0, 2 * u, v, 0, 3 * u2, 2 * uv, v2, 0, 4 * u2 * u, 3 * u2 * v, 2 * u * v2, v2 * v, 0};
    const double dv[15] = {0, 0, 1, 0, u, 2 * v, 0, u2, 2 * uv, 3 * v2, 0, u2 * u, 2 * u2 * v, 3 * u * v2, 4 * v2 * v};
    for (int k = 0; k < kMaxTerms; ++k) {
      r.mono[size_t(k) * n + points + i] = du[k];
      r.mono[size_t(k) * n + 2 * points + i] = dv[k];
    }
  }
  r.wt = wt_buf.data();
  r.target = target_buf.data();
  return r;
}

// Polynomials orthogonal over the rows, built term by term: beta_j = Σ_k T[j][k] m_k; a
// monomial the points cannot tell from the earlier ones (e.g. v² when the points lie on a
// line) is dropped. Rows of `basis` are the polynomials at the rows (those of the
// accepted degrees, then the current degree's new ones).
class OrthoBasis {
 public:
  explicit OrthoBasis(const HeightRows& rows) : r_(rows) {
    thread_local std::vector<double> basis_buf, b_buf, wb_buf;
    basis_buf.resize(size_t(kMaxTerms) * r_.n);
    b_buf.resize(r_.n);
    wb_buf.resize(r_.n);
    basis_ = basis_buf.data(), b_ = b_buf.data(), wb_ = wb_buf.data();
  }
  // Adds monomials [from, to) after the accepted basis functions; returns the smallest
  // ratio of a monomial's residual to itself (squared norms).
  double add_terms(int from, int to);
  // Takes the terms added since the last call: adds the target's projections on them
  // to h (monomial coefficients).
  void accept(Coeffs& h);

 private:
  double dot(const double* x, const double* y) const { return weighted_dot(r_.wt, x, y, r_.n); }
  const HeightRows& r_;
  double *basis_, *b_, *wb_;
  std::array<std::array<double, 15>, kMaxTerms> T_;
  std::array<double, kMaxTerms> norm2_;  // <beta, beta>
  int accepted_ = 0;                     // basis functions of the accepted degrees
  int count_ = 0;                        // and this degree's
};

double OrthoBasis::add_terms(int from, int to) {
  const size_t n = r_.n;
  count_ = accepted_;
  double worst_ratio = 1;
  for (int m = from; m < to; ++m) {
    std::copy(r_.mono + size_t(m) * n, r_.mono + size_t(m + 1) * n, b_);
    std::array<double, 15> t{};
    t[size_t(m)] = 1;
    const double start = dot(b_, b_);
    // Classical Gram-Schmidt, twice ("twice is enough": as orthogonal as the modified
    // one): each pass projects b on every earlier basis function at once, so that the
    // pass's dot products are independent and overlap, where the modified scheme's each
    // waits for the one before.
    for (int pass = 0; pass < 2; ++pass) {
      double p[kMaxTerms];
      for (size_t i = 0; i < n; ++i) wb_[i] = r_.wt[i] * b_[i];
      projections(wb_, basis_, count_, n, p);
      for (int j = 0; j < count_; ++j) {
        p[j] /= norm2_[size_t(j)];
        const double* bj = basis_ + size_t(j) * n;
        for (size_t i = 0; i < n; ++i) b_[i] -= p[j] * bj[i];
        for (int c = 0; c < 15; ++c) t[size_t(c)] -= p[j] * T_[size_t(j)][size_t(c)];
      }
    }
    const double nb = dot(b_, b_);
    worst_ratio = std::min(worst_ratio, start > 0 ? nb / start : 0.0);
    if (!(nb > 1e-12 * start) || !(nb > 1e-300)) continue;
    std::copy(b_, b_ + n, basis_ + size_t(count_) * n);
    T_[size_t(count_)] = t;
    norm2_[size_t(count_)] = nb;
    ++count_;
  }
  return worst_ratio;
}

void OrthoBasis::accept(Coeffs& h) {
  for (int j = accepted_; j < count_; ++j) {
    const double coef = dot(r_.target, basis_ + size_t(j) * r_.n) / norm2_[size_t(j)];
    for (int c = 0; c < 15; ++c) h[size_t(c)] += coef * T_[size_t(j)][size_t(c)];
  }
  accepted_ = count_;
}

}  // namespace

Leaf fit_height_orthopoly(const Ball& ball, const PointCloud& cloud, const Eigen::Vector3d& normal, int degree_cap,
                          double slope_length, double* error) {
  const Eigen::Matrix3d frame = frame_from_normal(normal);
  const Local& l = to_local(ball, cloud, frame);
  const HeightRows rows = height_rows(ball, cloud, frame, l, slope_length);
  const size_t points = rows.points;
  OrthoBasis basis(rows);
  Leaf best = make_leaf(ball, frame, FitKind::kHeightOrthopoly);
  double best_error = std::numeric_limits<double>::infinity();
  Coeffs h{};  // the monomial coefficients of h
  int k = 0;
  for (int degree = 1; degree <= std::clamp(degree_cap, 2, 4); ++degree) {
    const int terms = bivariate_terms(degree);
    // Degree 2 needs its 6 terms' worth of points; a higher degree twice its terms.
    if (degree == 2 && points < 6) break;
    if (degree > 2 && double(points) < 2.0 * terms) break;
    const double worst_ratio = basis.add_terms(k, terms);
    // Above degree 2, a degree is taken only when the points determine every one of its
    // terms: a monomial that is almost a combination of the lower ones over the points
    // (|residual| < kDetermined |monomial|) is free between them. Contours on a few
    // slices are such a case: a cubic across three contour lines vanishes on all of
    // them, and fitting it would bend the height field freely between the slices.
    constexpr double kDetermined = 0.05;
    if (degree > 2 && worst_ratio < kDetermined * kDetermined) break;
    k = terms;
    basis.accept(h);
    if (degree < 2) continue;
    Leaf leaf = make_leaf(ball, frame, FitKind::kHeightOrthopoly);
    leaf.degree = uint8_t(degree);
    for (int c = 0; c < 15; ++c) leaf.coeffs[size_t(c)] = -h[size_t(c)];
    leaf.coeffs[15] = 1;  // q = w - h(u, v)
    const double e = taubin_error_local(leaf, l);
    // A higher degree is kept only when it lowers the error by at least 10% below the best
    // so far; a degree that does not still leads on to the next (on a sphere the cubic
    // terms lower nothing, and the quartic term still mends the curvature that a
    // quadratic takes up wrongly).
    if (degree == 2 || e < 0.9 * best_error) {
      best = leaf;
      best_error = e;
    }
  }
  *error = best_error;
  return best;
}

Leaf fit_height_quadric(const Ball& ball, const PointCloud& cloud, const Eigen::Vector3d& normal, double* error) {
  const Eigen::Matrix3d frame = frame_from_normal(normal);
  const Local& l = to_local(ball, cloud, frame);
  Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
  for (size_t i = 0; i < l.u.size(); ++i) {
    double m[15];
    bivariate_monomials(l.u[i], l.v[i], m);
    const Eigen::Map<const Eigen::Matrix<double, 6, 1>> mv(m);
    A += l.weight[i] * mv * mv.transpose();
    b += l.weight[i] * l.w[i] * mv;
  }
  const Eigen::Matrix<double, 6, 1> x = A.ldlt().solve(b);  // Ohtake's normal equations
  Leaf leaf = make_leaf(ball, frame, FitKind::kHeightQuadric);
  for (int c = 0; c < 6; ++c) leaf.coeffs[size_t(c)] = -x[c];
  leaf.coeffs[15] = 1;
  *error = x.allFinite() ? taubin_error_local(leaf, l) : std::numeric_limits<double>::infinity();
  return leaf;
}

Leaf fit_general_quadric(const Ball& ball, const PointCloud& cloud, const std::vector<AuxPoint>& aux,
                         double* error) {
  // Unknowns: terms 0-5 and 15-18 of the basis, in the identity frame.
  static constexpr int kIdx[10] = {0, 1, 2, 3, 4, 5, 15, 16, 17, 18};
  const Eigen::Matrix3d frame = Eigen::Matrix3d::Identity();
  const Local& l = to_local(ball, cloud, frame);
  const size_t n = l.u.size();
  // The normal equations (10 x 10, LDLT, which zeroes the components of vanishing pivots),
  // summed row by row: cheaper than a column-pivoting QR of the whole (points + 9) x 10
  // system, or than building that system to multiply it out, and general quadrics are
  // most of a CT's leaves.
  double wsum = 0;
  for (double w : l.weight) wsum += w;
  Eigen::Matrix<double, 10, 10> AtA = Eigen::Matrix<double, 10, 10>::Zero();
  Eigen::Matrix<double, 10, 1> Atb = Eigen::Matrix<double, 10, 1>::Zero();
  auto add_row = [&](double u, double v, double w, double weight, double target) {
    const double a[10] = {1, u, v, u * u, u * v, v * v, w, w * w, u * w, v * w};
    for (int c = 0; c < 10; ++c) {
      const double wa = weight * a[c];
      for (int r = c; r < 10; ++r) AtA(r, c) += wa * a[r];
      Atb[c] += wa * target;
    }
  };
  for (size_t i = 0; i < n; ++i) add_row(l.u[i], l.v[i], l.w[i], l.weight[i] / wsum, 0.0);
  const double aux_weight = aux.empty() ? 0 : 1.0 / double(aux.size());
  for (const AuxPoint& p : aux) {
    const Eigen::Vector3d y = (p.position - ball.centre) / ball.radius;
    add_row(y.x(), y.y(), y.z(), aux_weight, p.distance / ball.radius);
  }
  const Eigen::Matrix<double, 10, 1> x = AtA.selfadjointView<Eigen::Lower>().ldlt().solve(Atb);
  Leaf leaf = make_leaf(ball, frame, FitKind::kGeneralQuadric);
  for (int c = 0; c < 10; ++c) leaf.coeffs[size_t(kIdx[c])] = x[c];
  *error = (x.allFinite() && !aux.empty()) ? taubin_error_local(leaf, l) : std::numeric_limits<double>::infinity();
  return leaf;
}

namespace {

// The weighted least-squares quadric height field w = h(u, v) of the rows `rows` of l (its
// six monomial coefficients), or the plane (three) where the rows do not determine the
// quadric (too few, or along a line); false where they determine neither.
bool sheet_height(const Local& l, const std::vector<size_t>& rows, std::array<double, 6>& h) {
  h.fill(0);
  for (int terms : {6, 3}) {
    if (rows.size() < size_t(terms) + 4) continue;
    Eigen::Matrix<double, 6, 6> A = Eigen::Matrix<double, 6, 6>::Zero();
    Eigen::Matrix<double, 6, 1> b = Eigen::Matrix<double, 6, 1>::Zero();
    for (size_t i : rows) {
      double m[15];
      bivariate_monomials(l.u[i], l.v[i], m);
      const Eigen::Map<const Eigen::Matrix<double, 6, 1>> mv(m);
      A += l.weight[i] * mv * mv.transpose();
      b += l.weight[i] * l.w[i] * mv;
    }
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(A.topLeftCorner(terms, terms));
    if (ldlt.info() != Eigen::Success || !(ldlt.rcond() > 1e-9)) continue;
    const Eigen::VectorXd x = ldlt.solve(b.head(terms));
    if (!x.allFinite()) continue;
    for (int k = 0; k < terms; ++k) h[size_t(k)] = x[k];
    return true;
  }
  return false;
}

double quadratic_at(const std::array<double, 6>& h, double u, double v) {
  return h[0] + h[1] * u + h[2] * v + h[3] * u * u + h[4] * u * v + h[5] * v * v;
}

}  // namespace

Leaf fit_two_sheets(const Ball& ball, const PointCloud& cloud, double* error) {
  *error = std::numeric_limits<double>::infinity();
  // The normals' axis.
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (uint32_t id : ball.ids) {
    const double wt = std::max(bspline((cloud.positions[id] - ball.centre).norm(), ball.radius), 1e-3);
    scatter += wt * cloud.normals[id] * cloud.normals[id].transpose();
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es;
  es.computeDirect(scatter);
  const Eigen::Vector3d axis = es.eigenvectors().col(2).normalized();
  const Eigen::Matrix3d frame = frame_from_normal(axis);
  Leaf leaf = make_leaf(ball, frame, FitKind::kTwoSheets);
  const Local& l = to_local(ball, cloud, frame);
  std::vector<size_t> up, down;
  double oblique = 0, total = 0;
  for (size_t i = 0; i < ball.ids.size(); ++i) {
    const double s = cloud.normals[ball.ids[i]].dot(axis);
    (s > 0 ? up : down).push_back(i);
    total += l.weight[i];
    if (std::abs(s) < 0.5) oblique += l.weight[i];
  }
  if (up.size() < size_t(kMinSheetPoints) || down.size() < size_t(kMinSheetPoints) || oblique > 0.1 * total) return leaf;
  std::array<double, 6> a, b;
  if (!sheet_height(l, up, a) || !sheet_height(l, down, b)) return leaf;
  // The mean separation, and the sheets apart at every point.
  double t = 0;
  for (size_t i = 0; i < l.u.size(); ++i) t += l.weight[i] * (quadratic_at(a, l.u[i], l.v[i]) - quadratic_at(b, l.u[i], l.v[i]));
  t /= total;
  if (!(std::abs(t) > 0)) return leaf;
  for (size_t i = 0; i < l.u.size(); ++i)
    if (!((quadratic_at(a, l.u[i], l.v[i]) - quadratic_at(b, l.u[i], l.v[i])) / t > 0.2)) return leaf;
  // Nor anywhere over the ball (|u|, |v| <= 1 in its scaled frame): sheets that cross
  // beyond the points turn inside and outside about there.
  for (int i = -4; i <= 4; ++i)
    for (int j = -4; j <= 4; ++j)
      if (!((quadratic_at(a, 0.25 * i, 0.25 * j) - quadratic_at(b, 0.25 * i, 0.25 * j)) / t > 0.2)) return leaf;
  // q t = w² - w (a + b) + a b, in the basis of local_poly.h.
  Coeffs& c = leaf.coeffs;
  c.fill(0);
  c[16] = 1;
  constexpr int kW[6] = {15, 17, 18, 19, 20, 21};  // w times 1, u, v, u², uv, v²
  for (int k = 0; k < 6; ++k) c[size_t(kW[k])] = -(a[size_t(k)] + b[size_t(k)]);
  // Monomial k of bivariate_monomials is u^(d - j) v^j, d its degree: k = d (d + 1) / 2 + j.
  constexpr int kDeg[6] = {0, 1, 1, 2, 2, 2}, kV[6] = {0, 0, 1, 0, 1, 2};
  for (int i = 0; i < 6; ++i)
    for (int k = 0; k < 6; ++k) {
      const int d = kDeg[i] + kDeg[k], j = kV[i] + kV[k];
      c[size_t(d * (d + 1) / 2 + j)] += a[size_t(i)] * b[size_t(k)];
    }
  for (double& x : c) x /= t;
  leaf.degree = 2;
  *error = taubin_error_local(leaf, l);
  return leaf;
}

}  // namespace mpumesh::mpu
