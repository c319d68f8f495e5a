#include "mesh/quality.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <span>
#include <sstream>

#include <fmt/format.h>

#include "mesh/cgal_geometry.h"
#include "mesh/edge_faces.h"

namespace mpumesh {
namespace {

constexpr double kDeg = 180.0 / std::numbers::pi;

// Value below which `q` of the total weight lies.
double weighted_quantile(std::vector<std::pair<double, double>> vw, double q) {
  if (vw.empty()) return 0;
  std::sort(vw.begin(), vw.end());
  double total = 0;
  for (const auto& [v, w] : vw) total += w;
  double acc = 0;
  for (const auto& [v, w] : vw) {
    acc += w;
    if (acc >= q * total) return v;
  }
  return vw.back().first;
}

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size())));
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(k), v.end());
  return v[k];
}

DistanceStats stats_of(const DistanceSamples& s) {
  DistanceStats d;
  std::vector<std::pair<double, double>> vw;
  double sw = 0;
  for (size_t i = 0; i < s.distance.size(); ++i) {
    d.mean += s.distance[i] * s.weight[i];
    sw += s.weight[i];
    d.max = std::max(d.max, s.distance[i]);
    vw.push_back({s.distance[i], s.weight[i]});
  }
  d.mean = sw > 0 ? d.mean / sw : 0;
  d.p99 = weighted_quantile(std::move(vw), 0.99);
  return d;
}

}  // namespace

// The smallest angle lies opposite the shortest side: only the angles opposite sides
// within a relative 1e-6 (in squared length) of the shortest are computed. A side longer
// than that faces an angle larger by a relative 5e-7 or more (law of sines), far beyond
// atan2's rounding, so the minimum is the one of all three, bit for bit, for a third of
// the atan2 calls (with all three, the mesh optimisation spends 16% of its time in them).
double triangle_min_angle_deg(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  const double la = (b - c).squaredNorm(), lb = (a - c).squaredNorm(), lc = (a - b).squaredNorm();
  const double shortest = std::min({la, lb, lc});
  if (!std::isfinite(la + lb + lc))
    return std::min({angle_between(b - a, c - a), angle_between(a - b, c - b), angle_between(a - c, b - c)}) * kDeg;
  const double near = shortest * (1 + 1e-6);
  double m = INFINITY;
  if (la <= near) m = std::min(m, angle_between(b - a, c - a));
  if (lb <= near) m = std::min(m, angle_between(a - b, c - b));
  if (lc <= near) m = std::min(m, angle_between(a - c, b - c));
  return m * kDeg;
}

// The scans over every triangle (the clean-up's collapse and flip passes, the
// optimisation's moves) ask this of every triangle, and the arc tangents would cost them
// most of their time.
bool triangle_min_angle_below(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
                              double deg) {
  const Eigen::Vector3d ab = b - a, bc = c - b, ca = a - c;
  const double lab = ab.squaredNorm(), lbc = bc.squaredNorm(), lca = ca.squaredNorm();
  // cos of the angles at a, b, c; an angle is below deg when its cosine is above cos(deg).
  const double den_a = std::sqrt(lab * lca), den_b = std::sqrt(lab * lbc), den_c = std::sqrt(lbc * lca);
  const double cmax = std::max({-ab.dot(ca) / den_a, -ab.dot(bc) / den_b, -bc.dot(ca) / den_c});
  // 1e-6 of margin in the cosine (about 0.0002 deg at 20 deg) covers the rounding of both
  // forms; a degenerate triangle (NaN) goes to the exact test.
  if (cmax < std::cos(deg * M_PI / 180) - 1e-6) return false;
  return triangle_min_angle_deg(a, b, c) < deg;
}

double triangle_radius_ratio(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  // r_in = 2A / P, r_circ = abc / 4A, so 2 r_in / r_circ = 16 A^2 / (abc P).
  const double la = (b - c).norm(), lb = (a - c).norm(), lc = (a - b).norm();
  const double area = 0.5 * (b - a).cross(c - a).norm();
  const double den = la * lb * lc * (la + lb + lc);
  return den > 0 ? 16.0 * area * area / den : 0.0;
}

TriangleShapes triangle_shapes(const TriangleMesh& mesh) {
  TriangleShapes s;
  s.min_angle_deg.reserve(mesh.triangles.size());
  s.radius_ratio.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    s.min_angle_deg.push_back(triangle_min_angle_deg(a, b, c));
    s.radius_ratio.push_back(triangle_radius_ratio(a, b, c));
  }
  return s;
}

