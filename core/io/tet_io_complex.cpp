// A multi-material complex's volume mesh in the four formats (io/tet_io.h), with the groups
// finite-element users look for: a volume per label and a surface per interface.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <unordered_map>

#include "io/tet_text.h"

namespace mpumesh::tet_text {
namespace {

// The labels and the interfaces, ascending, with their tetrahedra and their triangles.
struct Groups {
  std::vector<int32_t> labels;
  std::vector<std::vector<uint32_t>> tets_of;
  std::vector<std::array<int32_t, 2>> interfaces;
  std::vector<std::vector<uint32_t>> faces_of;
};

Groups groups(const TetMesh& m) {
  std::map<int32_t, std::vector<uint32_t>> tets;
  for (uint32_t t = 0; t < m.tets.size(); ++t) tets[m.region[t]].push_back(t);
  std::map<std::array<int32_t, 2>, std::vector<uint32_t>> faces;
  for (uint32_t f = 0; f < m.boundary.size(); ++f) faces[m.boundary_labels[f]].push_back(f);
  Groups g;
  for (auto& [l, ts] : tets) g.labels.push_back(l), g.tets_of.push_back(std::move(ts));
  for (auto& [pair, fs] : faces) g.interfaces.push_back(pair), g.faces_of.push_back(std::move(fs));
  return g;
}

// The bounding box of nodes, as MSH 4.1's entities give it.
template <class Cells>
std::string box_of(const TetMesh& m, const Cells& cells, const std::vector<uint32_t>& ids) {
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
  for (uint32_t i : ids)
    for (uint32_t v : cells[i]) lo = lo.cwiseMin(m.nodes[v]), hi = hi.cwiseMax(m.nodes[v]);
  return fmt::format("{:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g}", lo.x(), lo.y(), lo.z(), hi.x(), hi.y(), hi.z());
}

std::string upper(std::string s) {
  std::ranges::transform(s, s.begin(), [](unsigned char c) { return char(std::toupper(c)); });
  return s;
}

struct FaceHash {
  size_t operator()(const std::array<uint32_t, 3>& f) const {
    return std::hash<uint64_t>()((uint64_t(f[0]) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(f[1]) << 32) ^ f[2]);
  }
};

}  // namespace

std::string label_name(int32_t label) { return fmt::format("label_{}", label); }

std::string interface_name(const std::array<int32_t, 2>& labels) {
  return labels[0] == labels[1] ? "box" : fmt::format("interface_{}_{}", labels[0], labels[1]);
}

std::string msh_complex(const TetMesh& m) {
  const Groups g = groups(m);
  const size_t nl = g.labels.size(), ni = g.interfaces.size();
  Out o;
  o.put("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n{}\n", nl + ni);
  for (size_t i = 0; i < nl; ++i) o.put("3 {} \"{}\"\n", i + 1, label_name(g.labels[i]));
  for (size_t j = 0; j < ni; ++j) o.put("2 {} \"{}\"\n", nl + j + 1, interface_name(g.interfaces[j]));
  o.put("$EndPhysicalNames\n$Entities\n0 0 {} {}\n", ni, nl);
  for (size_t j = 0; j < ni; ++j) o.put("{} {} 1 {} 0\n", j + 1, box_of(m, m.boundary, g.faces_of[j]), nl + j + 1);
  for (size_t i = 0; i < nl; ++i) o.put("{} {} 1 {} 0\n", i + 1, box_of(m, m.tets, g.tets_of[i]), i + 1);
  // All nodes in one block of the first volume (elements of any entity may use them).
  o.put("$EndEntities\n$Nodes\n1 {} 1 {}\n3 1 0 {}\n", m.nodes.size(), m.nodes.size(), m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i) o.put("{}\n", i + 1);
  for (const auto& p : m.nodes) o.put("{:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
  const size_t cells = m.boundary.size() + m.tets.size();
  o.put("$EndNodes\n$Elements\n{} {} 1 {}\n", ni + nl, cells, cells);
  size_t tag = 1;
  for (size_t j = 0; j < ni; ++j) {
    o.put("2 {} 2 {}\n", j + 1, g.faces_of[j].size());
    for (uint32_t f : g.faces_of[j]) {
      const auto& v = m.boundary[f];
      o.put("{} {} {} {}\n", tag++, v[0] + 1, v[1] + 1, v[2] + 1);
    }
  }
  for (size_t i = 0; i < nl; ++i) {
    o.put("3 {} 4 {}\n", i + 1, g.tets_of[i].size());
    for (uint32_t t : g.tets_of[i]) {
      const auto& v = m.tets[t];
      o.put("{} {} {} {} {}\n", tag++, v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1);
    }
  }
  o.put("$EndElements\n");
  return std::move(o.s);
}

std::string vtu_complex(const TetMesh& m) {
  const size_t cells = m.tets.size() + m.boundary.size();
  Out o;
  o.put("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<Points>\n"
        "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
        m.nodes.size(), cells);
  for (const auto& p : m.nodes) o.put("{:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
  o.put("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (const auto& t : m.tets) o.put("{} {} {} {}\n", t[0], t[1], t[2], t[3]);
  for (const auto& f : m.boundary) o.put("{} {} {}\n", f[0], f[1], f[2]);
  o.put("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (size_t t = 0; t < m.tets.size(); ++t) o.put("{}\n", 4 * (t + 1));
  for (size_t f = 0; f < m.boundary.size(); ++f) o.put("{}\n", 4 * m.tets.size() + 3 * (f + 1));
  o.put("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (size_t t = 0; t < m.tets.size(); ++t) o.put("10\n");
  for (size_t f = 0; f < m.boundary.size(); ++f) o.put("5\n");
  // A tetrahedron's label; a triangle's two (-1 where a cell has none of them).
  o.put("</DataArray>\n</Cells>\n<CellData Scalars=\"label\">\n<DataArray type=\"Int32\" Name=\"label\" format=\"ascii\">\n");
  for (int32_t r : m.region) o.put("{}\n", r);
  for (size_t f = 0; f < m.boundary.size(); ++f) o.put("-1\n");
  for (int side = 0; side < 2; ++side) {
    o.put("</DataArray>\n<DataArray type=\"Int32\" Name=\"label_{}\" format=\"ascii\">\n", side == 0 ? 'a' : 'b');
    for (size_t t = 0; t < m.tets.size(); ++t) o.put("-1\n");
    for (const auto& l : m.boundary_labels) o.put("{}\n", l[size_t(side)]);
  }
  o.put("</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
  return std::move(o.s);
}

std::string medit_complex(const TetMesh& m) {
  const Groups g = groups(m);
  std::map<std::array<int32_t, 2>, int32_t> number;
  std::string comments = "# Tetrahedra: the reference is the label. Triangles: the reference numbers the interface:\n";
  for (size_t j = 0; j < g.interfaces.size(); ++j) {
    number[g.interfaces[j]] = int32_t(j) + 1;
    comments += fmt::format("# interface {}: labels {} {}\n", j + 1, g.interfaces[j][0], g.interfaces[j][1]);
  }
  std::vector<int32_t> ref;
  for (const auto& l : m.boundary_labels) ref.push_back(number.at(l));
  return medit(m, comments, ref);
}

std::string inp_complex(const TetMesh& m) {
  const Groups g = groups(m);
  Out o;
  o.put("** Written by mpumesh: {} nodes, {} linear tetrahedra (C3D4), {} labels; the mesh only, to be\n"
        "** *INCLUDEd by an analysis deck. Sets: NALL, EALL, an ELSET LABEL_l per label, an NSET and an\n"
        "** element-face *SURFACE INTERFACE_a_b per interface (the faces of label a's tetrahedra, or of b's\n"
        "** where a, the background, is not meshed; BOX: the background's box).\n",
        m.nodes.size(), m.tets.size(), g.labels.size());
  o.put("*NODE, NSET=NALL\n");
  for (size_t i = 0; i < m.nodes.size(); ++i) tet_text::inp_node(o, i + 1, m.nodes[i]);
  o.put("*ELEMENT, TYPE=C3D4, ELSET=EALL\n");
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const auto& v = m.tets[t];
    o.put("{}, {}, {}, {}, {}\n", t + 1, v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1);
  }
  for (size_t i = 0; i < g.labels.size(); ++i) {
    o.put("*ELSET, ELSET={}\n", upper(label_name(g.labels[i])));
    id_list(o, g.tets_of[i]);
  }
  // Each face of a tetrahedron by its sorted nodes: the tetrahedra that have it, with the
  // node opposite.
  std::unordered_map<std::array<uint32_t, 3>, std::vector<std::pair<uint32_t, int>>, FaceHash> faces;
  faces.reserve(4 * m.tets.size());
  for (uint32_t t = 0; t < m.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<uint32_t, 3> f = {m.tets[t][size_t(kTetFace[k][0])], m.tets[t][size_t(kTetFace[k][1])],
                                   m.tets[t][size_t(kTetFace[k][2])]};
      std::ranges::sort(f);
      faces[f].push_back({t, k});
    }
  // C3D4's faces: S1 = nodes 1-2-3 (opposite node 4), S2 = 1-4-2, S3 = 2-4-3, S4 = 3-4-1.
  constexpr int kFaceOpposite[4] = {3, 4, 2, 1};  // the S number of the face opposite node k + 1
  for (size_t j = 0; j < g.interfaces.size(); ++j) {
    const std::string name = upper(interface_name(g.interfaces[j]));
    std::vector<uint32_t> nodes;
    for (uint32_t f : g.faces_of[j]) nodes.insert(nodes.end(), m.boundary[f].begin(), m.boundary[f].end());
    std::ranges::sort(nodes);
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    o.put("*NSET, NSET={}\n", name);
    id_list(o, nodes);
    o.put("*SURFACE, NAME={}, TYPE=ELEMENT\n", name);
    for (uint32_t f : g.faces_of[j]) {
      std::array<uint32_t, 3> key = m.boundary[f];
      std::ranges::sort(key);
      const auto& have = faces.at(key);
      const auto side = [&](int32_t label) {
        return std::ranges::find_if(have, [&](const auto& tk) { return m.region[tk.first] == label; });
      };
      auto it = side(g.interfaces[j][0]);
      if (it == have.end()) it = side(g.interfaces[j][1]);
      o.put("{}, S{}\n", it->first + 1, kFaceOpposite[it->second]);
    }
  }
  return std::move(o.s);
}

}  // namespace mpumesh::tet_text
