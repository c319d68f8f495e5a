#include "phantom/ct_phantom.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace mpumesh::phantom {
namespace {

// Closest point x on the ellipsoid with semi-axes e to y: x = e² y / (e² + t), where
// F(t) = Σ (e y / (e² + t))² - 1 = 0; F falls monotonically for t > -min(e²), so
// bisection finds t (from either side of the surface).
Eigen::Vector3d ellipsoid_closest(const Eigen::Vector3d& e, const Eigen::Vector3d& y) {
  const Eigen::Vector3d e2 = e.cwiseProduct(e);
  auto F = [&](double t) {
    double s = 0;
    for (int d = 0; d < 3; ++d) {
      const double r = e[d] * y[d] / (e2[d] + t);
      s += r * r;
    }
    return s - 1.0;
  };
  double lo = -e2.minCoeff() * (1 - 1e-12), hi = 1.0;
  while (F(hi) > 0) hi *= 2;
  for (int it = 0; it < 100; ++it) {
    const double m = 0.5 * (lo + hi);
    (F(m) > 0 ? lo : hi) = m;
  }
  const double t = 0.5 * (lo + hi);
  Eigen::Vector3d x;
  for (int d = 0; d < 3; ++d) x[d] = e2[d] * y[d] / (e2[d] + t);
  return x;
}

}  // namespace

bool Shape::inside(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = rotation.transpose() * (p - centre);
  switch (kind) {
    case kEllipsoid: return (q.x() / a) * (q.x() / a) + (q.y() / b) * (q.y() / b) + (q.z() / c) * (q.z() / c) <= 1;
    case kTorus: {
      const double rho = std::hypot(q.x(), q.y()) - a;
      return rho * rho + q.z() * q.z() <= b * b;
    }
    case kCapsule: {
      const double z = q.z() - std::clamp(q.z(), -b, b);
      return q.x() * q.x() + q.y() * q.y() + z * z <= a * a;
    }
    case kShell: {
      const double r2 = q.squaredNorm();
      return r2 <= a * a && r2 >= (a - b) * (a - b);
    }
    case kDisc: {
      const double rho = std::max(std::hypot(q.x(), q.y()) - a, 0.0);
      return rho * rho + q.z() * q.z() <= b * b;
    }
  }
  return false;
}

Eigen::Vector3d Shape::closest_point(const Eigen::Vector3d& p) const {
  Eigen::Vector3d n;
  const double d = distance(p, &n);
  return p + (inside(p) ? d : -d) * n;
}

double Shape::distance(const Eigen::Vector3d& p, Eigen::Vector3d* normal, double* gauss) const {
  const Eigen::Vector3d q = rotation.transpose() * (p - centre);
  Eigen::Vector3d n(0, 0, 1);
  double d = 0, k = 0;
  switch (kind) {
    case kEllipsoid: {
      const Eigen::Vector3d e(a, b, c), x = ellipsoid_closest(e, q);
      const Eigen::Vector3d g = x.cwiseQuotient(e.cwiseProduct(e));
      n = g.normalized();
      d = (q - x).norm();
      k = 1 / (a * a * b * b * c * c * std::pow(g.squaredNorm(), 2));
      break;
    }
    case kTorus: {
      const double rho = std::hypot(q.x(), q.y());
      const Eigen::Vector3d ring =
          rho > 0 ? Eigen::Vector3d(a * q.x() / rho, a * q.y() / rho, 0) : Eigen::Vector3d(a, 0, 0);
      n = (q - ring).normalized();
      const double cosv = n.dot(ring.normalized());
      k = cosv / (b * (a + b * cosv));
      d = std::abs((q - ring).norm() - b);
      break;
    }
    case kCapsule: {
      const Eigen::Vector3d axis(0, 0, std::clamp(q.z(), -b, b));
      n = (q - axis).normalized();
      k = std::abs(q.z()) > b ? 1 / (a * a) : 0;
      d = std::abs((q - axis).norm() - a);
      break;
    }
    case kShell: {
      const double r = q.norm(), inner = a - b;
      const bool outer = std::abs(r - a) <= std::abs(r - inner);
      n = (outer ? 1.0 : -1.0) * q.normalized();
      k = outer ? 1 / (a * a) : 1 / (inner * inner);
      d = outer ? std::abs(r - a) : std::abs(r - inner);
      break;
    }
    case kDisc: {
      // The closest point of the flat disc; the surface lies b from it.
      const double rho = std::hypot(q.x(), q.y());
      const Eigen::Vector3d on_disc = rho > a ? Eigen::Vector3d(a * q.x() / rho, a * q.y() / rho, 0)
                                              : Eigen::Vector3d(q.x(), q.y(), 0);
      const Eigen::Vector3d off = q - on_disc;
      n = off.norm() > 0 ? Eigen::Vector3d(off.normalized()) : Eigen::Vector3d(0, 0, 1);
      d = std::abs(off.norm() - b);
      if (rho > a) {  // the rim: a torus of major radius a, minor b
        const double cosv = n.dot(Eigen::Vector3d(q.x() / rho, q.y() / rho, 0));
        k = cosv / (b * (a + b * cosv));
      }
      break;
    }
  }
  if (normal) *normal = rotation * n;
  if (gauss) *gauss = k;
  return d;
}

