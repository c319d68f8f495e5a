#include "multi/complex_optimize.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <span>
#include <unordered_set>

#include "geometry/angle.h"
#include "geometry/vertex_faces.h"
#include "mesh/cgal_geometry.h"
#include "mesh/edge_faces.h"
#include "multi/region_wedges.h"

namespace mpumesh::multi {
namespace {

using Tri = std::array<uint32_t, 3>;
using Pair = std::array<int, 2>;

constexpr double kMaxTurnDeg = 30;  // a moved vertex's triangles; a flipped pair's normals
constexpr double kPi = 3.14159265358979323846;

Eigen::Vector3d normal_of(const std::vector<Eigen::Vector3d>& V, const Tri& t) {
  const Eigen::Vector3d n = (V[t[1]] - V[t[0]]).cross(V[t[2]] - V[t[0]]);
  const double len = n.norm();
  return len > 0 ? Eigen::Vector3d(n / len) : Eigen::Vector3d::Zero();
}

// The triangle's angle at corner k (radians).
double angle_at(const std::vector<Eigen::Vector3d>& V, const Tri& t, int k) {
  const Eigen::Vector3d& p = V[t[size_t(k)]];
  return angle_between(V[t[size_t((k + 1) % 3)]] - p, V[t[size_t((k + 2) % 3)]] - p);
}

double smallest_angle(const std::vector<Eigen::Vector3d>& V, const Tri& t) {
  return std::min({angle_at(V, t, 0), angle_at(V, t, 1), angle_at(V, t, 2)});
}

// The complex as the optimiser edits it: positions, triangles and each triangle's region
// pair.
struct Complex {
  std::vector<Eigen::Vector3d>& V;
  std::vector<Tri>& T;
  std::vector<Pair> pair;  // regions, ascending
};

// The triangles around each vertex as a pass changes them: those at the pass's start and
// those a flip brought to it since. A flip keeps its two triangles' slots, so a slot that
// left a vertex stays listed and is told apart by its vertices.
struct LiveFans {
  VertexFaces start;
  std::unordered_map<uint32_t, std::vector<uint32_t>> gained;

  explicit LiveFans(const Complex& c)
      : start(vertex_faces(c.V.size(), c.T.size(), [&](size_t f) { return c.T[f]; })) {}

