#include "phantom/material_phantom.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "phantom/ct_phantom.h"

namespace mpumesh::phantom {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kSector = 2 * kPi / 3;
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// A closest point on a patch and the interface normal there (from a into b, local frame).
struct Closest {
  Eigen::Vector3d point{0, 0, 0}, normal{0, 0, 1};
};

// The closest point to q on the part of the sphere of radius r about the origin with
// sign(z) = side (-1: z <= 0, +1: z >= 0); its outward normal.
Closest hemisphere(const Eigen::Vector3d& q, double r, int side) {
  Closest c;
  if (q.z() * side >= 0 && q.norm() > 0) {
    c.normal = q.normalized();
  } else {
    const double rho = std::hypot(q.x(), q.y());
    c.normal = rho > 0 ? Eigen::Vector3d(q.x() / rho, q.y() / rho, 0) : Eigen::Vector3d(1, 0, 0);
  }
  c.point = r * c.normal;
  return c;
}

// The closest point to (x, y) in the disc of radius r, or in the annulus r0 <= rho <= r.
Eigen::Vector2d in_annulus(const Eigen::Vector2d& xy, double r0, double r) {
  const double rho = xy.norm();
  if (rho == 0) return {r0, 0};
  return xy * (std::clamp(rho, r0, r) / rho);
}

double angle_of(const Eigen::Vector3d& q) {
  double phi = std::atan2(q.y(), q.x());
  return phi < 0 ? phi + 2 * kPi : phi;
}

Eigen::Vector3d direction(double phi) { return {std::cos(phi), std::sin(phi), 0}; }

double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - a - t * ab).norm();
}

// Sectors: the closest point to the 2-D point xy in the wedge of sector k (angles
// [k, k + 1] × 120°) within radius r.
Eigen::Vector2d in_wedge(const Eigen::Vector2d& xy, int k, double r) {
  const double lo = k * kSector;
  const double rel = std::remainder(std::atan2(xy.y(), xy.x()) - lo - kSector / 2, 2 * kPi);
  if (std::abs(rel) <= kSector / 2) return in_annulus(xy, 0, r);
  Eigen::Vector2d best{0, 0};
  double best_d = kInfinity;
  for (const double beta : {lo, lo + kSector}) {
    const Eigen::Vector2d e(std::cos(beta), std::sin(beta));
    const Eigen::Vector2d x = std::clamp(xy.dot(e), 0.0, r) * e;
    if ((xy - x).norm() < best_d) best_d = (xy - x).norm(), best = x;
  }
  return best;
}

// Sectors: the seam angle and the normal's sign (from a into b along increasing angle)
// between labels a < b.
std::pair<double, double> seam(int a, int b) {
  if (a == 1 && b == 2) return {kSector, 1};
  if (a == 2 && b == 3) return {2 * kSector, 1};
  return {0, -1};  // (1, 3): at 0, label 3 below it
}