bool Shape::on_cap(const Eigen::Vector3d& p) const {
  return kind == kCapsule && std::abs((rotation.transpose() * (p - centre)).z()) > b;
}

Eigen::Vector3d Shape::half_extent() const {
  switch (kind) {
    case kEllipsoid: return {a, b, c};
    case kTorus: return {a + b, a + b, b};
    case kCapsule: return {a, a, a + b};
    case kShell: return Eigen::Vector3d::Constant(a);
    case kDisc: return {a + b, a + b, b};
  }
  return Eigen::Vector3d::Zero();
}

double Shape::volume() const {
  constexpr double pi = 3.14159265358979323846;
  switch (kind) {
    case kEllipsoid: return 4.0 / 3.0 * pi * a * b * c;
    case kTorus: return 2 * pi * pi * a * b * b;
    case kCapsule: return pi * a * a * 2 * b + 4.0 / 3.0 * pi * a * a * a;
    case kShell: return 4.0 / 3.0 * pi * (a * a * a - (a - b) * (a - b) * (a - b));
    // The slab over the disc, and the rim: half a torus (Pappus: the half disc's area
    // times the path of its centroid, a + 4b / 3π from the axis).
    case kDisc: return pi * a * a * 2 * b + pi * pi * a * b * b + 4.0 / 3.0 * pi * b * b * b;
  }
  return 0;
}

double Shape::max_abs_gauss() const {
  switch (kind) {
    case kEllipsoid:
      return std::max({a * a / (b * b * c * c), b * b / (a * a * c * c), c * c / (a * a * b * b)});
    case kTorus: return 1 / (b * (a - b));
    case kCapsule: return 1 / (a * a);
    case kShell: return 1 / ((a - b) * (a - b));
    case kDisc: return 1 / (b * (a + b));
  }
  return 0;
}

Volume phantom_grid(const Eigen::Vector3d& centre, const Eigen::Vector3d& half, const Eigen::Vector3d& spacing) {
  Volume v;
  v.spacing = spacing;
  v.source = "phantom";
  for (int d = 0; d < 3; ++d) v.dims[size_t(d)] = int64_t(std::ceil(2 * half[d] / spacing[d])) + 1;
  v.origin = centre - half + Eigen::Vector3d(0.37 * spacing.x(), 0.21 * spacing.y(), 0.43 * spacing.z());
  v.voxels.assign(size_t(v.voxel_count()), 0.0f);
  return v;
}

Eigen::Matrix3d tilt(double degrees, Eigen::Vector3d axis) {
  return Eigen::AngleAxisd(degrees * 3.14159265358979 / 180, axis.normalized()).toRotationMatrix();
}

namespace {

// The volume's grid over the shape with the scan's margin.
Volume grid_over(const Shape& s, const Scan& c) {
  return phantom_grid(s.centre, s.rotation.cwiseAbs() * s.half_extent() + Eigen::Vector3d::Constant(c.margin_mm),
                      c.spacing);
}

}  // namespace