  // The triangles at edge p-q now.
  std::vector<uint32_t> at_edge(const Complex& c, uint32_t p, uint32_t q) const {
    std::vector<uint32_t> out;
    auto take = [&](uint32_t f) {
      const Tri& t = c.T[f];
      const bool has_p = t[0] == p || t[1] == p || t[2] == p, has_q = t[0] == q || t[1] == q || t[2] == q;
      if (has_p && has_q && std::find(out.begin(), out.end(), f) == out.end()) out.push_back(f);
    };
    for (uint32_t f : start[p]) take(f);
    if (const auto it = gained.find(p); it != gained.end())
      for (uint32_t f : it->second) take(f);
    return out;
  }
};

// The smallest angle inside a region other than the background at edge p-q between its two
// triangles there (radians; 2 pi where no region has two): the region's wedge, which
// bounds its tetrahedra's dihedral angles there (multi/thin_wedges.h).
double least_wedge(const Complex& c, const LiveFans& fans, uint32_t p, uint32_t q) {
  const std::vector<uint32_t> faces = fans.at_edge(c, p, q);
  double least = 2 * kPi;
  for (const RegionWedge& w : region_wedges(p, q, faces, c.pair)) least = std::min(least, wedge_of(c.V, c.T, w));
  return least;
}

// Whether a change that took an edge's least wedge from `before` to `after` is allowed: it
// takes no wedge under kMinWedgeDeg, or lower where one is under already.
bool wedge_kept(double before, double after) {
  return after >= std::min(before, kMinWedgeDeg * kPi / 180);
}

// Step 1: the flips of one pass, each triangle at most once, none at a frozen vertex.
int64_t flip_pass(Complex& c, const std::vector<char>& frozen) {
  const EdgeFaces ef(c.T, /*lookup=*/true);
  LiveFans fans(c);
  std::vector<char> touched(c.T.size(), 0);
  std::unordered_set<uint64_t> made;
  const double coplanar = std::cos(kMaxTurnDeg * kPi / 180);
  int64_t flips = 0;
  for (size_t e = 0; e < ef.size(); ++e) {
    const auto faces = ef.faces(e);
    if (faces.size() != 2) continue;
    const uint32_t f1 = faces[0], f2 = faces[1];
    if (touched[f1] || touched[f2] || c.pair[f1] != c.pair[f2]) continue;
    // f1 = (u, v, w) with the edge u -> v; f2 must run v -> u, its third vertex x.
    const Tri& a = c.T[f1];
    int k = 0;
    while (k < 3 && edge_key(a[size_t(k)], a[size_t((k + 1) % 3)]) != ef.keys()[e]) ++k;
    if (k == 3) continue;
    const uint32_t u = a[size_t(k)], v = a[size_t((k + 1) % 3)], w = a[size_t((k + 2) % 3)];
    const Tri& b = c.T[f2];
    int m = 0;
    while (m < 3 && !(b[size_t(m)] == v && b[size_t((m + 1) % 3)] == u)) ++m;
    if (m == 3) continue;
    const uint32_t x = b[size_t((m + 2) % 3)];
    if (frozen[u] || frozen[v] || frozen[w] || frozen[x]) continue;
    if (x == w || ef.contains(edge_key(w, x)) || made.count(edge_key(w, x))) continue;
    if (angle_at(c.V, a, (k + 2) % 3) + angle_at(c.V, b, (m + 2) % 3) <= kPi) continue;  // locally Delaunay
    if (normal_of(c.V, a).dot(normal_of(c.V, b)) < coplanar) continue;
    const Tri n1 = {u, x, w}, n2 = {x, v, w};
    if (std::min(smallest_angle(c.V, n1), smallest_angle(c.V, n2)) <=
        std::min(smallest_angle(c.V, a), smallest_angle(c.V, b)))
      continue;
    const Tri was1 = a, was2 = b;
    const std::array<std::array<uint32_t, 2>, 4> outer = {{{u, w}, {v, w}, {u, x}, {v, x}}};
    std::array<double, 4> before{};
    for (size_t k = 0; k < 4; ++k) before[k] = least_wedge(c, fans, outer[k][0], outer[k][1]);
    c.T[f1] = n1;
    c.T[f2] = n2;
    fans.gained[w].push_back(f2);
    fans.gained[x].push_back(f1);
    bool kept = true;
    for (size_t k = 0; k < 4 && kept; ++k) kept = wedge_kept(before[k], least_wedge(c, fans, outer[k][0], outer[k][1]));
    if (!kept) {
      c.T[f1] = was1;
      c.T[f2] = was2;
      continue;
    }
    touched[f1] = touched[f2] = 1;
    made.insert(edge_key(w, x));
    ++flips;
  }
  return flips;
}

// Each vertex's pair where all its triangles have one (else it is held).
std::vector<std::optional<Pair>> single_pairs(const Complex& c, const VertexFaces& fans) {
  std::vector<std::optional<Pair>> out(c.V.size());
  for (size_t v = 0; v < c.V.size(); ++v) {
    const auto faces = fans[v];
    if (faces.empty()) continue;
    const Pair p = c.pair[faces[0]];
    if (std::all_of(faces.begin(), faces.end(), [&](uint32_t f) { return c.pair[f] == p; })) out[v] = p;
  }
  return out;
}

// Where vertex v would go: its triangles' area-weighted centroid, in its tangent plane,
// then back onto its interface, where that pair stays the two most inside regions.
std::optional<Eigen::Vector3d> candidate(const MaterialField& field, const Complex& c, std::span<const uint32_t> fan,
                                         const Pair& p, size_t v) {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double area = 0, edges = 0;
  for (uint32_t f : fan) {
    const Tri& t = c.T[f];
    const double a = 0.5 * (c.V[t[1]] - c.V[t[0]]).cross(c.V[t[2]] - c.V[t[0]]).norm();
    centroid += a * (c.V[t[0]] + c.V[t[1]] + c.V[t[2]]) / 3;
    area += a;
    for (uint32_t u : t) edges += (c.V[u] - c.V[v]).norm();
  }
  if (!(area > 0)) return std::nullopt;
  const double h = edges / (2.0 * double(fan.size()));  // mean edge length
  const Eigen::Vector3d n = field.interface_normal(c.V[v], p[0], p[1]);
  Eigen::Vector3d d = centroid / area - c.V[v];
  d -= n * n.dot(d);
  Eigen::Vector3d q = c.V[v] + d;
  if (!field.project_interface(q, p[0], p[1], 0.5 * h)) return std::nullopt;
  const std::vector<int> r = field.ranked(q);
  if (std::min(r[0], r[1]) != p[0] || std::max(r[0], r[1]) != p[1]) return std::nullopt;
  return q;
}

// The least wedge at each edge opposite v in its triangles (least_wedge).
std::vector<double> wedges_opposite(const Complex& c, const LiveFans& fans, uint32_t v) {
  std::vector<double> out;
  for (uint32_t f : fans.start[v]) {
    const Tri& t = c.T[f];
    const int k = t[0] == v ? 0 : t[1] == v ? 1 : 2;
    out.push_back(least_wedge(c, fans, t[size_t((k + 1) % 3)], t[size_t((k + 2) % 3)]));
  }
  return out;
}

// Step 2: the moves of one pass, frozen vertices held. A move is kept where no triangle
// around the vertex turns by more than kMaxTurnDeg, their smallest angle rises and no
// region's wedge at the edges opposite the vertex falls (wedge_kept).
int64_t move_pass(const MaterialField& field, Complex& c, const std::vector<char>& frozen) {
  const LiveFans fans(c);
  const std::vector<std::optional<Pair>> pair = single_pairs(c, fans.start);
  const size_t n = c.V.size();
  std::vector<std::optional<Eigen::Vector3d>> cand(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& rg) {
    for (size_t v = rg.begin(); v != rg.end(); ++v)
      if (pair[v] && !frozen[v]) cand[v] = candidate(field, c, fans.start[v], *pair[v], v);
  });
  const double turn = std::cos(kMaxTurnDeg * kPi / 180);
  int64_t moves = 0;
  std::vector<Eigen::Vector3d> before;
  for (size_t v = 0; v < n; ++v) {
    if (!cand[v]) continue;
    const auto fan = fans.start[v];
    double old_min = INFINITY;
    before.clear();
    for (uint32_t f : fan) {
      old_min = std::min(old_min, smallest_angle(c.V, c.T[f]));
      before.push_back(normal_of(c.V, c.T[f]));
    }
    const Eigen::Vector3d old = c.V[v];
    c.V[v] = *cand[v];
    double new_min = INFINITY;
    bool turned = false;
    for (size_t k = 0; k < fan.size(); ++k) {
      const Tri& t = c.T[fan[k]];
      new_min = std::min(new_min, smallest_angle(c.V, t));
      turned = turned || normal_of(c.V, t).dot(before[k]) < turn;
    }
    bool kept = !turned && new_min > old_min;
    if (kept) {
      const std::vector<double> now = wedges_opposite(c, fans, uint32_t(v));
      c.V[v] = old;
      const std::vector<double> was = wedges_opposite(c, fans, uint32_t(v));
      for (size_t k = 0; k < now.size() && kept; ++k) kept = wedge_kept(was[k], now[k]);
    }
    c.V[v] = kept ? *cand[v] : old;
    moves += kept;
  }
  return moves;
}

double smallest_angle_deg(const std::vector<Eigen::Vector3d>& V, const std::vector<Tri>& T) {
  double m = INFINITY;
  for (const Tri& t : T) m = std::min(m, smallest_angle(V, t));
  return T.empty() ? 0 : m * 180 / kPi;
}

// Up to this many tries: a try whose changed triangles intersect others has their
// vertices frozen and starts again from the complex as it was.
constexpr int kTries = 3;

}  // namespace

