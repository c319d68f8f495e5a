#include "io/tet_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iomanip>
#include <fstream>
#include <map>
#include <sstream>

#include "common/error.h"
#include "common/text.h"
#include "io/atomic_file.h"
#include "io/read_file.h"
#include "io/tet_text.h"
#include "io/vtu_arrays.h"

namespace mpumesh {

void tet_text::id_list(Out& o, const std::vector<uint32_t>& ids) {
  for (size_t k = 0; k < ids.size(); ++k) o.put("{}{}", ids[k] + 1, (k + 1) % 16 == 0 || k + 1 == ids.size() ? "\n" : ", ");
}

namespace {
// x in at most 20 characters, with as many significant digits as fit.
void inp_number(tet_text::Out& o, double x) {
  for (int digits = 17; digits > 1; --digits) {
    const std::string s = fmt::format("{:.{}g}", x, digits);
    if (s.size() <= 20) {
      o.s += s;
      return;
    }
  }
  o.put("{:.1g}", x);
}
}  // namespace

void tet_text::inp_node(Out& o, size_t id, const Eigen::Vector3d& p) {
  o.put("{}", id);
  for (int d = 0; d < 3; ++d) {
    o.s += ", ";
    inp_number(o, p[d]);
  }
  o.s += '\n';
}

namespace {

using tet_text::id_list;
using tet_text::Out;

// The nodes on the boundary, in order.
std::vector<uint32_t> boundary_nodes(const TetMesh& m) {
  std::vector<uint32_t> out;
  out.reserve(3 * m.boundary.size());
  for (const auto& f : m.boundary) out.insert(out.end(), f.begin(), f.end());
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

// Each region's tetrahedra, in order.
std::vector<std::vector<uint32_t>> tets_by_region(const TetMesh& m) {
  std::vector<std::vector<uint32_t>> by(size_t(std::max(m.regions, 0)) + 1);
  for (uint32_t t = 0; t < m.tets.size(); ++t) by[size_t(m.region[t])].push_back(t);
  return by;
}

std::string msh(const TetMesh& m) {
  Out o;
  o.put("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n{}\n", m.regions);
  for (int r = 1; r <= m.regions; ++r) o.put("3 {} \"region_{}\"\n", r, r);
  o.put("$EndPhysicalNames\n$Entities\n0 0 0 {}\n", m.regions);
  const auto by = tets_by_region(m);
  for (int r = 1; r <= m.regions; ++r) {
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo;
    for (uint32_t t : by[size_t(r)])
      for (uint32_t v : m.tets[t]) lo = lo.cwiseMin(m.nodes[v]), hi = hi.cwiseMax(m.nodes[v]);
    o.put("{} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} {:.17g} 1 {} 0\n", r, lo.x(), lo.y(), lo.z(), hi.x(), hi.y(),
          hi.z(), r);
  }
  // All nodes in one block of the first volume (elements of any entity may use them).
  o.put("$EndEntities\n$Nodes\n1 {} 1 {}\n3 1 0 {}\n", m.nodes.size(), m.nodes.size(), m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i) o.put("{}\n", i + 1);
  for (const auto& p : m.nodes) o.put("{:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
  o.put("$EndNodes\n$Elements\n{} {} 1 {}\n", m.regions, m.tets.size(), m.tets.size());
  size_t tag = 1;
  for (int r = 1; r <= m.regions; ++r) {
    o.put("3 {} 4 {}\n", r, by[size_t(r)].size());
    for (uint32_t t : by[size_t(r)]) {
      const auto& v = m.tets[t];
      o.put("{} {} {} {} {}\n", tag++, v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1);
    }
  }
  o.put("$EndElements\n");
  return std::move(o.s);
}

std::string vtu(const TetMesh& m) {
  Out o;
  o.put("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
        "<UnstructuredGrid>\n<Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n<Points>\n"
        "<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
        m.nodes.size(), m.tets.size());
  for (const auto& p : m.nodes) o.put("{:.17g} {:.17g} {:.17g}\n", p.x(), p.y(), p.z());
  o.put("</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
  for (const auto& t : m.tets) o.put("{} {} {} {}\n", t[0], t[1], t[2], t[3]);
  o.put("</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
  for (size_t t = 0; t < m.tets.size(); ++t) o.put("{}\n", 4 * (t + 1));
  o.put("</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
  for (size_t t = 0; t < m.tets.size(); ++t) o.put("10\n");
  o.put("</DataArray>\n</Cells>\n<CellData Scalars=\"region\">\n"
        "<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n");
  for (int32_t r : m.region) o.put("{}\n", r);
  o.put("</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
  return std::move(o.s);
}

}  // namespace

std::string tet_text::medit(const TetMesh& m, const std::string& comments, const std::vector<int32_t>& triangle_ref) {
  // A vertex's reference: the region of a tetrahedron that uses it.
  std::vector<int32_t> ref(m.nodes.size(), 0);
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (uint32_t v : m.tets[t]) ref[v] = m.region[t];
  Out o;
  o.put("MeshVersionFormatted 2\nDimension 3\n{}Vertices\n{}\n", comments, m.nodes.size());
  for (size_t i = 0; i < m.nodes.size(); ++i)
    o.put("{:.17g} {:.17g} {:.17g} {}\n", m.nodes[i].x(), m.nodes[i].y(), m.nodes[i].z(), ref[i]);
  o.put("Tetrahedra\n{}\n", m.tets.size());
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const auto& v = m.tets[t];
    o.put("{} {} {} {} {}\n", v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1, m.region[t]);
  }
  o.put("Triangles\n{}\n", m.boundary.size());
  for (size_t f = 0; f < m.boundary.size(); ++f) {
    const auto& v = m.boundary[f];
    o.put("{} {} {} {}\n", v[0] + 1, v[1] + 1, v[2] + 1, triangle_ref[f]);
  }
  o.put("End\n");
  return std::move(o.s);
}

namespace {

std::string inp(const TetMesh& m) {
  Out o;
  o.put("** Written by mpumesh: {} nodes, {} linear tetrahedra (C3D4), {} regions; the mesh only, to be\n"
        "** *INCLUDEd by an analysis deck. Sets: NALL, EALL, REGION_1 ..., BOUNDARY (the surface's nodes).\n",
        m.nodes.size(), m.tets.size(), m.regions);
  o.put("*NODE, NSET=NALL\n");
  for (size_t i = 0; i < m.nodes.size(); ++i) tet_text::inp_node(o, i + 1, m.nodes[i]);
  o.put("*ELEMENT, TYPE=C3D4, ELSET=EALL\n");
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const auto& v = m.tets[t];
    o.put("{}, {}, {}, {}, {}\n", t + 1, v[0] + 1, v[1] + 1, v[2] + 1, v[3] + 1);
  }
  const auto by = tets_by_region(m);
  for (int r = 1; r <= m.regions; ++r) {
    o.put("*ELSET, ELSET=REGION_{}\n", r);
    id_list(o, by[size_t(r)]);
  }
  o.put("*NSET, NSET=BOUNDARY\n");
  id_list(o, boundary_nodes(m));
  return std::move(o.s);
}

// Readers ------------------------------------------------------------------------------

[[noreturn]] void bad(const std::string& path, const std::string& what) {
  throw InputError(path + ": not a volume mesh mpumesh can read: " + what);
}

// Regions from the tetrahedra's numbers, and the count.
void finish(TetMesh& m, const std::string& path) {
  for (const auto& t : m.tets)
    for (uint32_t v : t)
      if (v >= m.nodes.size()) bad(path, "a tetrahedron names node " + std::to_string(v + 1) + " of " + std::to_string(m.nodes.size()));
  for (const auto& f : m.boundary)
    for (uint32_t v : f)
      if (v >= m.nodes.size()) bad(path, "a triangle names node " + std::to_string(v + 1) + " of " + std::to_string(m.nodes.size()));
  std::vector<int32_t> present = m.region;
  std::sort(present.begin(), present.end());
  m.regions = int32_t(std::unique(present.begin(), present.end()) - present.begin());
}

// A group's name as the writers spell it (any case): label_L or region_r for tetrahedra,
// interface_a_b or box for triangles; false for another name.
bool parse_label(const std::string& name, int32_t& label) {
  const std::string n = lower_case(name);
  for (const char* prefix : {"label_", "region_"})
    if (n.rfind(prefix, 0) == 0) return std::sscanf(n.c_str() + std::strlen(prefix), "%d", &label) == 1;
  return false;
}
bool parse_interface(const std::string& name, std::array<int32_t, 2>& labels) {
  const std::string n = lower_case(name);
  if (n == "box") return labels = {0, 0}, true;
  return std::sscanf(n.c_str(), "interface_%d_%d", &labels[0], &labels[1]) == 2;
}

// MSH 4.1's $Entities: each entity's first physical tag, by (dimension, tag).
std::map<std::pair<int, int>, int> read_msh_entities(std::istream& in) {
  std::map<std::pair<int, int>, int> physical;
  size_t count[4];
  in >> count[0] >> count[1] >> count[2] >> count[3];
  for (int dim = 0; dim < 4; ++dim)
    for (size_t e = 0; e < count[dim] && in; ++e) {
      int tag;
      size_t n;
      double x;
      in >> tag;
      for (int k = 0; k < (dim == 0 ? 3 : 6); ++k) in >> x;
      in >> n;
      for (size_t k = 0; k < n && in; ++k) {
        int p;
        in >> p;
        if (k == 0) physical[{dim, tag}] = p;
      }
      if (dim == 0) continue;
      in >> n;
      for (size_t k = 0; k < n && in; ++k) in >> x;
    }
  return physical;
}

TetMesh read_msh(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  std::string line;
  TetMesh m;
  std::map<int64_t, uint32_t> node_index;
  std::map<std::pair<int, int>, std::string> names;  // (dimension, physical tag) -> name
  std::map<std::pair<int, int>, int> physical;       // (dimension, entity tag) -> physical tag
  auto name_of = [&](int dim, int entity) {
    const auto p = physical.find({dim, entity});
    if (p == physical.end()) return std::string();
    const auto n = names.find({dim, p->second});
    return n == names.end() ? std::string() : n->second;
  };
  while (std::getline(in, line)) {
    if (line == "$MeshFormat") {
      std::string version;
      in >> version;
      if (version.rfind("4.1", 0) != 0) bad(path, "MSH version " + version + " (4.1 is read)");
    } else if (line == "$PhysicalNames") {
      size_t n;
      in >> n;
      for (size_t k = 0; k < n && in; ++k) {
        int dim, tag;
        std::string name;
        in >> dim >> tag >> std::quoted(name);
        names[{dim, tag}] = name;
      }
    } else if (line == "$Entities") {
      physical = read_msh_entities(in);
    } else if (line == "$Nodes") {
      size_t blocks, count, lo, hi;
      in >> blocks >> count >> lo >> hi;
      for (size_t b = 0; b < blocks; ++b) {
        int dim, tag, param;
        size_t n;
        in >> dim >> tag >> param >> n;
        if (!in || n > text.size()) bad(path, "a node block cut short or malformed");
        std::vector<int64_t> tags(n);
        for (auto& t : tags) in >> t;
        for (size_t k = 0; k < n; ++k) {
          Eigen::Vector3d p;
          in >> p.x() >> p.y() >> p.z();
          node_index[tags[k]] = uint32_t(m.nodes.size());
          m.nodes.push_back(p);
        }
      }
    } else if (line == "$Elements") {
      size_t blocks, count, lo, hi;
      in >> blocks >> count >> lo >> hi;
      for (size_t b = 0; b < blocks; ++b) {
        int dim, tag, type;
        size_t n;
        in >> dim >> tag >> type >> n;
        if (!in || n > text.size()) bad(path, "an element block cut short or malformed");
        const int nodes = type == 4 ? 4 : type == 2 ? 3 : type == 1 ? 2 : type == 15 ? 1 : -1;
        if (nodes < 0) bad(path, "element type " + std::to_string(type));
        // A volume's region: its label, or its entity; a surface's triangles are a complex's
        // interface when named so.
        int32_t region = tag;
        std::array<int32_t, 2> labels{};
        if (type == 4) parse_label(name_of(dim, tag), region);
        const bool interface = type == 2 && parse_interface(name_of(dim, tag), labels);
        for (size_t k = 0; k < n; ++k) {
          int64_t id, v[4];
          in >> id;
          for (int j = 0; j < nodes; ++j) in >> v[j];
          if (!in) bad(path, "an element block cut short or malformed");
          if (type != 4 && !interface) continue;
          std::array<uint32_t, 4> t{};
          for (int j = 0; j < nodes; ++j) {
            const auto it = node_index.find(v[j]);
            if (it == node_index.end()) bad(path, "an element names node " + std::to_string(v[j]) + ", which is not listed");
            t[size_t(j)] = it->second;
          }
          if (type == 4) {
            m.tets.push_back(t);
            m.region.push_back(region);
          } else {
            m.boundary.push_back({t[0], t[1], t[2]});
            m.boundary_labels.push_back(labels);
            m.boundary_region.push_back(labels[1]);
          }
        }
      }
    }
    if (!in) bad(path, "cut short or malformed");
  }
  return m;
}

// A .vtu file's tetrahedra (cell type 10) and triangles (5), ASCII or binary
// (io/vtu_arrays.h): one surface's `region` per cell, or a complex's (`label`, or `label_a`
// and `label_b` on its triangles), as mpumesh and meshio write them.
TetMesh read_vtu(const std::string& text, const std::string& path) {
  const VtuArrays arrays(text, path);
  TetMesh m;
  const std::vector<double> xyz = arrays.numbers("");
  if (xyz.size() % 3 != 0) bad(path, "the points' coordinates are not triples");
  for (size_t i = 0; i + 2 < xyz.size(); i += 3) m.nodes.emplace_back(xyz[i], xyz[i + 1], xyz[i + 2]);
  const std::vector<double> conn = arrays.numbers("connectivity"), types = arrays.numbers("types");
  const bool complex = arrays.has("label") || arrays.has("label_a");
  auto per_cell = [&](const char* name, double otherwise) {
    std::vector<double> v = arrays.has(name) ? arrays.numbers(name) : std::vector<double>();
    if (!v.empty() && v.size() != types.size()) bad(path, std::string("array ") + name + " is not one value per cell");
    if (v.empty()) v.assign(types.size(), otherwise);
    return v;
  };
  const std::vector<double> regions = per_cell(arrays.has("label") ? "label" : "region", 1),
                            label_a = per_cell("label_a", -1), label_b = per_cell("label_b", -1);
  // A cell's type, region or label: an integer that fits 32 bits.
  auto integer = [&](double v, const char* what) -> int32_t {
    if (!(v >= -2147483648.0 && v <= 2147483647.0) || v != std::floor(v))
      bad(path, std::string("a cell's ") + what + " is not a 32-bit integer");
    return int32_t(v);
  };
  size_t at = 0;
  auto node = [&]() -> uint32_t {
    if (at >= conn.size()) bad(path, "connectivity cut short");
    const double v = conn[at++];
    if (!(v >= 0 && v < double(m.nodes.size()))) bad(path, "a cell names a node beyond the points");
    return uint32_t(v);
  };
  for (size_t c = 0; c < types.size(); ++c) {
    const int type = integer(types[c], "type");
    if (type == 5) {
      const std::array<uint32_t, 3> f = {node(), node(), node()};
      m.boundary.push_back(f);
      if (complex) {
        m.boundary_labels.push_back({integer(label_a[c], "label_a"), integer(label_b[c], "label_b")});
        m.boundary_region.push_back(m.boundary_labels.back()[1]);
      } else {
        m.boundary_region.push_back(integer(regions[c], "region"));
      }
      continue;
    }
    if (type != 10) bad(path, "cell type " + std::to_string(type) + " (10, a tetrahedron, and 5, a triangle, are read)");
    const std::array<uint32_t, 4> t = {node(), node(), node(), node()};
    m.tets.push_back(t);
    m.region.push_back(integer(regions[c], "region"));
  }
  return m;
}

// A medit cell block after its keyword: the count, then per cell its 1-based nodes and
// its reference.
template <size_t N>
void read_medit_cells(std::istream& in, std::vector<std::array<uint32_t, N>>& cells, std::vector<int32_t>& refs) {
  size_t n;
  in >> n;
  for (size_t i = 0; i < n && in; ++i) {
    std::array<uint32_t, N> c;
    int32_t ref;
    for (auto& v : c) in >> v, --v;
    in >> ref;
    cells.push_back(c);
    refs.push_back(ref);
  }
}

TetMesh read_medit(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  TetMesh m;
  std::map<int32_t, std::array<int32_t, 2>> interfaces;  // a complex's: triangle reference -> labels
  for (std::string word; in >> word;) {
    if (word[0] == '#') {  // a comment line; a complex's interfaces are named in them
      std::string line;
      std::getline(in, line);
      int32_t k, a, b;
      if (std::sscanf(line.c_str(), " interface %d: labels %d %d", &k, &a, &b) == 3) interfaces[k] = {a, b};
      continue;
    }
    if (word == "Vertices") {
      size_t n;
      in >> n;
      for (size_t i = 0; i < n && in; ++i) {
        Eigen::Vector3d p;
        int ref;
        in >> p.x() >> p.y() >> p.z() >> ref;
        m.nodes.push_back(p);
      }
    } else if (word == "Tetrahedra") {
      read_medit_cells(in, m.tets, m.region);
    } else if (word == "Triangles") {
      read_medit_cells(in, m.boundary, m.boundary_region);
    }
    if (!in && !in.eof()) bad(path, "cut short or malformed after " + word);
  }
  if (!interfaces.empty())
    for (int32_t& ref : m.boundary_region) {
      const auto it = interfaces.find(ref);
      if (it == interfaces.end()) bad(path, "a triangle's reference " + std::to_string(ref) + " names no interface");
      m.boundary_labels.push_back(it->second);
      ref = it->second[1];
    }
  return m;
}

TetMesh read_inp(const std::string& text, const std::string& path) {
  std::istringstream in(text);
  TetMesh m;
  std::map<int64_t, uint32_t> node_index, elem_index;
  std::string mode, set;
  std::vector<std::pair<std::string, std::vector<int64_t>>> elsets;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("**", 0) == 0 || line.empty()) continue;
    if (line[0] == '*') {
      const std::string head = lower_case(line);
      const auto keyword = [&](const char* k) { return head == k || head.rfind(std::string(k) + ",", 0) == 0; };
      mode = keyword("*node") ? "node" : keyword("*element") ? "element" : keyword("*elset") ? "elset" : "";
      if (mode == "element" && head.find("c3d4") == std::string::npos) bad(path, "elements other than C3D4");
      if (mode == "elset") {
        const size_t at = head.find("elset=");
        elsets.push_back({line.substr(at + 6), {}});
      }
      continue;
    }
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    if (mode == "node") {
      int64_t id;
      Eigen::Vector3d p;
      row >> id >> p.x() >> p.y() >> p.z();
      node_index[id] = uint32_t(m.nodes.size());
      m.nodes.push_back(p);
    } else if (mode == "element") {
      int64_t id, v[4];
      row >> id >> v[0] >> v[1] >> v[2] >> v[3];
      std::array<uint32_t, 4> t;
      for (int j = 0; j < 4; ++j) {
        const auto it = node_index.find(v[j]);
        if (it == node_index.end()) bad(path, "an element names node " + std::to_string(v[j]) + ", which is not listed");
        t[size_t(j)] = it->second;
      }
      elem_index[id] = uint32_t(m.tets.size());
      m.tets.push_back(t);
      m.region.push_back(1);
    } else if (mode == "elset") {
      for (int64_t id; row >> id;) elsets.back().second.push_back(id);
    }
  }
  // The regions from the ELSETs named REGION_r (one surface's) or LABEL_l (a complex's).
  for (const auto& [name, ids] : elsets) {
    int32_t r = 0;
    if (!parse_label(name, r)) continue;
    for (int64_t id : ids) {
      const auto it = elem_index.find(id);
      if (it != elem_index.end()) m.region[it->second] = r;
    }
  }
  return m;
}

}  // namespace

bool is_tet_mesh_path(const std::string& path) {
  const std::string ext = lower_case(std::filesystem::path(path).extension().string());
  return ext == ".msh" || ext == ".vtu" || ext == ".mesh" || ext == ".inp";
}

TetFormat tet_format_from_path(const std::string& path) {
  const std::string ext = lower_case(std::filesystem::path(path).extension().string());
  if (ext == ".msh") return TetFormat::kMsh;
  if (ext == ".vtu") return TetFormat::kVtu;
  if (ext == ".mesh") return TetFormat::kMedit;
  if (ext == ".inp") return TetFormat::kInp;
  throw InputError(path + ": unknown volume mesh format '" + ext + "' (use .msh, .vtu, .mesh or .inp)");
}

void write_tet_mesh(const TetMesh& m, const std::string& path) {
  const TetFormat f = tet_format_from_path(path);
  MPUMESH_ASSERT(m.region.size() == m.tets.size() && m.boundary_region.size() == m.boundary.size(),
                 "volume mesh regions");
  std::string bytes;
  const bool complex = m.multi_material();
  switch (f) {
    case TetFormat::kMsh: bytes = complex ? tet_text::msh_complex(m) : msh(m); break;
    case TetFormat::kVtu: bytes = complex ? tet_text::vtu_complex(m) : vtu(m); break;
    case TetFormat::kMedit: bytes = complex ? tet_text::medit_complex(m) : tet_text::medit(m, "", m.boundary_region); break;
    case TetFormat::kInp: bytes = complex ? tet_text::inp_complex(m) : inp(m); break;
  }
  write_file_atomically(bytes, path);
}

TetMesh read_tet_mesh(const std::string& path) {
  const TetFormat f = tet_format_from_path(path);
  return parse_tet_mesh(read_file(path), f, path);
}

TetMesh parse_tet_mesh(const std::string& text, TetFormat f, const std::string& path) {
  TetMesh m;
  switch (f) {
    case TetFormat::kMsh: m = read_msh(text, path); break;
    case TetFormat::kVtu: m = read_vtu(text, path); break;
    case TetFormat::kMedit: m = read_medit(text, path); break;
    case TetFormat::kInp: m = read_inp(text, path); break;
  }
  finish(m, path);
  if (m.tets.empty()) bad(path, "no tetrahedra");
  return m;
}

}  // namespace mpumesh