Quality measure_quality(const TriangleMesh& mesh, const QualityOptions& opt) {
  Quality q;
  q.topo = analyze_topology(mesh);
  const size_t nf = mesh.triangles.size();
  if (nf == 0) return q;
  std::vector<Eigen::Vector3d> normal(nf);
  const TriangleShapes shapes = triangle_shapes(mesh);
  const std::vector<double>& min_angle = shapes.min_angle_deg;
  double edge_sum = 0;
  int64_t edge_count = 0;
  q.edge_min = INFINITY;
  double ratio_sum = 0, axis_area = 0;
  int64_t below[3] = {0, 0, 0}, ratio_below = 0;
  const double cos5 = std::cos(5.0 / kDeg);
  for (size_t f = 0; f < nf; ++f) {
    const auto& t = mesh.triangles[f];
    const Eigen::Vector3d &a = mesh.vertices[t[0]], &b = mesh.vertices[t[1]], &c = mesh.vertices[t[2]];
    const Eigen::Vector3d cr = (b - a).cross(c - a);
    const double area = 0.5 * cr.norm();
    q.zero_area_triangles += t[0] != t[1] && t[1] != t[2] && t[0] != t[2] &&
                             !(area > 1e-12 * std::max({(b - a).squaredNorm(), (c - a).squaredNorm(), 1e-300}));
    q.area_mm2 += area;
    q.volume_mm3 += a.dot(b.cross(c)) / 6.0;
    normal[f] = area > 0 ? Eigen::Vector3d(cr / (2 * area)) : Eigen::Vector3d::Zero();
    if (normal[f].cwiseAbs().maxCoeff() >= cos5) axis_area += area;
    for (double len : {(b - a).norm(), (c - b).norm(), (a - c).norm()}) {
      q.edge_min = std::min(q.edge_min, len);
      q.edge_max = std::max(q.edge_max, len);
      edge_sum += len;
      ++edge_count;
    }
    q.angle_mean += min_angle[f];
    for (int k = 0; k < 3; ++k) below[k] += min_angle[f] < 10.0 * (k + 1);
    const double rr = shapes.radius_ratio[f];
    ratio_sum += rr;
    ratio_below += rr < 0.5;
  }
  const double n = double(nf);
  q.edge_mean = edge_sum / double(edge_count);
  q.angle_mean /= n;
  q.angle_min = *std::min_element(min_angle.begin(), min_angle.end());
  q.angle_p01 = quantile(min_angle, 0.01);
  for (int k = 0; k < 3; ++k) q.pct_angle_below[k] = 100.0 * double(below[k]) / n;
  q.radius_ratio_mean = ratio_sum / n;
  q.pct_radius_ratio_below_half = 100.0 * double(ratio_below) / n;
  q.pct_area_axis_aligned = q.area_mm2 > 0 ? 100.0 * axis_area / q.area_mm2 : 0;
  // Dihedral angles over edges with exactly two faces.
  const EdgeFaces edges(mesh.triangles);
  std::vector<double> dihedral;
  for (size_t e = 0; e < edges.size(); ++e) {
    const std::span<const uint32_t> faces = edges.faces(e);
    if (faces.size() == 2) dihedral.push_back(angle_between(normal[faces[0]], normal[faces[1]]) * kDeg);
  }
  if (!dihedral.empty()) {
    double s = 0;
    for (double d : dihedral) s += d;
    q.dihedral_mean = s / double(dihedral.size());
    q.dihedral_p99 = quantile(dihedral, 0.99);
  }
  if (opt.self_intersections) q.self_intersections = count_self_intersections(mesh);
  if (opt.reference) {
    q.to_reference = stats_of(sample_distances(mesh, *opt.reference));
    q.from_reference = stats_of(sample_distances(*opt.reference, mesh));
    q.hausdorff_mm = std::max(q.to_reference->max, q.from_reference->max);
    q.mean_distance_mm = 0.5 * (q.to_reference->mean + q.from_reference->mean);
  }
  return q;
}

