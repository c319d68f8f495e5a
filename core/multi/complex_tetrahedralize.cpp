#include "multi/complex_tetrahedralize.h"

#include <fmt/format.h>

#include <algorithm>
#include <map>
#include <unordered_map>

#include "common/error.h"
#include "geometry/drop_unused.h"
#include "multi/complex_figures.h"
#include "tet/region_quality.h"
#include "tet/sliver_cavities.h"
#include "tet/tet_quality.h"
#include "tet/tetgen_steps.h"

namespace mpumesh::multi {
namespace {

using namespace tetgen_steps;

// The label beyond the background's box.
constexpr int32_t kOutside = -1;

void check_complex(const TriangleMesh& c) {
  if (c.triangles.empty() || c.face_labels.size() != c.triangles.size())
    throw InputError("tetmesh: the mesh is not a multi-material complex (its faces carry no label_a, label_b)");
  for (const auto& l : c.face_labels)
    if (!(l[0] >= 0 && l[0] < l[1]))
      throw InputError(fmt::format("tetmesh: a face of the complex is tagged ({}, {}); the tags are two labels a < b, "
                                   "0 the background",
                                   l[0], l[1]));
  for (const int64_t label : complex_labels(c)) {
    if (label == 0) continue;
    const int64_t defects = boundary_defects(c, label);
    if (defects > 0)
      throw InputError(fmt::format("tetmesh: label {}'s boundary in the complex has {} edges that are not closed and "
                                   "oriented; a volume mesh fills closed regions",
                                   label, defects));
  }
}

// The complex's box (TetOptions::background): its six faces in squares of about `step`,
// two triangles each, facing out; each face's `sides` (0 inside, kOutside beyond).
void add_box(TriangleMesh& plc, std::vector<std::array<int32_t, 2>>& sides, double step) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (const auto& p : plc.vertices) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double margin = std::max(step, 0.1 * (hi - lo).maxCoeff());
  lo.array() -= margin, hi.array() += margin;
  std::array<int, 3> n;
  for (int d = 0; d < 3; ++d) n[size_t(d)] = std::max(1, int(std::ceil((hi[d] - lo[d]) / step)));
  std::map<std::array<int, 3>, uint32_t> index;  // grid corner -> vertex
  auto vertex = [&](std::array<int, 3> g) {
    const auto [it, fresh] = index.try_emplace(g, uint32_t(plc.vertices.size()));
    if (fresh) {
      Eigen::Vector3d p;
      for (int d = 0; d < 3; ++d) p[d] = lo[d] + (hi[d] - lo[d]) * g[size_t(d)] / n[size_t(d)];
      plc.vertices.push_back(p);
    }
    return it->second;
  };
  for (int a = 0; a < 3; ++a) {
    const int u = (a + 1) % 3, v = (a + 2) % 3;  // e_u x e_v = e_a
    for (int side = 0; side < 2; ++side)
      for (int i = 0; i < n[size_t(u)]; ++i)
        for (int j = 0; j < n[size_t(v)]; ++j) {
          auto corner = [&](int di, int dj) {
            std::array<int, 3> g;
            g[size_t(a)] = side * n[size_t(a)], g[size_t(u)] = i + di, g[size_t(v)] = j + dj;
            return vertex(g);
          };
          const uint32_t c00 = corner(0, 0), c10 = corner(1, 0), c11 = corner(1, 1), c01 = corner(0, 1);
          if (side == 1) {
            plc.triangles.push_back({c00, c10, c11});
            plc.triangles.push_back({c00, c11, c01});
          } else {
            plc.triangles.push_back({c00, c11, c10});
            plc.triangles.push_back({c00, c01, c11});
          }
          sides.push_back({0, kOutside});
          sides.push_back({0, kOutside});
        }
  }
}

// Each tetrahedron's label: its component's majority of the sides its faces on the complex
// give (the triangle's first label where it faces out of the tetrahedron).
std::vector<int32_t> tet_labels(const std::vector<Eigen::Vector3d>& nodes, const std::vector<std::array<uint32_t, 4>>& tets,
                                const Components& c, const TriangleMesh& plc, const SurfaceFaces& faces,
                                const std::vector<std::array<int32_t, 2>>& sides) {
  std::unordered_map<uint32_t, std::map<int32_t, int64_t>> votes;
  for (const Components::Face& f : c.faces) {
    const std::array<uint32_t, 3>* s = faces.at(f.key);
    const auto& pair = sides[size_t(s - plc.triangles.data())];
    ++votes[c.component[f.tet]][faces_out_of(nodes, tets[f.tet], f.face, *s) ? pair[0] : pair[1]];
  }
  std::unordered_map<uint32_t, int32_t> label;
  for (const auto& [component, v] : votes)
    label[component] = std::ranges::max_element(v, {}, [](const auto& e) { return e.second; })->first;
  std::vector<int32_t> out(tets.size(), kOutside);
  for (size_t t = 0; t < tets.size(); ++t) {
    const auto it = label.find(c.component[t]);
    if (it != label.end()) out[t] = it->second;
  }
  return out;
}

// The labelled tetrahedra kept (label 0 only with the background) and the complex's
// triangles that bound them, each once, with its labels.
TetMesh to_complex_mesh(const tetgenio& out, const TriangleMesh& plc, const std::vector<std::array<int32_t, 2>>& sides,
                        size_t complex_triangles, bool background) {
  TetMesh m;
  const std::vector<std::array<uint32_t, 4>> tets = positive_tets(out, m.nodes);
  const SurfaceFaces faces = surface_faces(plc);
  const Components c = solid_components(tets, faces);
  const std::vector<int32_t> label = tet_labels(m.nodes, tets, c, plc, faces, sides);
  auto kept = [&](uint32_t t) { return label[t] > 0 || (background && label[t] == 0); };
  std::vector<int32_t> present;
  for (uint32_t t = 0; t < tets.size(); ++t)
    if (kept(t)) m.tets.push_back(tets[t]), m.region.push_back(label[t]), present.push_back(label[t]);
  std::ranges::sort(present);
  m.regions = int32_t(std::unique(present.begin(), present.end()) - present.begin());
  for (size_t k = 0; k < c.faces.size(); ++k) {
    const Components::Face& f = c.faces[k];
    if (!kept(f.tet) || (k > 0 && c.faces[k - 1].key == f.key && kept(c.faces[k - 1].tet))) continue;
    const std::array<uint32_t, 3>* s = faces.at(f.key);
    const size_t i = size_t(s - plc.triangles.data());
    m.boundary.push_back(*s);
    m.boundary_labels.push_back(i < complex_triangles ? sides[i] : std::array<int32_t, 2>{0, 0});
    m.boundary_region.push_back(m.boundary_labels.back()[1]);
  }
  return m;
}

// Each label's figures (LabelTetFigures); `box_volume`: the background's box (0: none).
std::vector<LabelTetFigures> label_figures(const TetMesh& m, const TriangleMesh& complex, double box_volume) {
  std::vector<char> on_complex(m.nodes.size(), 0), on_junction(m.nodes.size(), 0);
  for (const auto& t : complex.triangles)
    for (uint32_t v : t) on_complex[v] = 1;
  for (const auto& e : junction_edges(complex)) on_junction[e[0]] = on_junction[e[1]] = 1;
  std::map<int32_t, LabelTetFigures> figures;
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const int32_t l = m.region[t];
    LabelTetFigures& f = figures[l];
    f.label = l;
    const auto& v = m.tets[t];
    bool interface = false, junction = false;
    for (uint32_t n : v) interface |= on_complex[n] != 0, junction |= on_junction[n] != 0;
    if (!interface) continue;
    const double d = tet_shape(m.nodes[v[0]], m.nodes[v[1]], m.nodes[v[2]], m.nodes[v[3]]).min_dihedral_deg;
    f.min_dihedral_at_interfaces = std::min(f.min_dihedral_at_interfaces, d);
    if (junction) f.min_dihedral_at_junctions = std::min(f.min_dihedral_at_junctions, d);
  }
  std::vector<LabelTetFigures> out;
  double labels_volume = 0;
  for (const auto& [l, quality] : quality_by_region(m)) {
    LabelTetFigures& f = figures[l];
    f.quality = quality;
    if (l > 0) f.boundary_volume = enclosed_volume(label_boundary(complex, l)), labels_volume += f.boundary_volume;
    out.push_back(f);
  }
  for (LabelTetFigures& f : out)
    if (f.label == 0) f.boundary_volume = box_volume - labels_volume;
  return out;
}

}  // namespace

