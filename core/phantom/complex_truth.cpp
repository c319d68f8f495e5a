#include "phantom/complex_truth.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "geometry/angle.h"
#include "multi/complex_figures.h"
#include "phantom/truth_figures.h"

namespace mpumesh::phantom {
namespace {

double segment_distance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double len2 = ab.squaredNorm();
  const double t = len2 > 0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return (a + t * ab - p).norm();
}

struct Samples {
  std::vector<double> distance, distance_w, angle, angle_w, angle_away, angle_away_w;
};

double weighted_mean(const std::vector<double>& x, const std::vector<double>& w) {
  double s = 0, t = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    s += x[i] * w[i];
    t += w[i];
  }
  return t > 0 ? s / t : 0;
}

// One face's samples: the distances at its centroid and three inner points (a quarter of
// its area each), and its normal's angle to the true one at its centroid.
void sample_face(const MaterialPhantom& m, int a, int b, const Eigen::Vector3d (&v)[3], double rim, Samples& s) {
  const Eigen::Vector3d cr = (v[1] - v[0]).cross(v[2] - v[0]);
  const double area = 0.5 * cr.norm();
  if (!(area > 0)) return;
  const Eigen::Vector3d c = (v[0] + v[1] + v[2]) / 3;
  const Eigen::Vector3d pts[4] = {c, (4 * v[0] + v[1] + v[2]) / 6, (v[0] + 4 * v[1] + v[2]) / 6,
                                  (v[0] + v[1] + 4 * v[2]) / 6};
  for (const Eigen::Vector3d& p : pts) {
    s.distance.push_back(m.interface_distance(a, b, p));
    s.distance_w.push_back(area / 4);
  }
  Eigen::Vector3d n;
  m.interface_distance(a, b, c, &n);
  const double angle = angle_between(cr, n) * 180 / M_PI;
  s.angle.push_back(angle);
  s.angle_w.push_back(area);
  if (m.rim_distance(c) > rim) {
    s.angle_away.push_back(angle);
    s.angle_away_w.push_back(area);
  }
}

}  // namespace

ComplexTruth complex_truth(const MaterialPhantom& m, const TriangleMesh& c, double rim) {
  ComplexTruth out;
  std::map<std::array<int32_t, 2>, Samples> by_pair;
  Samples all;
  for (size_t t = 0; t < c.triangles.size(); ++t) {
    const auto& l = c.face_labels[t];
    if (!m.shares_interface(l[0], l[1])) {
      ++out.foreign_triangles;
      continue;
    }
    const Eigen::Vector3d v[3] = {c.vertices[c.triangles[t][0]], c.vertices[c.triangles[t][1]],
                                  c.vertices[c.triangles[t][2]]};
    sample_face(m, l[0], l[1], v, rim, by_pair[l]);
    sample_face(m, l[0], l[1], v, rim, all);
  }
  auto fill = [](const Samples& s, InterfaceTruth& f) {
    f.distance_mean = weighted_mean(s.distance, s.distance_w);
    f.distance_p99 = weighted_quantile(s.distance, s.distance_w, 0.99);
    f.normal_mean_deg = weighted_mean(s.angle, s.angle_w);
    f.normal_p95_deg = weighted_quantile(s.angle, s.angle_w, 0.95);
    f.normal_mean_away_deg = weighted_mean(s.angle_away, s.angle_away_w);
    f.normal_p95_away_deg = weighted_quantile(s.angle_away, s.angle_away_w, 0.95);
  };
  for (const auto& [pair, s] : by_pair) {
    InterfaceTruth f;
    f.a = pair[0];
    f.b = pair[1];
    f.true_interface = true;
    f.triangles = int64_t(s.angle.size());
    fill(s, f);
    out.interfaces.push_back(f);
  }
  InterfaceTruth whole;
  fill(all, whole);
  out.distance_mean = whole.distance_mean;
  out.distance_p99 = whole.distance_p99;
  out.normal_mean_deg = whole.normal_mean_deg;
  out.normal_p95_deg = whole.normal_p95_deg;
  out.normal_mean_away_deg = whole.normal_mean_away_deg;
  out.normal_p95_away_deg = whole.normal_p95_away_deg;
  // Junctions: points along our junction edges against the true curves, and the true
  // curves' points against our edges.
  const auto edges = multi::junction_edges(c);
  out.junction_edges = int64_t(edges.size());
  std::vector<double> jd;
  for (const auto& e : edges)
    for (int k = 0; k <= 4; ++k) {
      const Eigen::Vector3d p = c.vertices[e[0]] + (c.vertices[e[1]] - c.vertices[e[0]]) * (k / 4.0);
      jd.push_back(m.junction_distance(p));
    }
  if (!jd.empty()) {
    out.junction_p95 = weighted_quantile(jd, std::vector<double>(jd.size(), 1.0), 0.95);
    out.junction_max = *std::max_element(jd.begin(), jd.end());
  }
  const std::vector<Eigen::Vector3d> truth = m.junction_points(0.5);
  std::vector<double> cover;
  for (const Eigen::Vector3d& p : truth) {
    double best = INFINITY;
    for (const auto& e : edges) best = std::min(best, segment_distance(p, c.vertices[e[0]], c.vertices[e[1]]));
    cover.push_back(best);
  }
  if (!cover.empty()) out.junction_cover_p95 = weighted_quantile(cover, std::vector<double>(cover.size(), 1.0), 0.95);
  for (const int label : m.labels()) {
    const double truth_volume = m.label_volume(label);
    LabelTruth l;
    l.label = label;
    l.volume_error = (enclosed_volume(multi::label_boundary(c, label)) - truth_volume) / truth_volume;
    out.worst_volume_error = std::max(out.worst_volume_error, std::abs(l.volume_error));
    out.labels.push_back(l);
  }
  return out;
}

}  // namespace mpumesh::phantom
