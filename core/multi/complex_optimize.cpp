#include "multi/complex_optimize.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <unordered_set>

#include "geometry/angle.h"
#include "mesh/cgal_geometry.h"
#include "mesh/edge_faces.h"

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

// Step 1: the flips of one pass, each triangle at most once, none at a frozen vertex.
int64_t flip_pass(Complex& c, const std::vector<char>& frozen) {
  const EdgeFaces ef(c.T, /*lookup=*/true);
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
    c.T[f1] = n1;
    c.T[f2] = n2;
    touched[f1] = touched[f2] = 1;
    made.insert(edge_key(w, x));
    ++flips;
  }
  return flips;
}

// Each vertex's triangles (CSR), and its pair where all of them have one (else held).
struct Fans {
  std::vector<uint32_t> first, faces;
  std::vector<std::optional<Pair>> pair;
};

Fans fans_of(const Complex& c) {
  Fans f;
  const size_t n = c.V.size();
  f.first.assign(n + 1, 0);
  for (const Tri& t : c.T)
    for (uint32_t v : t) ++f.first[v + 1];
  for (size_t i = 0; i < n; ++i) f.first[i + 1] += f.first[i];
  f.faces.resize(f.first[n]);
  std::vector<uint32_t> at(f.first.begin(), f.first.end() - 1);
  for (uint32_t t = 0; t < c.T.size(); ++t)
    for (uint32_t v : c.T[t]) f.faces[at[v]++] = t;
  f.pair.resize(n);
  for (size_t v = 0; v < n; ++v) {
    if (f.first[v] == f.first[v + 1]) continue;
    const Pair p = c.pair[f.faces[f.first[v]]];
    bool one = true;
    for (uint32_t k = f.first[v]; k < f.first[v + 1]; ++k) one = one && c.pair[f.faces[k]] == p;
    if (one) f.pair[v] = p;
  }
  return f;
}

// Where vertex v would go: its triangles' area-weighted centroid, in its tangent plane,
// then back onto its interface, where that pair stays the two most inside regions.
std::optional<Eigen::Vector3d> candidate(const MaterialField& field, const Complex& c, const Fans& f, size_t v) {
  const Pair p = *f.pair[v];
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  double area = 0, edges = 0;
  for (uint32_t k = f.first[v]; k < f.first[v + 1]; ++k) {
    const Tri& t = c.T[f.faces[k]];
    const double a = 0.5 * (c.V[t[1]] - c.V[t[0]]).cross(c.V[t[2]] - c.V[t[0]]).norm();
    centroid += a * (c.V[t[0]] + c.V[t[1]] + c.V[t[2]]) / 3;
    area += a;
    for (uint32_t u : t) edges += (c.V[u] - c.V[v]).norm();
  }
  if (!(area > 0)) return std::nullopt;
  const double h = edges / (2.0 * double(f.first[v + 1] - f.first[v]));  // mean edge length
  const Eigen::Vector3d n = field.interface_normal(c.V[v], p[0], p[1]);
  Eigen::Vector3d d = centroid / area - c.V[v];
  d -= n * n.dot(d);
  Eigen::Vector3d q = c.V[v] + d;
  if (!field.project_interface(q, p[0], p[1], 0.5 * h)) return std::nullopt;
  const std::vector<int> r = field.ranked(q);
  if (std::min(r[0], r[1]) != p[0] || std::max(r[0], r[1]) != p[1]) return std::nullopt;
  return q;
}

// Step 2: the moves of one pass, frozen vertices held.
int64_t move_pass(const MaterialField& field, Complex& c, const std::vector<char>& frozen) {
  const Fans f = fans_of(c);
  const size_t n = c.V.size();
  std::vector<std::optional<Eigen::Vector3d>> cand(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& rg) {
    for (size_t v = rg.begin(); v != rg.end(); ++v)
      if (f.pair[v] && !frozen[v]) cand[v] = candidate(field, c, f, v);
  });
  const double turn = std::cos(kMaxTurnDeg * kPi / 180);
  int64_t moves = 0;
  std::vector<Eigen::Vector3d> before;
  for (size_t v = 0; v < n; ++v) {
    if (!cand[v]) continue;
    double old_min = INFINITY;
    before.clear();
    for (uint32_t k = f.first[v]; k < f.first[v + 1]; ++k) {
      const Tri& t = c.T[f.faces[k]];
      old_min = std::min(old_min, smallest_angle(c.V, t));
      before.push_back(normal_of(c.V, t));
    }
    const Eigen::Vector3d old = c.V[v];
    c.V[v] = *cand[v];
    double new_min = INFINITY;
    bool turned = false;
    for (uint32_t k = f.first[v]; k < f.first[v + 1]; ++k) {
      const Tri& t = c.T[f.faces[k]];
      new_min = std::min(new_min, smallest_angle(c.V, t));
      turned = turned || normal_of(c.V, t).dot(before[k - f.first[v]]) < turn;
    }
    if (turned || !(new_min > old_min)) {
      c.V[v] = old;
      continue;
    }
    ++moves;
  }
  return moves;
}

double smallest_angle_deg(const std::vector<Eigen::Vector3d>& V, const std::vector<Tri>& T) {
  double m = INFINITY;
  for (const Tri& t : T) m = std::min(m, smallest_angle(V, t));
  return T.empty() ? 0 : m * 180 / kPi;
}

// The triangles that differ from the original's (moved vertex or flipped).
std::vector<uint32_t> changed_triangles(const TriangleMesh& now, const TriangleMesh& was) {
  std::vector<uint32_t> out;
  for (uint32_t t = 0; t < now.triangles.size(); ++t) {
    bool same = now.triangles[t] == was.triangles[t];
    for (uint32_t v : now.triangles[t]) same = same && now.vertices[v] == was.vertices[v];
    if (!same) out.push_back(t);
  }
  return out;
}

// The intersecting pairs (adjacent ones included) among `changed` that `was` did not have.
std::vector<std::pair<uint32_t, uint32_t>> new_intersections(const TriangleMesh& now, const TriangleMesh& was,
                                                             const std::vector<uint32_t>& changed) {
  const auto before = intersecting_triangles(was, &changed, true);
  const std::set<std::pair<uint32_t, uint32_t>> old(before.begin(), before.end());
  std::vector<std::pair<uint32_t, uint32_t>> out;
  for (const auto& p : intersecting_triangles(now, &changed, true))
    if (!old.count(p)) out.push_back(p);
  return out;
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
    std::vector<std::pair<uint32_t, uint32_t>> crossing;
    if (!changed.empty()) crossing = new_intersections(complex, original, changed);
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
