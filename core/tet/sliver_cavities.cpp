#include "tet/sliver_cavities.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <utility>

#include "tet/tetgen_steps.h"

namespace mpumesh {
namespace {

constexpr int kGrowths = 8;

double smallest_dihedral(const TetMesh& m, uint32_t t) {
  const auto& v = m.tets[t];
  return std::ranges::min(dihedral_angles(m.nodes[v[0]], m.nodes[v[1]], m.nodes[v[2]], m.nodes[v[3]]));
}

// Each node's tetrahedra: those of the mesh as it came (a CSR table) and those added since.
class Stars {
 public:
  explicit Stars(const TetMesh& m) : start_(m.nodes.size() + 1, 0) {
    for (const auto& t : m.tets)
      for (uint32_t v : t) ++start_[v + 1];
    for (size_t v = 0; v + 1 < start_.size(); ++v) start_[v + 1] += start_[v];
    tets_.resize(start_.back());
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (uint32_t t = 0; t < m.tets.size(); ++t)
      for (uint32_t v : m.tets[t]) tets_[fill[v]++] = t;
  }
  void add(uint32_t v, uint32_t t) { added_[v].push_back(t); }
  template <class F>
  void each(uint32_t v, F&& f) const {
    if (v + 1 < start_.size())
      for (uint32_t i = start_[v]; i < start_[v + 1]; ++i) f(tets_[i]);
    const auto it = added_.find(v);
    if (it != added_.end())
      for (uint32_t t : it->second) f(t);
  }

 private:
  std::vector<uint32_t> start_, tets_;
  std::unordered_map<uint32_t, std::vector<uint32_t>> added_;
};

struct Mesh {
  TetMesh& m;
  Stars stars;
  std::vector<char> dead;
  std::unordered_set<tetgen_steps::FaceKey, tetgen_steps::FaceKeyHash> walls;  // the boundary's triangles

