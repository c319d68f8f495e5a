#include "multi/complex_figures.h"

#include <algorithm>
#include <map>
#include <unordered_map>
#include <unordered_set>

#include "common/disjoint_sets.h"
#include "geometry/angle.h"
#include "mesh/cgal_geometry.h"
#include "mesh/edge_faces.h"
#include "mesh/quality.h"
#include "mesh/topology.h"
#include "multi/region_wedges.h"

namespace mpumesh::multi {
std::vector<int64_t> complex_labels(const TriangleMesh& c) {
  std::vector<int64_t> out;
  for (const auto& l : c.face_labels) {
    out.push_back(l[0]);
    out.push_back(l[1]);
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

TriangleMesh label_boundary(const TriangleMesh& c, int64_t label) {
  TriangleMesh m;
  m.vertices = c.vertices;
  for (size_t t = 0; t < c.triangles.size(); ++t) {
    const auto& tri = c.triangles[t];
    if (c.face_labels[t][0] == label) m.triangles.push_back(tri);
    if (c.face_labels[t][1] == label) m.triangles.push_back({tri[0], tri[2], tri[1]});
  }
  return m;
}

namespace {
// Edges not closed and oriented: one face, three or more, or two running the same way.
int64_t defects_of(const Topology& t) { return t.border_edges + t.nonmanifold_edges + t.misoriented_edges; }
}  // namespace

int64_t boundary_defects(const TriangleMesh& c, int64_t label) {
  return defects_of(analyze_topology(label_boundary(c, label)));
}

std::vector<std::array<uint32_t, 2>> junction_edges(const TriangleMesh& c) {
  std::unordered_map<uint64_t, std::vector<int32_t>> regions;  // per edge, the regions its triangles separate
  for (size_t t = 0; t < c.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      auto& r = regions[edge_key(c.triangles[t][size_t(k)], c.triangles[t][size_t((k + 1) % 3)])];
      r.push_back(c.face_labels[t][0]);
      r.push_back(c.face_labels[t][1]);
    }
  std::vector<std::array<uint32_t, 2>> out;
  for (auto& [key, r] : regions) {
    std::sort(r.begin(), r.end());
    if (std::unique(r.begin(), r.end()) - r.begin() >= 3) out.push_back({uint32_t(key >> 32), uint32_t(key)});
  }
  std::sort(out.begin(), out.end());
  return out;
}

namespace {

constexpr double kPi = 3.14159265358979323846;

// Every region's wedges at the junction edges (`junction`: their keys; multi/region_wedges.h)
// into its RegionFigures.
void measure_wedges(const TriangleMesh& c, const std::unordered_set<uint64_t>& junction,
                    std::vector<RegionFigures>& regions) {
  std::unordered_map<int64_t, RegionFigures*> of_label;
  for (RegionFigures& f : regions) of_label[f.label] = &f;
  const EdgeFaces ef(c.triangles);
  for (size_t e = 0; e < ef.size(); ++e) {
    const uint64_t key = ef.keys()[e];
    if (!junction.count(key)) continue;
    for (const RegionWedge& w : region_wedges(uint32_t(key >> 32), uint32_t(key), ef.faces(e), c.face_labels)) {
      RegionFigures& f = *of_label.at(w.region);
      const double deg = wedge_of(c.vertices, c.triangles, w) * 180 / kPi;
      f.min_wedge_deg = std::min(f.min_wedge_deg, deg);
      f.wedges_under_10 += deg < 10;
    }
  }
}

}  // namespace

ComplexFigures measure_complex(const TriangleMesh& c, bool crossings) {
  ComplexFigures out;
  const auto& V = c.vertices;
  const std::vector<std::array<uint32_t, 2>> jedges = junction_edges(c);
  std::unordered_set<uint64_t> junction;
  for (const auto& e : jedges) junction.insert(edge_key(e[0], e[1]));
  for (const int64_t label : complex_labels(c)) {
    if (label == 0) continue;
    const TriangleMesh b = label_boundary(c, label);
    const Topology t = analyze_topology(b);
    RegionFigures f;
    f.label = label;
    f.triangles = int64_t(b.triangles.size());
    f.volume_mm3 = enclosed_volume(b);
    f.defects = defects_of(t);
    f.components = t.components;
    f.pinched_vertices = t.nonmanifold_vertices;
    out.regions.push_back(f);
  }
  measure_wedges(c, junction, out.regions);
  std::vector<char> at_junction(V.size(), 0);
  DisjointSets sets(V.size());
  for (const auto& e : jedges) {
    out.junction_length_mm += (V[e[0]] - V[e[1]]).norm();
    at_junction[e[0]] = at_junction[e[1]] = 1;
    sets.join(e[0], e[1]);
  }
  out.junction_edges = int64_t(jedges.size());
  for (uint32_t v = 0; v < V.size(); ++v) out.junction_curves += at_junction[v] && sets.find(v) == v;
  std::map<std::array<int32_t, 2>, InterfaceFigures> by_pair;
  double rr_sum = 0;
  out.min_angle_deg = out.min_angle_off_junction_deg = 180;
  for (size_t t = 0; t < c.triangles.size(); ++t) {
    const auto& tri = c.triangles[t];
    const Eigen::Vector3d &a = V[tri[0]], &b = V[tri[1]], &d = V[tri[2]];
    const double angle = triangle_min_angle_deg(a, b, d), rr = triangle_radius_ratio(a, b, d);
    InterfaceFigures& f = by_pair[c.face_labels[t]];
    if (f.triangles == 0) {
      f.label_a = c.face_labels[t][0];
      f.label_b = c.face_labels[t][1];
      f.min_angle_deg = 180;
    }
    ++f.triangles;
    f.area_mm2 += 0.5 * (b - a).cross(d - a).norm();
    f.min_angle_deg = std::min(f.min_angle_deg, angle);
    f.mean_radius_ratio += rr;
    rr_sum += rr;
    out.min_angle_deg = std::min(out.min_angle_deg, angle);
    if (!at_junction[tri[0]] && !at_junction[tri[1]] && !at_junction[tri[2]])
      out.min_angle_off_junction_deg = std::min(out.min_angle_off_junction_deg, angle);
  }
  for (auto& [pair, f] : by_pair) {
    f.mean_radius_ratio /= double(f.triangles);
    out.interfaces.push_back(f);
  }
  if (!c.triangles.empty()) out.mean_radius_ratio = rr_sum / double(c.triangles.size());
  if (crossings) {
    TriangleMesh soup;
    soup.vertices = V;
    soup.triangles = c.triangles;
    out.crossing_pairs = int64_t(intersecting_triangles(soup, nullptr, false).size());
  }
  return out;
}

}  // namespace mpumesh::multi