// The distance from q (local frame) to the interface (a, b), its closest point and normal
// in c; infinity where there is none.
double local_interface(const MaterialPhantom& m, int a, int b, const Eigen::Vector3d& q, Closest& c) {
  const double r = m.radius;
  auto take = [&](const Closest& x, double& best, Closest& out) {
    const double d = (q - x.point).norm();
    if (d < best) best = d, out = x;
  };
  double best = kInfinity;
  switch (m.kind) {
    case MaterialPhantom::kSplitBall:
      if (a == 0) {  // the hemisphere of label b: b = 1 below the plane, 2 above
        c = hemisphere(q, r, b == 1 ? -1 : 1);
        c.normal = -c.normal;
      } else {
        const Eigen::Vector2d xy = in_annulus(q.head<2>(), 0, r);
        c = {Eigen::Vector3d(xy.x(), xy.y(), 0), Eigen::Vector3d(0, 0, 1)};
      }
      return (q - c.point).norm();
    case MaterialPhantom::kNested: {
      const Eigen::Vector3d n = q.norm() > 0 ? q.normalized() : Eigen::Vector3d(1, 0, 0);
      if (a == 0 && b == 2) c = {r * n, -n};
      else if (a == 1 && b == 2) c = {m.inner * n, n};
      else return kInfinity;
      return (q - c.point).norm();
    }
    case MaterialPhantom::kSectors: {
      const double h = m.inner;
      if (a > 0) {
        const auto [beta, sign] = seam(a, b);
        const Eigen::Vector3d e = direction(beta);
        c.point = std::clamp(q.dot(e), 0.0, r) * e + Eigen::Vector3d(0, 0, std::clamp(q.z(), -h, h));
        c.normal = sign * Eigen::Vector3d(-e.y(), e.x(), 0);
        return (q - c.point).norm();
      }
      const int k = b - 1;
      // The barrel: the angle clamped into the sector, the height into the length.
      const double rel = std::remainder(angle_of(q) - k * kSector - kSector / 2, 2 * kPi);
      const double phi = k * kSector + kSector / 2 + std::clamp(rel, -kSector / 2, kSector / 2);
      take({direction(phi) * r + Eigen::Vector3d(0, 0, std::clamp(q.z(), -h, h)), -direction(phi)}, best, c);
      const Eigen::Vector2d xy = in_wedge(q.head<2>(), k, r);
      for (const double z : {-h, h}) take({Eigen::Vector3d(xy.x(), xy.y(), z), Eigen::Vector3d(0, 0, -z / h)}, best, c);
      return best;
    }
    case MaterialPhantom::kJoint: {
      const double r1 = r + m.inner, r2 = r1 + m.thickness;
      if (a == 0 && b == 1) {
        const Eigen::Vector3d n = q.norm() > 0 ? q.normalized() : Eigen::Vector3d(1, 0, 0);
        c = {r * n, -n};
        return (q - c.point).norm();
      }
      if (a != 0 || b != 2) return kInfinity;
      Closest x = hemisphere(q, r1, -1);  // the cup's inside: the gap (0) within it
      take(x, best, c);
      x = hemisphere(q, r2, -1);
      x.normal = -x.normal;
      take(x, best, c);
      const Eigen::Vector2d xy = in_annulus(q.head<2>(), r1, r2);
      take({Eigen::Vector3d(xy.x(), xy.y(), 0), Eigen::Vector3d(0, 0, -1)}, best, c);
      return best;
    }
  }
  return kInfinity;
}

// The straight junction curves (local frame): the sectors' axis, seams and end-face radii.
// The split ball's circle has its own closed form.
std::vector<std::array<Eigen::Vector3d, 2>> junction_segments(const MaterialPhantom& m) {
  std::vector<std::array<Eigen::Vector3d, 2>> out;
  if (m.kind != MaterialPhantom::kSectors) return out;
  const double r = m.radius, h = m.inner;
  out.push_back({Eigen::Vector3d(0, 0, -h), Eigen::Vector3d(0, 0, h)});
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = r * direction(k * kSector);
    out.push_back({e + Eigen::Vector3d(0, 0, -h), e + Eigen::Vector3d(0, 0, h)});
    for (const double z : {-h, h}) out.push_back({Eigen::Vector3d(0, 0, z), e + Eigen::Vector3d(0, 0, z)});
  }
  return out;
}

}  // namespace

int MaterialPhantom::label_at(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = rotation.transpose() * (p - centre);
  const double d = q.norm();
  switch (kind) {
    case kSplitBall:
      return d <= radius ? (q.z() < 0 ? 1 : 2) : 0;
    case kNested:
      return d <= inner ? 1 : d <= radius ? 2 : 0;
    case kSectors:
      if (std::abs(q.z()) > inner || std::hypot(q.x(), q.y()) > radius) return 0;
      return std::min(int(angle_of(q) / kSector), 2) + 1;
    case kJoint:
      if (d <= radius) return 1;
      return d >= radius + inner && d <= radius + inner + thickness && q.z() <= 0 ? 2 : 0;
  }
  return 0;
}

std::vector<int> MaterialPhantom::labels() const {
  if (kind == kSectors) return {1, 2, 3};
  return {1, 2};
}

double MaterialPhantom::label_volume(int label) const {
  const double r3 = radius * radius * radius;
  switch (kind) {
    case kSplitBall:
      return label == 1 || label == 2 ? 2.0 / 3.0 * kPi * r3 : 0;
    case kNested:
      return label == 1 ? 4.0 / 3.0 * kPi * inner * inner * inner : label == 2 ? 4.0 / 3.0 * kPi * (r3 - std::pow(inner, 3)) : 0;
    case kSectors:
      return label >= 1 && label <= 3 ? kPi * radius * radius * 2 * inner / 3 : 0;
    case kJoint: {
      const double r1 = radius + inner, r2 = r1 + thickness;
      return label == 1 ? 4.0 / 3.0 * kPi * r3 : label == 2 ? 2.0 / 3.0 * kPi * (r2 * r2 * r2 - r1 * r1 * r1) : 0;
    }
  }
  return 0;
}