  bool has(uint32_t t, uint32_t v) const { return std::ranges::find(m.tets[t], v) != m.tets[t].end(); }
  std::array<uint32_t, 3> face(uint32_t t, int k) const {
    const auto& v = m.tets[t];
    return {v[size_t(kTetFace[k][0])], v[size_t(kTetFace[k][1])], v[size_t(kTetFace[k][2])]};
  }
  // The live tetrahedron across face k of t, or -1 (also where the face is the boundary's).
  int64_t across(uint32_t t, int k) const {
    const auto f = face(t, k);
    if (walls.count(tetgen_steps::face_key(f[0], f[1], f[2]))) return -1;
    int64_t found = -1;
    stars.each(f[0], [&](uint32_t u) {
      if (u != t && !dead[u] && has(u, f[1]) && has(u, f[2])) found = u;
    });
    return found;
  }
};

double volume(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c, const Eigen::Vector3d& d) {
  return (b - a).dot((c - a).cross(d - a)) / 6;
}

// A cavity: its tetrahedra, their faces outward that are not shared among them, its old
// smallest dihedral angle and volume.
struct Cavity {
  std::vector<uint32_t> tets;
  std::vector<std::array<uint32_t, 3>> faces;
  double old_min = 180, old_volume = 0;
};

// The cavity's faces; false where they are not a closed surface that keeps every node of
// the cavity (an edge not on exactly two faces, or a node inside).
bool cavity_faces(const Mesh& g, Cavity& c) {
  const std::vector<uint32_t>& in = c.tets;
  c.faces.clear();
  for (uint32_t t : in)
    for (int k = 0; k < 4; ++k) {
      const int64_t u = g.across(t, k);
      if (u < 0 || std::ranges::find(in, uint32_t(u)) == in.end()) c.faces.push_back(g.face(t, k));
    }
  std::map<std::pair<uint32_t, uint32_t>, int> edges;
  for (const auto& f : c.faces)
    for (int i = 0; i < 3; ++i) ++edges[std::minmax(f[size_t(i)], f[size_t((i + 1) % 3)])];
  for (const auto& [e, n] : edges)
    if (n != 2) return false;
  for (uint32_t t : in)
    for (uint32_t v : g.m.tets[t])
      if (std::ranges::none_of(c.faces, [&](const auto& f) { return std::ranges::find(f, v) != f.end(); }))
        return false;
  return true;
}

// The smallest dihedral angle of the tetrahedra joining p to the cavity's faces. Where one
// is not positive: below -1, by how far p lies outside the cavity's kernel (the distance
// beyond the face it is furthest behind, over the mean edge `scale`), so that a search
// climbs into the kernel first.
double refill_quality(const Mesh& g, const Cavity& c, const Eigen::Vector3d& p, double scale) {
  double worst = 180, behind = 0;
  for (const auto& f : c.faces) {
    const Eigen::Vector3d &a = g.m.nodes[f[0]], &b = g.m.nodes[f[2]], &d = g.m.nodes[f[1]];
    // The face turned inward: p on its inner side makes (a, b, d, p) positive.
    const Eigen::Vector3d n = (b - a).cross(d - a);
    const double height = (p - a).dot(n) / n.norm();
    if (!(height > 1e-6 * scale)) {
      behind = std::max(behind, 1e-6 * scale - height);
      continue;
    }
    if (behind > 0) continue;
    const auto angle = dihedral_angles(a, b, d, p);
    worst = std::min(worst, *std::ranges::min_element(angle));
  }
  return behind > 0 ? -1 - behind / scale : worst;
}

// The node's place: the best of the cavity's centroids, then a pattern search over 26
// directions with halving steps. Returns {quality, place}.
std::pair<double, Eigen::Vector3d> place_node(const Mesh& g, const Cavity& c) {
  std::vector<Eigen::Vector3d> seeds;
  Eigen::Vector3d all = Eigen::Vector3d::Zero();
  double edges = 0;
  for (uint32_t t : c.tets) {
    Eigen::Vector3d s = Eigen::Vector3d::Zero();
    for (uint32_t v : g.m.tets[t]) s += g.m.nodes[v] / 4;
    seeds.push_back(s);
    all += s / double(c.tets.size());
  }
  seeds.insert(seeds.begin(), all);
  for (const auto& f : c.faces)
    for (int i = 0; i < 3; ++i) edges += (g.m.nodes[f[size_t(i)]] - g.m.nodes[f[size_t((i + 1) % 3)]]).norm();
  edges /= 3.0 * double(c.faces.size());
  double best = -INFINITY;
  Eigen::Vector3d at = all;
  for (const auto& s : seeds) {
    const double q = refill_quality(g, c, s, edges);
    if (q > best) best = q, at = s;
  }
  int steps = 0;
  for (double h = 0.25 * edges; h > 0.005 * edges && steps < 500; ++steps) {
    bool moved = false;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          const Eigen::Vector3d p = at + h * Eigen::Vector3d(dx, dy, dz).normalized();
          const double q = refill_quality(g, c, p, edges);
          if (q > best + 1e-9) best = q, at = p, moved = true;
        }
    if (!moved) h /= 2;
  }
  return {best, at};
}

// The cavity's old smallest angle and volume.
void measure(const Mesh& g, Cavity& c) {
  c.old_min = 180, c.old_volume = 0;
  for (uint32_t t : c.tets) {
    c.old_min = std::min(c.old_min, smallest_dihedral(g.m, t));
    const auto& v = g.m.tets[t];
    c.old_volume += volume(g.m.nodes[v[0]], g.m.nodes[v[1]], g.m.nodes[v[2]], g.m.nodes[v[3]]);
  }
}

// The cavity grown by the live tetrahedra of its region across those of its faces for
// which across_face(face) holds; whether any was added.
template <class AcrossFace>
bool grow(const Mesh& g, Cavity& c, AcrossFace&& across_face) {
  const std::vector<uint32_t> now = c.tets;
  const int32_t region = g.m.region[now[0]];
  bool grown = false;
  for (uint32_t t : now)
    for (int k = 0; k < 4; ++k) {
      const int64_t u = g.across(t, k);
      if (u < 0 || g.m.region[size_t(u)] != region || std::ranges::find(c.tets, uint32_t(u)) != c.tets.end() ||
          !across_face(g.face(t, k)))
        continue;
      c.tets.push_back(uint32_t(u));
      grown = true;
    }
  measure(g, c);
  return grown;
}

// The cavity grown by one ring.
void grow_ring(const Mesh& g, Cavity& c) {
  grow(g, c, [](const std::array<uint32_t, 3>&) { return true; });
}

// The cavity grown across the faces whose tetrahedron with p has an angle under
// `below_deg` or is not positive (where the face is not a wall); false when none is.
bool grow_where_poor(const Mesh& g, Cavity& c, const Eigen::Vector3d& p, double below_deg) {
  return grow(g, c, [&](const std::array<uint32_t, 3>& f) {
    const Eigen::Vector3d &a = g.m.nodes[f[0]], &b = g.m.nodes[f[2]], &d = g.m.nodes[f[1]];
    return !(volume(a, b, d, p) > 0) || std::ranges::min(dihedral_angles(a, b, d, p)) < below_deg;
  });
}

// The cavity's tetrahedra replaced by p joined to its faces.
void refill(Mesh& g, const Cavity& c, const Eigen::Vector3d& p) {
  const uint32_t node = uint32_t(g.m.nodes.size());
  g.m.nodes.push_back(p);
  const int32_t region = g.m.region[c.tets[0]];
  for (uint32_t t : c.tets) g.dead[t] = 1;
  for (const auto& f : c.faces) {
    const uint32_t t = uint32_t(g.m.tets.size());
    g.m.tets.push_back({f[0], f[2], f[1], node});
    g.m.region.push_back(region);
    g.dead.push_back(0);
    for (uint32_t v : g.m.tets.back()) g.stars.add(v, t);
  }
}

// Tetrahedron t's cavity refilled where that raises its smallest angle; true when done.
// The cavity starts as t and its neighbours and grows where its node makes poor
// tetrahedra (kGrowths times at most), or by a ring where its faces are not a surface.
bool mend(Mesh& g, uint32_t t, double below_deg) {
  Cavity c;
  c.tets = {t};
  grow_ring(g, c);
  Cavity best_cavity;
  double best = -1;
  Eigen::Vector3d best_at;
  for (int step = 0; step < kGrowths; ++step) {
    if (!cavity_faces(g, c)) {
      grow_ring(g, c);
      continue;
    }
    const auto [q, p] = place_node(g, c);
    if (q > c.old_min && q > best) {
      double filled = 0;
      for (const auto& f : c.faces) filled += volume(g.m.nodes[f[0]], g.m.nodes[f[2]], g.m.nodes[f[1]], p);
      if (std::abs(filled - c.old_volume) <= 1e-9 * c.old_volume) best = q, best_at = p, best_cavity = c;
    }
    if (best >= below_deg || !grow_where_poor(g, c, p, below_deg)) break;
  }
  if (best < 0) return false;
  refill(g, best_cavity, best_at);
  return true;
}

}  // namespace

int64_t refill_sliver_cavities(TetMesh& m, double below_deg) {
  std::vector<uint32_t> slivers;
  for (uint32_t t = 0; t < m.tets.size(); ++t)
    if (smallest_dihedral(m, t) < below_deg) slivers.push_back(t);
  if (slivers.empty()) return 0;  // without the tables below, which cost more than the scan
  Mesh g{m, Stars(m), std::vector<char>(m.tets.size(), 0), {}};
  for (const auto& f : m.boundary) g.walls.insert(tetgen_steps::face_key(f[0], f[1], f[2]));
  int64_t added = 0;
  for (uint32_t t : slivers)
    if (!g.dead[t] && smallest_dihedral(m, t) < below_deg) added += mend(g, t, below_deg);
  if (added == 0) return 0;
  size_t kept = 0;
  for (size_t t = 0; t < m.tets.size(); ++t)
    if (!g.dead[t]) m.tets[kept] = m.tets[t], m.region[kept] = m.region[t], ++kept;
  m.tets.resize(kept);
  m.region.resize(kept);
  return added;
}

}  // namespace mpumesh
