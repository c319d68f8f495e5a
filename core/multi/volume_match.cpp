#include "multi/volume_match.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "mesh/cgal_geometry.h"
#include "mesh/edge_faces.h"
#include "mesh/quality.h"
#include "multi/region_wedges.h"

namespace mpumesh::multi {
namespace {

constexpr int kRounds = 3;
// The displacement's regularisation, a fraction of the vertex's summed face areas: none
// along a junction curve's tangent, where the interfaces' normals leave it free.
constexpr double kTikhonov = 1e-3;

// Up to this many tries (match_label_volumes).
constexpr int kTries = 3;
// A vertex moves at most this fraction of its shortest edge in all rounds together, so
// that no triangle turns or narrows by more than a few degrees, nor a patch of fine
// triangles (a repair's points at a thin layer) wrinkles where some of its vertices move
// and others stay.
constexpr double kEdgeFraction = 0.05;

// A triangle's smallest angle under this (degrees) may not fall.
constexpr double kAngleKept = 30;

// A region's wedge at a junction edge (multi/region_wedges.h) and its angle before any move.
struct Wedge : RegionWedge {
  double before = 0;
};

// Every label's wedge at the edges where three or more regions meet, with its angle now.
std::vector<Wedge> junction_wedges(const TriangleMesh& c) {
  std::vector<Wedge> out;
  const EdgeFaces ef(c.triangles);
  for (size_t e = 0; e < ef.size(); ++e) {
    const std::span<const uint32_t> faces = ef.faces(e);
    if (faces.size() < 3) continue;
    const uint64_t key = ef.keys()[e];
    for (const RegionWedge& w : region_wedges(uint32_t(key >> 32), uint32_t(key & 0xffffffffu), faces, c.face_labels))
      out.push_back({w, wedge_of(c.vertices, c.triangles, w)});
  }
  return out;
}

// The regions of the complex that match a volume: region 0 holds every label that keeps
// its place (the background among them), regions 1..n the labels in `volumes`.
struct Regions {
  std::map<int64_t, int> index;  // label -> region (absent: 0)
  std::vector<double> target;    // per region (mm³)
  int of(int32_t label) const {
    const auto it = index.find(label);
    return it == index.end() ? 0 : it->second;
  }
};

Regions regions_of(const TriangleMesh& c, const std::map<int64_t, double>& volumes) {
  Regions r;
  r.target.push_back(0);
  for (const auto& l : c.face_labels)
    for (const int32_t label : l)
      if (label != 0 && volumes.count(label) && !r.index.count(label)) r.index[label] = 0;
  for (auto& [label, region] : r.index) {
    region = int(r.target.size());
    r.target.push_back(volumes.at(label));
  }
  return r;
}

// Each region's enclosed volume and the interfaces' areas (dense, by region).
struct Measure {
  std::vector<double> volume;
  Eigen::MatrixXd area;
};

Measure measure(const TriangleMesh& c, const Regions& r) {
  const int n = int(r.target.size());
  Measure m{std::vector<double>(size_t(n), 0.0), Eigen::MatrixXd::Zero(n, n)};
  for (size_t t = 0; t < c.triangles.size(); ++t) {
    const int a = r.of(c.face_labels[t][0]), b = r.of(c.face_labels[t][1]);
    if (a == b) continue;
    const Eigen::Vector3d &p = c.vertices[c.triangles[t][0]], &q = c.vertices[c.triangles[t][1]],
                          &s = c.vertices[c.triangles[t][2]];
    // The triangle's normal points from a into b: out of a.
    const double v = p.dot(q.cross(s)) / 6.0, area = 0.5 * (q - p).cross(s - p).norm();
    m.volume[size_t(a)] += v;
    m.volume[size_t(b)] -= v;
    m.area(a, b) += area;
    m.area(b, a) += area;
  }
  return m;
}

double worst_error(const Measure& m, const Regions& r) {
  double worst = 0;
  for (size_t k = 1; k < r.target.size(); ++k)
    if (r.target[k] > 0) worst = std::max(worst, std::abs(m.volume[k] - r.target[k]) / r.target[k]);
  return worst;
}

// The regions' constants c (c_0 = 0): the weighted graph Laplacian's system above.
Eigen::VectorXd constants(const Measure& m, const Regions& r) {
  const int n = int(r.target.size()) - 1;
  Eigen::MatrixXd L = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs(n);
  for (int a = 1; a <= n; ++a) {
    rhs(a - 1) = r.target[size_t(a)] - m.volume[size_t(a)];
    for (int b = 0; b <= n; ++b) {
      if (b == a) continue;
      L(a - 1, a - 1) += m.area(a, b);
      if (b > 0) L(a - 1, b - 1) -= m.area(a, b);
    }
  }
  Eigen::VectorXd c = Eigen::VectorXd::Zero(n + 1);
  // A label left with no interface (all its pieces merged as specks) keeps its place: its
  // row would be zero.
  for (int a = 1; a <= n; ++a)
    if (!(L(a - 1, a - 1) > 0)) L(a - 1, a - 1) = 1, rhs(a - 1) = 0;
  c.tail(n) = L.ldlt().solve(rhs);
  return c;
}

void keep_shape(const TriangleMesh& complex, const std::vector<Wedge>& wedges, std::vector<Eigen::Vector3d>& moved,
                std::vector<char>& frozen);

// One round: each vertex not frozen moved by its least-squares displacement (above), at
// most its faces' largest |s|, and in all rounds together (from `start`) at most
// kEdgeFraction of its shortest edge.
void move_round(TriangleMesh& complex, const std::vector<Eigen::Vector3d>& start, const Regions& r,
                const std::vector<Wedge>& wedges, const Eigen::VectorXd& c, double max_shift, std::vector<char>& frozen,
                VolumeMatchStats& stats) {
  const size_t nv = complex.vertices.size();
  std::vector<Eigen::Matrix3d> M(nv, Eigen::Matrix3d::Zero());
  std::vector<Eigen::Vector3d> rhs(nv, Eigen::Vector3d::Zero());
  std::vector<double> weight(nv, 0.0), reach(nv, 0.0), edge(nv, INFINITY);
  for (size_t t = 0; t < complex.triangles.size(); ++t) {
    const int a = r.of(complex.face_labels[t][0]), b = r.of(complex.face_labels[t][1]);
    const auto& tri = complex.triangles[t];
    for (size_t k = 0; k < 3; ++k) {
      const double e = (complex.vertices[tri[k]] - complex.vertices[tri[(k + 1) % 3]]).norm();
      edge[tri[k]] = std::min(edge[tri[k]], e);
      edge[tri[(k + 1) % 3]] = std::min(edge[tri[(k + 1) % 3]], e);
    }
    if (a == b) continue;
    const Eigen::Vector3d cr =
        (complex.vertices[tri[1]] - complex.vertices[tri[0]]).cross(complex.vertices[tri[2]] - complex.vertices[tri[0]]);
    const double area = 0.5 * cr.norm();
    if (!(area > 0)) continue;
    const Eigen::Vector3d n = cr.normalized();
    const double s = std::clamp(c(a) - c(b), -max_shift, max_shift);
    stats.largest_shift_mm = std::max(stats.largest_shift_mm, std::abs(s));
    for (const uint32_t v : tri) {
      M[v] += area * n * n.transpose();
      rhs[v] += area * s * n;
      weight[v] += area;
      reach[v] = std::max(reach[v], std::abs(s));
    }
  }
  std::vector<Eigen::Vector3d> moved = complex.vertices;
  for (size_t v = 0; v < nv; ++v) {
    if (!(weight[v] > 0) || frozen[v]) continue;
    const Eigen::Matrix3d A = M[v] + kTikhonov * weight[v] * Eigen::Matrix3d::Identity();
    Eigen::Vector3d d = A.ldlt().solve(rhs[v]);
    // Two interfaces at a thin wedge with different shifts ask for a long move.
    if (d.norm() > reach[v]) d *= reach[v] / d.norm();
    Eigen::Vector3d total = moved[v] + d - start[v];
    const double most = kEdgeFraction * edge[v];
    if (total.norm() > most) total *= most / total.norm();
    moved[v] = start[v] + total;
  }
  keep_shape(complex, wedges, moved, frozen);
  complex.vertices = std::move(moved);
}

// The moves in `moved` undone at the vertices of every triangle whose smallest angle they
// take lower, under kAngleKept, and of every wedge's two triangles that they take lower,
// under kMinWedgeDeg (multi/region_wedges.h: a tetrahedron there is no better), until
// there is none; those vertices stay frozen.
void keep_shape(const TriangleMesh& complex, const std::vector<Wedge>& wedges, std::vector<Eigen::Vector3d>& moved,
                std::vector<char>& frozen) {
  const auto& was = complex.vertices;
  auto undo = [&](uint32_t v) { moved[v] = was[v], frozen[v] = 1; };
  bool undone = true;
  while (undone) {
    undone = false;
    for (const auto& t : complex.triangles) {
      if (moved[t[0]] == was[t[0]] && moved[t[1]] == was[t[1]] && moved[t[2]] == was[t[2]]) continue;
      const double now = triangle_min_angle_deg(moved[t[0]], moved[t[1]], moved[t[2]]);
      if (now >= kAngleKept || now >= triangle_min_angle_deg(was[t[0]], was[t[1]], was[t[2]])) continue;
      for (const uint32_t v : t) undo(v);
      undone = true;
    }
    for (const Wedge& w : wedges) {
      if (wedge_of(moved, complex.triangles, w) >= std::min(w.before, kMinWedgeDeg * M_PI / 180)) continue;
      for (const uint32_t f : {w.f1, w.f2})
        for (const uint32_t v : complex.triangles[f]) undo(v);
      undone = true;
    }
  }
}

}  // namespace

VolumeMatchStats match_label_volumes(TriangleMesh& complex, const std::map<int64_t, double>& volumes,
                                     double max_shift) {
  VolumeMatchStats stats;
  const Regions r = regions_of(complex, volumes);
  if (r.target.size() < 2) return stats;
  const TriangleMesh original = complex;
  const std::vector<Wedge> wedges = junction_wedges(complex);
  const Measure first = measure(complex, r);
  stats.worst_before = worst_error(first, r);
  std::vector<char> frozen(complex.vertices.size(), 0);
  Measure m = first;
  bool clean = false;
  // A try whose moved triangles cross others has their vertices frozen and starts again.
  for (int attempt = 0; attempt < kTries && !clean; ++attempt) {
    complex = original;
    m = first;
    for (int round = 0; round < kRounds; ++round) {
      move_round(complex, original.vertices, r, wedges, constants(m, r), max_shift, frozen, stats);
      m = measure(complex, r);
    }
    const std::vector<uint32_t> changed = changed_triangles(complex, original);
    const std::vector<std::pair<uint32_t, uint32_t>> crossing = new_intersections(complex, original, changed);
    clean = crossing.empty();
    for (const auto& [i, j] : crossing)
      for (const uint32_t t : {i, j})
        for (const uint32_t v : complex.triangles[t]) frozen[v] = 1;
    stats.frozen = int64_t(std::count(frozen.begin(), frozen.end(), 1));
  }
  if (!clean) {
    complex = original;
    m = first;
    stats.reverted = true;
  }
  stats.worst_after = worst_error(m, r);
  return stats;
}

}  // namespace mpumesh::multi