bool MaterialPhantom::shares_interface(int a, int b) const {
  if (a >= b) return false;
  switch (kind) {
    case kSplitBall: return b <= 2;
    case kNested: return b == 2;
    case kSectors: return b <= 3;
    case kJoint: return a == 0 && b <= 2;
  }
  return false;
}

double MaterialPhantom::interface_distance(int a, int b, const Eigen::Vector3d& p, Eigen::Vector3d* normal,
                                           Eigen::Vector3d* closest) const {
  if (!shares_interface(a, b)) return kInfinity;
  Closest c;
  const double d = local_interface(*this, a, b, rotation.transpose() * (p - centre), c);
  if (normal) *normal = rotation * c.normal;
  if (closest) *closest = centre + rotation * c.point;
  return d;
}

double MaterialPhantom::junction_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = rotation.transpose() * (p - centre);
  if (kind == kSplitBall) return std::hypot(std::hypot(q.x(), q.y()) - radius, q.z());
  double best = kInfinity;
  for (const auto& s : junction_segments(*this)) best = std::min(best, segment_distance(q, s[0], s[1]));
  return best;
}

double MaterialPhantom::rim_distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = rotation.transpose() * (p - centre);
  // A circle of radius r in the plane z = z0 of the local frame.
  auto circle = [&](double r, double z0) { return std::hypot(std::hypot(q.x(), q.y()) - r, q.z() - z0); };
  double rim = kInfinity;
  if (kind == kSectors) rim = std::min(circle(radius, -inner), circle(radius, inner));
  if (kind == kJoint) rim = std::min(circle(radius + inner, 0), circle(radius + inner + thickness, 0));
  return std::min(rim, junction_distance(p));
}

std::vector<Eigen::Vector3d> MaterialPhantom::junction_points(double step) const {
  std::vector<Eigen::Vector3d> local;
  if (kind == kSplitBall) {
    const int n = std::max(8, int(std::ceil(2 * kPi * radius / step)));
    for (int i = 0; i < n; ++i) local.push_back(radius * direction(2 * kPi * i / n));
  }
  for (const auto& s : junction_segments(*this)) {
    const int n = std::max(1, int(std::ceil((s[1] - s[0]).norm() / step)));
    for (int i = 0; i <= n; ++i) local.push_back(s[0] + (s[1] - s[0]) * (double(i) / n));
  }
  for (auto& x : local) x = centre + rotation * x;
  return local;
}

double MaterialPhantom::extent() const {
  switch (kind) {
    case kSectors: return std::hypot(radius, inner);
    case kJoint: return radius + inner + thickness;
    default: return radius;
  }
}

Volume material_scan(const MaterialPhantom& m) {
  Volume v = phantom_grid(m.centre, Eigen::Vector3d::Constant(m.extent() + m.margin_mm), m.spacing);
  v.source = "phantom " + m.name;
  tbb::parallel_for(int64_t(0), v.dims[2], [&](int64_t k) {
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i)
        v.voxels[size_t(v.index(i, j, k))] =
            float(m.label_at(v.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k)))));
  });
  return v;
}

std::vector<MaterialPhantom> material_suite() {
  std::vector<MaterialPhantom> out;
  MaterialPhantom s;
  s.kind = MaterialPhantom::kSplitBall, s.name = "split ball", s.radius = 15;
  s.rotation = tilt(25, {1, 1, 0.3}), s.centre = {1.3, -0.7, 0.4}, s.spacing = {0.7, 0.7, 2.0};
  out.push_back(s);
  MaterialPhantom n;
  n.kind = MaterialPhantom::kNested, n.name = "nested", n.radius = 15, n.inner = 8;
  n.rotation = tilt(30, {1, 0.4, 0.2}), n.centre = {-0.4, 0.9, 0.2}, n.spacing = {0.6, 0.6, 1.8};
  out.push_back(n);
  MaterialPhantom c;
  c.kind = MaterialPhantom::kSectors, c.name = "sectors", c.radius = 12, c.inner = 14;
  c.rotation = tilt(20, {0.3, 1, 0.2}), c.centre = {0.6, 0.2, -0.8}, c.spacing = {0.7, 0.7, 1.6};
  out.push_back(c);
  MaterialPhantom j;
  j.kind = MaterialPhantom::kJoint, j.name = "joint", j.radius = 10, j.thickness = 4;
  j.rotation = tilt(35, {0.3, 1, 0}), j.centre = {0.3, -0.5, 0.6}, j.spacing = {0.7, 0.7, 1.6};
  j.inner = j.spacing.z();  // a gap of one slice spacing
  out.push_back(j);
  return out;
}

}  // namespace mpumesh::phantom
