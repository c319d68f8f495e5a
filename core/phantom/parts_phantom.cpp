#include "phantom/parts_phantom.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "phantom/truth_figures.h"

namespace mpumesh::phantom {
namespace {

// A profile point: the distance from the axis and the height along it.
struct Rz {
  double rho, z;
};

// The closed surface of revolution of `profile` (its first and last points on the axis)
// about the z axis, `n` vertices to a ring, outward. Between two rings each quad is split
// along the diagonal from the inner ring's vertex j to the outer ring's j+1, so that two
// surfaces with a common stretch of profile have the same triangles there.
TriangleMesh lathe(const std::vector<Rz>& profile, int n) {
  TriangleMesh m;
  const size_t rings = profile.size() - 2;
  m.vertices.push_back({0, 0, profile.front().z});
  for (size_t i = 1; i + 1 < profile.size(); ++i)
    for (int j = 0; j < n; ++j) {
      const double a = 2 * M_PI * j / n;
      m.vertices.push_back({profile[i].rho * std::cos(a), profile[i].rho * std::sin(a), profile[i].z});
    }
  m.vertices.push_back({0, 0, profile.back().z});
  const uint32_t last = uint32_t(m.vertices.size() - 1);
  auto at = [&](size_t ring, int j) { return uint32_t(1 + ring * size_t(n) + size_t((j + n) % n)); };
  for (int j = 0; j < n; ++j) {
    m.triangles.push_back({0, at(0, j + 1), at(0, j)});
    m.triangles.push_back({last, at(rings - 1, j), at(rings - 1, j + 1)});
  }
  for (size_t i = 0; i + 1 < rings; ++i) {
    const bool a_inner = profile[i + 1].rho < profile[i + 2].rho;
    for (int j = 0; j < n; ++j) {
      const uint32_t a0 = at(i, j), a1 = at(i, j + 1), b0 = at(i + 1, j), b1 = at(i + 1, j + 1);
      if (a_inner) {
        m.triangles.push_back({a0, b1, b0});
        m.triangles.push_back({a0, a1, b1});
      } else {
        m.triangles.push_back({a0, a1, b0});
        m.triangles.push_back({a1, b1, b0});
      }
    }
  }
  if (enclosed_volume(m) < 0)
    for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

// Points along the arc of the ellipse (rho, z) = (a cos phi, c sin phi) from phi0 to
// phi1, ends included, about `edge` apart.
std::vector<Rz> arc(double a, double c, double phi0, double phi1, double edge) {
  const int steps = std::max(2, int(std::ceil(std::max(a, c) * std::abs(phi1 - phi0) / edge)));
  std::vector<Rz> out;
  for (int k = 0; k <= steps; ++k) {
    const double phi = phi0 + (phi1 - phi0) * k / steps;
    out.push_back({std::abs(phi) == M_PI / 2 ? 0.0 : a * std::cos(phi), c * std::sin(phi)});
  }
  return out;
}

// Points along the segment from the axis at height z out to rho, about `edge` apart,
// ends included, from the axis outward.
std::vector<Rz> disc(double rho, double z, double edge) {
  const int steps = std::max(2, int(std::ceil(rho / edge)));
  std::vector<Rz> out;
  for (int k = 0; k <= steps; ++k) out.push_back({rho * k / steps, z});
  return out;
}

// `p` without its last point, followed by `q` (whose first point is the same, as the disc
// computes it, so that the parts that share the disc share its rim exactly).
std::vector<Rz> joined(std::vector<Rz> p, const std::vector<Rz>& q) {
  p.pop_back();
  p.insert(p.end(), q.begin(), q.end());
  return p;
}

int ring_count(double radius, double edge) { return std::max(12, int(std::ceil(2 * M_PI * radius / edge))); }

void append(TriangleMesh& all, const TriangleMesh& part, const Eigen::Matrix3d& rotation,
            const Eigen::Vector3d& centre) {
  const uint32_t base = uint32_t(all.vertices.size());
  for (const auto& v : part.vertices) all.vertices.push_back(rotation * v + centre);
  for (const auto& t : part.triangles) all.triangles.push_back({t[0] + base, t[1] + base, t[2] + base});
}

// The distance from (rho, z) to the ellipse (a cos t, c sin t), rho >= 0: Newton steps on
// the foot point's parameter from the radial guess.
double ellipse_distance(double rho, double z, double a, double c) {
  if (a == c) return std::abs(std::hypot(rho, z) - a);
  double t = std::atan2(z * a, rho * c);
  for (int it = 0; it < 30; ++it) {
    const double ct = std::cos(t), st = std::sin(t);
    const double dx = a * ct - rho, dz = c * st - z;
    // d/dt of half the squared distance, and its derivative.
    const double g = -dx * a * st + dz * c * ct;
    const double h = a * a * st * st + c * c * ct * ct - dx * a * ct - dz * c * st;
    if (!(std::abs(h) > 1e-15)) break;
    t -= g / h;
  }
  return std::hypot(a * std::cos(t) - rho, c * std::sin(t) - z);
}

}  // namespace

double TruePart::distance(const Eigen::Vector3d& p) const {
  const Eigen::Vector3d q = rotation.transpose() * (p - centre);
  const double rho = std::hypot(q.x(), q.y());
  if (side == 0) return ellipse_distance(rho, q.z(), a, c);
  const double rim = std::sqrt(a * a - cut * cut);
  const double to_rim = std::hypot(rho - rim, q.z() - cut);
  // The ball's part: its nearest point when that lies on the kept side, else the rim.
  const double r = q.norm();
  const double foot_z = r > 0 ? a * q.z() / r : a;
  const double to_ball = (foot_z - cut) * side >= 0 ? std::abs(r - a) : to_rim;
  const double to_disc = rho <= rim ? std::abs(q.z() - cut) : to_rim;
  return std::min(to_ball, to_disc);
}

double PartsPhantom::true_distance(const Eigen::Vector3d& p) const {
  double d = INFINITY;
  for (const TruePart& t : truth) d = std::min(d, t.distance(p));
  return d;
}

PartsPhantom::Distances PartsPhantom::distance_to_truth(const TriangleMesh& m) const {
  std::vector<double> d, w;
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const double area = 0.5 * (b - a).cross(c - a).norm();
    for (const Eigen::Vector3d* q : {&a, &b, &c}) {
      d.push_back(true_distance((2.0 / 3.0) * *q + (1.0 / 6.0) * (a + b + c - *q)));
      w.push_back(area / 3);
    }
  }
  Distances out;
  double total = 0;
  for (size_t k = 0; k < d.size(); ++k) out.mean += d[k] * w[k], total += w[k];
  if (total > 0) out.mean /= total;
  out.p99 = weighted_quantile(d, w, 0.99);
  return out;
}

PartsPhantom parts_phantom(double edge, double gap) {
  const double R = 10, cut = 2.5, rim = std::sqrt(R * R - cut * cut), phi_cut = std::asin(cut / R);
  const int n = ring_count(R, edge);
  std::vector<Rz> rim_in = disc(rim, cut, edge);
  std::reverse(rim_in.begin(), rim_in.end());
  const TriangleMesh lower = lathe(joined(arc(R, R, -M_PI / 2, phi_cut, edge), rim_in), n);
  std::vector<Rz> cap_profile = disc(rim, cut, edge);
  const std::vector<Rz> cap_arc = arc(R, R, phi_cut, M_PI / 2, edge);
  cap_profile.insert(cap_profile.end(), cap_arc.begin() + 1, cap_arc.end());
  const TriangleMesh cap = lathe(cap_profile, n);
  auto ball = [&](double a, double c) { return lathe(arc(a, c, -M_PI / 2, M_PI / 2, edge), ring_count(a, edge)); };
  const TriangleMesh ball5 = ball(5, 5), spheroid = ball(4, 7), ball3 = ball(3, 3);
  // The whole tilted about a skew axis; each smaller part turned about its own too.
  const Eigen::Matrix3d tilt = Eigen::AngleAxisd(0.35, Eigen::Vector3d(1, 2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Matrix3d own = Eigen::AngleAxisd(0.6, Eigen::Vector3d(0.3, 1, 0.2).normalized()).toRotationMatrix();
  PartsPhantom p;
  p.gap = gap;
  const Eigen::Vector3d origin(1.3, -0.7, 0.4);
  auto add = [&](const TriangleMesh& m, const TruePart& t) {
    append(p.mesh, m, t.rotation, t.centre);
    p.truth.push_back(t);
  };
  add(lower, {tilt, origin, R, R, -1, cut});
  add(cap, {tilt, origin, R, R, 1, cut});
  // Part 1's surface along ±x (in its frame) is its sphere's equator, below the cut.
  add(ball5, {tilt * own, origin + tilt * Eigen::Vector3d(-(R + gap + 5), 0, 0), 5, 5, 0, 0});
  // The spheroid's axis along z: its equator (radius 4) faces the ball along x.
  add(spheroid, {tilt, origin + tilt * Eigen::Vector3d(R + gap + 4, 0, 0), 4, 7, 0, 0});
  add(ball3, {tilt * own, origin + tilt * Eigen::Vector3d(0, R + 3 + 3, -1), 3, 3, 0, 0});
  for (const TriangleMesh* m : {&lower, &cap, &ball5, &spheroid, &ball3}) p.part_volumes.push_back(enclosed_volume(*m));
  p.touching = {{1, 2}};
  return p;
}

}  // namespace mpumesh::phantom