void optimize_complex(const MaterialField& field, TriangleMesh& complex, int rounds, ComplexOptimizeStats* stats) {
  const auto t0 = std::chrono::steady_clock::now();
  ComplexOptimizeStats st;
  const TriangleMesh original = complex;
  std::map<int64_t, int> region;
  for (int r = 0; r < field.regions(); ++r) region[field.label(r)] = r;
  std::vector<Pair> pairs;
  for (const auto& l : complex.face_labels) {
    const int a = region.at(l[0]), b = region.at(l[1]);
    pairs.push_back({std::min(a, b), std::max(a, b)});
  }
  st.min_angle_before_deg = smallest_angle_deg(complex.vertices, complex.triangles);
  std::vector<char> frozen(complex.vertices.size(), 0);
  bool clean = false;
  for (int attempt = 0; attempt < kTries && !clean; ++attempt) {
    complex = original;
    Complex c{complex.vertices, complex.triangles, pairs};
    st.flips = st.moves = 0;
    st.rounds = 0;
    for (int round = 0; round < rounds; ++round) {
      st.flips += flip_pass(c, frozen);
      st.moves += move_pass(field, c, frozen);
      ++st.rounds;
    }
    const std::vector<uint32_t> changed = changed_triangles(complex, original);
    const std::vector<std::pair<uint32_t, uint32_t>> crossing = new_intersections(complex, original, changed);
    clean = crossing.empty();
    for (const auto& [i, j] : crossing)
      for (uint32_t t : {i, j})
        for (uint32_t v : complex.triangles[t]) frozen[v] = 1;
  }
  if (!clean) {
    complex = original;
    st.reverted = true;
  }
  st.min_angle_after_deg = smallest_angle_deg(complex.vertices, complex.triangles);
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats) *stats = st;
}

}  // namespace mpumesh::multi