nlohmann::json quality_to_json(const Quality& q) {
  nlohmann::json j;
  j["vertices"] = q.topo.vertices;
  j["triangles"] = q.topo.triangles;
  j["closed"] = q.topo.closed;
  j["manifold"] = q.topo.manifold;
  j["oriented"] = q.topo.oriented;
  j["components"] = q.topo.components;
  j["euler"] = q.topo.euler;
  j["genus"] = q.topo.genus;
  j["border_edges"] = q.topo.border_edges;
  j["nonmanifold_edges"] = q.topo.nonmanifold_edges;
  j["nonmanifold_vertices"] = q.topo.nonmanifold_vertices;
  j["degenerate_triangles"] = q.topo.degenerate_triangles;
  j["zero_area_triangles"] = q.zero_area_triangles;
  j["self_intersections"] = q.self_intersections < 0 ? nlohmann::json() : nlohmann::json(q.self_intersections);
  j["area_mm2"] = q.area_mm2;
  j["volume_mm3"] = q.volume_mm3;
  j["edge_mm"] = {{"min", q.edge_min}, {"mean", q.edge_mean}, {"max", q.edge_max}};
  j["min_angle_deg"] = {{"min", q.angle_min}, {"p01", q.angle_p01}, {"mean", q.angle_mean}};
  j["pct_min_angle_below"] = {{"10", q.pct_angle_below[0]}, {"20", q.pct_angle_below[1]}, {"30", q.pct_angle_below[2]}};
  j["radius_ratio"] = {{"mean", q.radius_ratio_mean}, {"pct_below_0_5", q.pct_radius_ratio_below_half}};
  j["dihedral_deg"] = {{"mean", q.dihedral_mean}, {"p99", q.dihedral_p99}};
  j["pct_area_axis_aligned_5deg"] = q.pct_area_axis_aligned;
  j["hausdorff_mm"] = q.hausdorff_mm ? nlohmann::json(*q.hausdorff_mm) : nlohmann::json();
  j["mean_distance_mm"] = q.mean_distance_mm ? nlohmann::json(*q.mean_distance_mm) : nlohmann::json();
  auto dist = [](const std::optional<DistanceStats>& d) {
    return d ? nlohmann::json{{"mean", d->mean}, {"p99", d->p99}, {"max", d->max}} : nlohmann::json();
  };
  j["distance_to_reference_mm"] = dist(q.to_reference);
  j["distance_from_reference_mm"] = dist(q.from_reference);
  return j;
}

std::string quality_to_text(const Quality& q) {
  const auto& t = q.topo;
  std::string s;
  s += fmt::format("vertices            {}\ntriangles           {}\n", t.vertices, t.triangles);
  s += fmt::format("closed              {} ({} border edges)\n", t.closed ? "yes" : "no", t.border_edges);
  s += fmt::format("manifold            {} ({} non-manifold edges, {} non-manifold vertices, {} degenerate)\n",
                   t.manifold ? "yes" : "no", t.nonmanifold_edges, t.nonmanifold_vertices, t.degenerate_triangles);
  s += fmt::format("oriented            {}\n", t.oriented ? "yes" : "no");
  s += fmt::format("components          {}\neuler               {}\ngenus               {}\n", t.components, t.euler,
                   t.genus < 0 ? std::string("n/a (not a closed manifold)") : std::to_string(t.genus));
  s += fmt::format("self-intersections  {}\n", q.self_intersections < 0 ? std::string("not checked")
                                                                         : std::to_string(q.self_intersections));
  s += fmt::format("area                {:.2f} mm2\nvolume              {:.2f} mm3\n", q.area_mm2, q.volume_mm3);
  s += fmt::format("edge length         min {:.4f}  mean {:.4f}  max {:.4f} mm\n", q.edge_min, q.edge_mean, q.edge_max);
  s += fmt::format("min angle           min {:.2f}  p01 {:.2f}  mean {:.2f} deg\n", q.angle_min, q.angle_p01,
                   q.angle_mean);
  s += fmt::format("min angle below     10deg {:.2f}%  20deg {:.2f}%  30deg {:.2f}%\n", q.pct_angle_below[0],
                   q.pct_angle_below[1], q.pct_angle_below[2]);
  s += fmt::format("radius ratio        mean {:.4f}  below 0.5 {:.2f}%\n", q.radius_ratio_mean,
                   q.pct_radius_ratio_below_half);
  s += fmt::format("dihedral            mean {:.2f}  p99 {:.2f} deg\n", q.dihedral_mean, q.dihedral_p99);
  s += fmt::format("axis-aligned area   {:.2f}% (normal within 5 deg of an axis)\n", q.pct_area_axis_aligned);
  if (q.hausdorff_mm) {
    s += fmt::format("hausdorff           {:.4f} mm\nmean distance       {:.4f} mm\n", *q.hausdorff_mm,
                     *q.mean_distance_mm);
    s += fmt::format("to reference        mean {:.4f}  p99 {:.4f}  max {:.4f} mm\n", q.to_reference->mean,
                     q.to_reference->p99, q.to_reference->max);
    s += fmt::format("from reference      mean {:.4f}  p99 {:.4f}  max {:.4f} mm\n", q.from_reference->mean,
                     q.from_reference->p99, q.from_reference->max);
  }
  return s;
}

}  // namespace mpumesh