TetMesh tetrahedralize_complex(const TriangleMesh& input, const TetOptions& opt, TetStats* stats_out,
                               const ProgressFn& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  // Without the vertices no triangle uses: each would be a node with no spacing of its own.
  TriangleMesh complex;
  complex.vertices = input.vertices;
  complex.triangles = input.triangles;
  complex.face_labels = input.face_labels;
  drop_unused_points(complex.vertices, complex.triangles);
  check_complex(complex);
  TetStats st;
  st.surface_points = int64_t(complex.vertices.size());
  TriangleMesh plc;
  plc.vertices = complex.vertices;
  plc.triangles = complex.triangles;
  std::vector<std::array<int32_t, 2>> sides = complex.face_labels;
  st.size = interior_size(mean_edge_lengths(complex), opt.size);
  if (opt.background) add_box(plc, sides, st.size);
  const std::vector<double> spacing = mean_edge_lengths(plc);
  const std::unique_ptr<tetgenio> out = quality_tetrahedra(plc, spacing, opt, st.size, FlatSide::kFromTetrahedron, st,
                                                                progress);
  TetMesh m = to_complex_mesh(*out, plc, sides, complex.triangles.size(), opt.background);
  st.perturbed = perturb_slivers(m, uint32_t(plc.vertices.size()));
  st.sliver_cavities = refill_sliver_cavities(m, kSliverBelowDeg);
  TriangleMesh box;
  box.vertices = plc.vertices;
  box.triangles.assign(plc.triangles.begin() + ptrdiff_t(complex.triangles.size()), plc.triangles.end());
  // Before finish() drops the unused nodes: the complex's vertices are still the first nodes.
  st.labels = label_figures(m, complex, opt.background ? enclosed_volume(box) : 0);
  finish(m, plc.vertices.size(), t0, st);
  for (const LabelTetFigures& f : st.labels) st.surface_volume += f.boundary_volume;
  st.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (stats_out) *stats_out = st;
  tell(progress, 1);
  return m;
}

TriangleMesh surface_as_complex(const TriangleMesh& surface) {
  TriangleMesh c;
  c.vertices = surface.vertices;
  for (const auto& t : surface.triangles) c.triangles.push_back({t[0], t[2], t[1]});
  c.face_labels.assign(c.triangles.size(), {0, 1});
  return c;
}

TetMesh tetrahedralize_surface(const TriangleMesh& surface, const TetOptions& opt, TetStats* stats,
                               const ProgressFn& progress) {
  if (!surface.face_labels.empty()) return tetrahedralize_complex(surface, opt, stats, progress);
  if (opt.background) return tetrahedralize_complex(surface_as_complex(surface), opt, stats, progress);
  return tetrahedralize(surface, opt, stats, progress);
}

}  // namespace mpumesh::multi
