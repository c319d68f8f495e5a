#include "multi/complex_specks.h"

#include <tbb/parallel_sort.h>

#include <algorithm>
#include <map>
#include <optional>

#include "common/disjoint_sets.h"
#include "geometry/drop_unused.h"

namespace mpumesh::multi {
namespace {

// A closed piece of a label's boundary: its triangles, each seen from the label's side
// (0: the label is the triangle's label_a, 1: its label_b).
struct Piece {
  int32_t label = 0;
  double volume_mm3 = 0;  // enclosed, the triangles oriented out of the label
  std::vector<std::pair<uint32_t, int>> sides;
};

// Every label's pieces (not the background's): the triangles' sides of one label joined
// across the edges they share.
std::vector<Piece> pieces_of(const TriangleMesh& m) {
  const size_t n = m.triangles.size();
  struct Key {
    uint64_t edge;
    int32_t label;
    uint32_t side;  // 2 t + s
  };
  std::vector<Key> keys;
  keys.reserve(6 * n);
  for (uint32_t t = 0; t < n; ++t)
    for (int s = 0; s < 2; ++s) {
      const int32_t label = m.face_labels[t][size_t(s)];
      if (label == 0) continue;
      const auto& v = m.triangles[t];
      for (size_t k = 0; k < 3; ++k) keys.push_back({edge_key(v[k], v[(k + 1) % 3]), label, 2 * t + uint32_t(s)});
    }
  tbb::parallel_sort(keys.begin(), keys.end(), [](const Key& a, const Key& b) {
    return a.edge != b.edge ? a.edge < b.edge : a.label != b.label ? a.label < b.label : a.side < b.side;
  });
  DisjointSets sides(2 * n);
  for (size_t k = 1; k < keys.size(); ++k)
    if (keys[k].edge == keys[k - 1].edge && keys[k].label == keys[k - 1].label) sides.join(keys[k].side, keys[k - 1].side);
  std::vector<Piece> pieces;
  std::vector<uint32_t> piece_of(2 * n, UINT32_MAX);
  for (uint32_t t = 0; t < n; ++t)
    for (int s = 0; s < 2; ++s) {
      const int32_t label = m.face_labels[t][size_t(s)];
      if (label == 0) continue;
      const uint32_t r = sides.find(2 * t + uint32_t(s));
      if (piece_of[r] == UINT32_MAX) {
        piece_of[r] = uint32_t(pieces.size());
        pieces.push_back({label, 0, {}});
      }
      Piece& p = pieces[piece_of[r]];
      const auto& v = m.triangles[t];
      const double volume = m.vertices[v[0]].dot(m.vertices[v[1]].cross(m.vertices[v[2]])) / 6;
      p.volume_mm3 += s == 0 ? volume : -volume;
      p.sides.push_back({t, s});
    }
  return pieces;
}

double area_of(const TriangleMesh& m, uint32_t t) {
  const auto& v = m.triangles[t];
  return 0.5 * (m.vertices[v[1]] - m.vertices[v[0]]).cross(m.vertices[v[2]] - m.vertices[v[0]]).norm();
}

// The region a speck goes to: the one it shares the most area with (the lower label on a
// tie); none when it touches three or more.
std::optional<int32_t> receiver(const TriangleMesh& m, const Piece& p) {
  std::map<int32_t, double> shared;
  for (const auto& [t, s] : p.sides) shared[m.face_labels[t][size_t(1 - s)]] += area_of(m, t);
  if (shared.size() > 2) return std::nullopt;
  int32_t best = shared.begin()->first;
  for (const auto& [label, area] : shared)
    if (area > shared[best]) best = label;
  return best;
}

// Piece p's triangles against `to` marked for removal, the others relabelled with `to` in
// place of p's label (turned where the pair's order changes); every triangle marked done.
void give_to(TriangleMesh& m, const Piece& p, int32_t to, std::vector<char>& removed, std::vector<char>& done) {
  for (const auto& [t, s] : p.sides) {
    done[t] = 1;
    const int32_t other = m.face_labels[t][size_t(1 - s)];
    if (other == to) {
      removed[t] = 1;
      continue;
    }
    if ((p.label < other) != (to < other)) std::swap(m.triangles[t][1], m.triangles[t][2]);
    m.face_labels[t] = {std::min(to, other), std::max(to, other)};
  }
}

// The triangles marked removed taken out, and the vertices no triangle uses.
void remove_triangles(TriangleMesh& m, const std::vector<char>& removed) {
  size_t n = 0;
  for (size_t t = 0; t < m.triangles.size(); ++t) {
    if (removed[t]) continue;
    m.triangles[n] = m.triangles[t];
    m.face_labels[n] = m.face_labels[t];
    ++n;
  }
  m.triangles.resize(n);
  m.face_labels.resize(n);
  const std::vector<uint32_t> kept = drop_unused_points(m.vertices, m.triangles);
  if (!m.normals.empty()) {
    for (size_t i = 0; i < kept.size(); ++i) m.normals[i] = m.normals[kept[i]];
    m.normals.resize(kept.size());
  }
  if (!m.curvature.empty()) {
    for (size_t i = 0; i < kept.size(); ++i) m.curvature[i] = m.curvature[kept[i]];
    m.curvature.resize(kept.size());
  }
}

constexpr int kMaxRounds = 8;

}  // namespace

SpeckStats merge_specks(TriangleMesh& complex, double min_volume_mm3) {
  SpeckStats st;
  if (!(min_volume_mm3 > 0) || complex.face_labels.size() != complex.triangles.size()) return st;
  for (int round = 0; round < kMaxRounds; ++round) {
    std::vector<Piece> specks;
    for (Piece& p : pieces_of(complex))
      if (p.volume_mm3 > 0 && p.volume_mm3 < min_volume_mm3) specks.push_back(std::move(p));
    std::stable_sort(specks.begin(), specks.end(),
                     [](const Piece& a, const Piece& b) { return a.volume_mm3 < b.volume_mm3; });
    std::vector<char> removed(complex.triangles.size(), 0), done(complex.triangles.size(), 0);
    bool waiting = false;
    int64_t merged = 0;
    for (const Piece& p : specks) {
      const bool next_to_merged = std::any_of(p.sides.begin(), p.sides.end(), [&](const auto& x) { return done[x.first]; });
      if (next_to_merged) {
        waiting = true;
        continue;
      }
      const std::optional<int32_t> to = receiver(complex, p);
      if (!to) continue;
      give_to(complex, p, *to, removed, done);
      ++merged;
      st.volume_mm3 += p.volume_mm3;
    }
    st.merged += merged;
    if (merged > 0) remove_triangles(complex, removed);
    if (merged == 0 || !waiting) break;
  }
  return st;
}

}  // namespace mpumesh::multi