Volume scan(const Shape& s, const Scan& c) {
  Volume v = grid_over(s, c);
  v.modality = "CT";
  const int nx = c.sub_xy, nz = c.sub_z;
  tbb::parallel_for(int64_t(0), v.dims[2], [&](int64_t k) {
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i) {
        int in = 0;
        for (int t = 0; t < nz; ++t)
          for (int b = 0; b < nx; ++b)
            for (int a = 0; a < nx; ++a) {
              const Eigen::Vector3d ijk(double(i) + (a + 0.5) / nx - 0.5, double(j) + (b + 0.5) / nx - 0.5,
                                        double(k) + (t + 0.5) / nz - 0.5);
              in += s.inside(v.index_to_physical(ijk));
            }
        const double f = double(in) / double(nx * nx * nz);
        v.voxels[size_t(v.index(i, j, k))] = float(c.outside_hu + f * (c.inside_hu - c.outside_hu));
      }
  });
  std::mt19937 rng(c.seed);
  std::normal_distribution<double> noise(0.0, c.noise_hu);
  for (float& x : v.voxels) x = float(std::round(x + noise(rng)));  // whole HU, as CT stores them
  return v;
}


Volume label_scan(const Shape& s, const Scan& c, int label) {
  Volume v = grid_over(s, c);
  tbb::parallel_for(int64_t(0), v.dims[2], [&](int64_t k) {
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i)
        if (s.inside(v.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k)))))
          v.voxels[size_t(v.index(i, j, k))] = float(label);
  });
  return v;
}

std::vector<Phantom> label_suite() {
  std::vector<Phantom> out;
  Phantom e{"ellipsoid", {Shape::kEllipsoid, 26, 19, 13, tilt(25, {1, 1, 0.3}), {1.3, -0.7, 0.4}}, {}};
  e.scan.spacing = {0.7, 0.7, 2.0};
  Phantom t{"torus", {Shape::kTorus, 18, 7, 0, tilt(30, {1, 0.4, 0.2}), {-0.4, 0.9, 0.2}}, {}};
  t.scan.spacing = {0.6, 0.6, 1.8};
  Phantom d{"disc", {Shape::kDisc, 16, 6, 0, tilt(20, {0.3, 1, 0.2}), {0.6, 0.2, -0.8}}, {}};
  d.scan.spacing = {0.7, 0.7, 1.6};
  for (Phantom* p : {&e, &t, &d}) p->scan.noise_hu = 0;
  return {e, t, d};
}

std::vector<Phantom> suite() {
  std::vector<Phantom> out;
  Phantom e{"ellipsoid", {Shape::kEllipsoid, 30, 21, 15, tilt(25, {1, 1, 0.3}), {1.3, -0.7, 0.4}}, {}};
  e.scan.spacing = {0.5, 0.5, 1.5};
  e.scan.noise_hu = 50;
  e.scan.seed = 11;
  Phantom t{"torus", {Shape::kTorus, 20, 7, 0, tilt(30, {1, 0.4, 0.2}), {-0.4, 0.9, 0.2}}, {}};
  t.scan.spacing = {0.6, 0.6, 2.0};
  t.scan.noise_hu = 60;
  t.scan.seed = 12;
  Phantom c{"capsule", {Shape::kCapsule, 10, 15, 0, tilt(35, {0.3, 1, 0}), {0.6, 0.2, -0.8}}, {}};
  c.scan.spacing = {0.7, 0.7, 2.5};
  c.scan.noise_hu = 40;
  c.scan.seed = 13;
  Phantom s{"shell", {Shape::kShell, 22, 2.5, 0, Eigen::Matrix3d::Identity(), {0.3, -0.2, 0.5}}, {}};
  s.scan.spacing = {0.5, 0.5, 1.5};
  s.scan.noise_hu = 50;
  s.scan.seed = 14;
  out = {e, t, c, s};
  return out;
}

}  // namespace mpumesh::phantom
