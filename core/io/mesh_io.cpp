#include "io/mesh_io.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <unordered_map>

#include "common/error.h"
#include "io/atomic_file.h"
#include "io/read_file.h"

namespace mpumesh {
namespace {

void add_polygon(TriangleMesh& m, const std::vector<int64_t>& idx, const std::string& name) {
  if (idx.size() < 3) throw InputError(name + ": a face has fewer than 3 vertices");
  for (int64_t i : idx)
    if (i < 0 || i >= int64_t(m.vertices.size()))
      throw InputError(name + ": face index " + std::to_string(i) + " is out of range (" +
                       std::to_string(m.vertices.size()) + " vertices)");
  for (size_t k = 1; k + 1 < idx.size(); ++k)
    m.triangles.push_back({uint32_t(idx[0]), uint32_t(idx[k]), uint32_t(idx[k + 1])});
}

void check_finite(const TriangleMesh& m, const std::string& name) {
  for (const auto& v : m.vertices)
    if (!v.allFinite()) throw InputError(name + ": a vertex coordinate is NaN or infinite");
}

// ---------------------------------------------------------------- PLY
struct PlyProp {
  std::string name, type, list_count_type;  // list_count_type empty unless a list
};
struct PlyElement {
  std::string name;
  int64_t count = 0;
  std::vector<PlyProp> props;
};

int ply_type_size(const std::string& t, const std::string& name) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  throw InputError(name + ": unknown PLY property type '" + t + "'");
}

class PlyBinaryCursor {
 public:
  PlyBinaryCursor(const std::string& b, size_t at, bool big, const std::string& name)
      : b_(b), at_(at), big_(big), name_(name) {}
  double read(const std::string& t) {
    int n = ply_type_size(t, name_);
    if (at_ + size_t(n) > b_.size()) throw InputError(name_ + ": truncated PLY data");
    unsigned char raw[8];
    std::memcpy(raw, b_.data() + at_, size_t(n));
    at_ += size_t(n);
    if (big_) std::reverse(raw, raw + n);
    auto get = [&](auto v) {
      std::memcpy(&v, raw, sizeof v);
      return double(v);
    };
    if (t == "char" || t == "int8") return get(int8_t{});
    if (t == "uchar" || t == "uint8") return get(uint8_t{});
    if (t == "short" || t == "int16") return get(int16_t{});
    if (t == "ushort" || t == "uint16") return get(uint16_t{});
    if (t == "int" || t == "int32") return get(int32_t{});
    if (t == "uint" || t == "uint32") return get(uint32_t{});
    if (t == "float" || t == "float32") return get(float{});
    return get(double{});
  }

 private:
  const std::string& b_;
  size_t at_;
  bool big_;
  const std::string& name_;
};

// The header of a PLY file: its format, its elements with their properties, and where
// the data start.
struct PlyHeader {
  std::string format;
  std::vector<PlyElement> elems;
  size_t data = 0;
};

PlyHeader parse_ply_header(const std::string& b, const std::string& name) {
  if (b.compare(0, 4, "ply\n") != 0 && b.compare(0, 5, "ply\r\n") != 0)
    throw InputError(name + ": not a PLY file (no 'ply' magic)");
  size_t end = b.find("end_header");
  if (end == std::string::npos) throw InputError(name + ": PLY header has no end_header");
  PlyHeader h;
  h.data = b.find('\n', end);
  if (h.data == std::string::npos) throw InputError(name + ": truncated PLY header");
  ++h.data;
  std::istringstream hs(b.substr(0, end));
  std::string line;
  while (std::getline(hs, line)) {
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "format") {
      ls >> h.format;
    } else if (kw == "element") {
      PlyElement e;
      ls >> e.name >> e.count;
      if (!ls || e.count < 0) throw InputError(name + ": bad PLY element line '" + line + "'");
      h.elems.push_back(e);
    } else if (kw == "property") {
      if (h.elems.empty()) throw InputError(name + ": PLY property before any element");
      PlyProp p;
      ls >> p.type;
      if (p.type == "list") ls >> p.list_count_type >> p.type;
      ls >> p.name;
      if (!ls) throw InputError(name + ": bad PLY property line '" + line + "'");
      ply_type_size(p.type, name);
      if (!p.list_count_type.empty()) ply_type_size(p.list_count_type, name);
      h.elems.back().props.push_back(p);
    }
  }
  if (h.format != "ascii" && h.format != "binary_little_endian" && h.format != "binary_big_endian")
    throw InputError(name + ": unsupported PLY format '" + h.format + "'");
  // Sizes are bounded by the file before anything is allocated.
  for (const auto& e : h.elems)
    if (e.count > int64_t(b.size())) throw InputError(name + ": PLY element count exceeds the file size");
  return h;
}

// The data's values one by one, as text or binary.
class PlyValues {
 public:
  PlyValues(const std::string& b, const PlyHeader& h, const std::string& name)
      : ascii_(h.format == "ascii"),
        text_(ascii_ ? b.substr(h.data) : std::string()),
        cursor_(b, h.data, h.format == "binary_big_endian", name),
        name_(name) {}
  double next(const std::string& type) {
    if (!ascii_) return cursor_.read(type);
    double v;
    if (!(text_ >> v)) throw InputError(name_ + ": truncated or malformed PLY data");
    return v;
  }

 private:
  bool ascii_;
  std::istringstream text_;
  PlyBinaryCursor cursor_;
  const std::string& name_;
};

// Where an element's properties of interest sit (-1: absent).
struct PlyColumns {
  int x = -1, y = -1, z = -1, nx = -1, ny = -1, nz = -1;
  int k[4] = {-1, -1, -1, -1};  // k1 k2 K H
  int label_a = -1, label_b = -1;  // a face's regions (a multi-material complex)
  explicit PlyColumns(const PlyElement& e) {
    static const char* const kCurvatureNames[4] = {"k1", "k2", "K", "H"};
    for (size_t i = 0; i < e.props.size(); ++i) {
      const std::string& n = e.props[i].name;
      for (int c = 0; c < 4; ++c)
        if (n == kCurvatureNames[c] && e.props[i].list_count_type.empty()) k[c] = int(i);
      if (n == "x") x = int(i);
      if (n == "y") y = int(i);
      if (n == "z") z = int(i);
      if (n == "nx") nx = int(i);
      if (n == "ny") ny = int(i);
      if (n == "nz") nz = int(i);
      if (n == "label_a" && e.props[i].list_count_type.empty()) label_a = int(i);
      if (n == "label_b" && e.props[i].list_count_type.empty()) label_b = int(i);
    }
  }
  bool labels() const { return label_a >= 0 && label_b >= 0; }
  bool normals() const { return nx >= 0 && ny >= 0 && nz >= 0; }
  bool curvature() const { return k[0] >= 0 && k[1] >= 0 && k[2] >= 0 && k[3] >= 0; }
};

// One element's rows into the mesh: vertices (with their normals and curvature) or faces;
// any other element's values are read past.
void read_ply_element(const PlyElement& e, PlyValues& values, TriangleMesh& m, std::vector<Eigen::Vector3d>* normals,
                      const std::string& name) {
  const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
  const PlyColumns col(e);
  if (is_vertex && (col.x < 0 || col.y < 0 || col.z < 0)) throw InputError(name + ": PLY vertices lack x, y or z");
  if (is_vertex && normals && !col.normals()) throw InputError(name + ": PLY vertices lack the normal nx, ny, nz");
  if (is_vertex) m.vertices.reserve(size_t(e.count));
  std::vector<int64_t> idx;
  for (int64_t r = 0; r < e.count; ++r) {
    Eigen::Vector3d v = Eigen::Vector3d::Zero(), nv = Eigen::Vector3d::Zero();
    std::array<float, 4> kv{};
    std::array<double, 2> pair{0, 0};
    for (size_t i = 0; i < e.props.size(); ++i) {
      const PlyProp& p = e.props[i];
      if (!p.list_count_type.empty()) {
        double cnt = values.next(p.list_count_type);
        if (!(cnt >= 0 && cnt <= 1e6)) throw InputError(name + ": bad PLY list length");
        idx.clear();
        for (int64_t c = 0; c < int64_t(cnt); ++c) {
          double x = values.next(p.type);
          if (!(std::abs(x) < 9.2e18)) throw InputError(name + ": bad PLY face index");
          idx.push_back(int64_t(x));
        }
        if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) add_polygon(m, idx, name);
        continue;
      }
      const double x = values.next(p.type);
      const int at = int(i);
      if (at == col.x) v.x() = x;
      if (at == col.y) v.y() = x;
      if (at == col.z) v.z() = x;
      if (at == col.nx) nv.x() = x;
      if (at == col.ny) nv.y() = x;
      if (at == col.nz) nv.z() = x;
      for (int c = 0; c < 4; ++c)
        if (at == col.k[c]) kv[size_t(c)] = float(x);
      if (at == col.label_a) pair[0] = x;
      if (at == col.label_b) pair[1] = x;
    }
    if (is_face && col.labels()) {
      for (const double l : pair)
        if (!(l >= 0 && l < 2147483648.0 && l == std::floor(l)))
          throw InputError(name + ": bad PLY face label (label_a and label_b are whole numbers, 0 or more)");
      m.face_labels.resize(m.triangles.size(), {int32_t(pair[0]), int32_t(pair[1])});
    }
    if (!is_vertex) continue;
    m.vertices.push_back(v);
    if (normals) normals->push_back(nv);
    if (col.normals()) m.normals.push_back(nv.cast<float>());
    if (col.curvature()) m.curvature.push_back(kv);
  }
}

}  // namespace

namespace detail {
TriangleMesh parse_ply(const std::string& b, const std::string& name, std::vector<Eigen::Vector3d>* normals) {
  const PlyHeader h = parse_ply_header(b, name);
  PlyValues values(b, h, name);
  TriangleMesh m;
  for (const auto& e : h.elems) read_ply_element(e, values, m, normals, name);
  return m;
}
}  // namespace detail

namespace {

void write_ply(const TriangleMesh& m, std::ostream& os) {
  static_assert(std::endian::native == std::endian::little, "PLY writer assumes a little-endian host");
  const bool normals = m.normals.size() == m.vertices.size() && !m.vertices.empty();
  const bool curvature = m.curvature.size() == m.vertices.size() && !m.vertices.empty();
  os << "ply\nformat binary_little_endian 1.0\ncomment mpumesh, units mm\n";
  if (curvature) os << "comment k1 >= k2 principal curvatures (1/mm), K Gaussian (1/mm^2), H mean (1/mm)\n";
  os << "element vertex " << m.vertices.size() << "\nproperty float x\nproperty float y\nproperty float z\n";
  if (normals) os << "property float nx\nproperty float ny\nproperty float nz\n";
  if (curvature) os << "property float k1\nproperty float k2\nproperty float K\nproperty float H\n";
  const bool labels = m.face_labels.size() == m.triangles.size() && !m.triangles.empty();
  os << "element face " << m.triangles.size() << "\nproperty list uchar int vertex_indices\n";
  if (labels) os << "property int label_a\nproperty int label_b\n";
  os << "end_header\n";
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const auto& v = m.vertices[i];
    float f[10] = {float(v.x()), float(v.y()), float(v.z())};
    size_t n = 3;
    if (normals)
      for (int c = 0; c < 3; ++c) f[n++] = m.normals[i][c];
    if (curvature)
      for (float k : m.curvature[i]) f[n++] = k;
    os.write(reinterpret_cast<const char*>(f), std::streamsize(n * sizeof(float)));
  }
  for (size_t f = 0; f < m.triangles.size(); ++f) {
    const auto& t = m.triangles[f];
    char rec[21];
    rec[0] = 3;
    int32_t idx[5] = {int32_t(t[0]), int32_t(t[1]), int32_t(t[2]), 0, 0};
    if (labels) {
      idx[3] = m.face_labels[f][0];
      idx[4] = m.face_labels[f][1];
    }
    std::memcpy(rec + 1, idx, 20);
    os.write(rec, labels ? 21 : 13);
  }
}

// ---------------------------------------------------------------- STL
struct Vec3Hash {
  size_t operator()(const std::array<float, 3>& a) const {
    uint32_t h[3];
    std::memcpy(h, a.data(), 12);
    return (size_t(h[0]) * 73856093u) ^ (size_t(h[1]) * 19349663u) ^ (size_t(h[2]) * 83492791u);
  }
};

class Welder {
 public:
  explicit Welder(TriangleMesh& m) : m_(m) {}
  uint32_t add(std::array<float, 3> p) {
    auto [it, fresh] = map_.try_emplace(p, uint32_t(m_.vertices.size()));
    if (fresh) m_.vertices.emplace_back(p[0], p[1], p[2]);
    return it->second;
  }

 private:
  TriangleMesh& m_;
  std::unordered_map<std::array<float, 3>, uint32_t, Vec3Hash> map_;
};

TriangleMesh parse_stl(const std::string& b, const std::string& name) {
  TriangleMesh m;
  Welder weld(m);
  if (b.size() >= 84) {
    uint32_t n;
    std::memcpy(&n, b.data() + 80, 4);
    if (84 + uint64_t(n) * 50 == b.size()) {
      for (uint32_t t = 0; t < n; ++t) {
        const char* rec = b.data() + 84 + size_t(t) * 50 + 12;
        std::array<uint32_t, 3> tri;
        for (int c = 0; c < 3; ++c) {
          std::array<float, 3> p;
          std::memcpy(p.data(), rec + 12 * c, 12);
          tri[size_t(c)] = weld.add(p);
        }
        m.triangles.push_back(tri);
      }
      return m;
    }
  }
  if (b.compare(0, 5, "solid") != 0)
    throw InputError(name + ": not an STL file (binary size does not match its triangle count, "
                            "and it does not start with 'solid')");
  std::istringstream is(b);
  std::string w;
  std::vector<uint32_t> poly;
  while (is >> w) {
    if (w == "vertex") {
      std::array<float, 3> p;
      if (!(is >> p[0] >> p[1] >> p[2])) throw InputError(name + ": malformed STL vertex");
      poly.push_back(weld.add(p));
    } else if (w == "endloop") {
      if (poly.size() != 3) throw InputError(name + ": STL facet without exactly 3 vertices");
      m.triangles.push_back({poly[0], poly[1], poly[2]});
      poly.clear();
    }
  }
  return m;
}

void write_stl(const TriangleMesh& m, std::ostream& os) {
  char header[80] = "mpumesh binary STL, units mm";
  os.write(header, 80);
  uint32_t n = uint32_t(m.triangles.size());
  os.write(reinterpret_cast<const char*>(&n), 4);
  for (const auto& t : m.triangles) {
    const Eigen::Vector3d &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    Eigen::Vector3d nrm = (b - a).cross(c - a);
    double len = nrm.norm();
    if (len > 0) nrm /= len;
    float rec[12] = {float(nrm.x()), float(nrm.y()), float(nrm.z())};
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) rec[3 + 3 * k + d] = float(m.vertices[t[size_t(k)]][d]);
    os.write(reinterpret_cast<const char*>(rec), sizeof rec);
    uint16_t attr = 0;
    os.write(reinterpret_cast<const char*>(&attr), 2);
  }
}

// ---------------------------------------------------------------- OBJ / OFF
TriangleMesh parse_obj(const std::string& b, const std::string& name) {
  TriangleMesh m;
  std::istringstream is(b);
  std::string line;
  std::vector<int64_t> idx;
  while (std::getline(is, line)) {
    std::istringstream ls(line);
    std::string kw;
    ls >> kw;
    if (kw == "v") {
      Eigen::Vector3d v;
      if (!(ls >> v.x() >> v.y() >> v.z())) throw InputError(name + ": malformed OBJ vertex '" + line + "'");
      m.vertices.push_back(v);
    } else if (kw == "f") {
      idx.clear();
      std::string tok;
      while (ls >> tok) {
        long long i = 0;
        try {
          i = std::stoll(tok.substr(0, tok.find('/')));
        } catch (const std::exception&) {
          throw InputError(name + ": malformed OBJ face '" + line + "'");
        }
        idx.push_back(i < 0 ? int64_t(m.vertices.size()) + i : i - 1);
      }
      add_polygon(m, idx, name);
    }
  }
  return m;
}

TriangleMesh parse_off(const std::string& b, const std::string& name) {
  // Comments (#...) are dropped before tokenising.
  std::string clean;
  clean.reserve(b.size());
  bool comment = false;
  for (char c : b) {
    if (c == '#') comment = true;
    if (c == '\n') comment = false;
    if (!comment) clean += c;
  }
  std::istringstream is(clean);
  std::string magic;
  is >> magic;
  if (magic != "OFF") throw InputError(name + ": not an OFF file (no 'OFF' magic)");
  int64_t nv, nf, ne;
  if (!(is >> nv >> nf >> ne) || nv < 0 || nf < 0 || nv > int64_t(b.size()) || nf > int64_t(b.size()))
    throw InputError(name + ": bad OFF counts");
  TriangleMesh m;
  m.vertices.resize(size_t(nv));
  for (auto& v : m.vertices)
    if (!(is >> v.x() >> v.y() >> v.z())) throw InputError(name + ": truncated OFF vertices");
  std::vector<int64_t> idx;
  for (int64_t f = 0; f < nf; ++f) {
    int64_t k;
    if (!(is >> k) || k < 0 || k > 1000000) throw InputError(name + ": truncated or bad OFF face");
    idx.resize(size_t(k));
    for (auto& i : idx)
      if (!(is >> i)) throw InputError(name + ": truncated OFF face");
    std::string rest;
    std::getline(is, rest);  // optional colour
    add_polygon(m, idx, name);
  }
  return m;
}

void write_obj(const TriangleMesh& m, std::ostream& os) {
  os << "# mpumesh, units mm\n";
  os.precision(9);
  for (const auto& v : m.vertices) os << "v " << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& t : m.triangles) os << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
}

void write_off(const TriangleMesh& m, std::ostream& os) {
  os << "OFF\n" << m.vertices.size() << ' ' << m.triangles.size() << " 0\n";
  os.precision(9);
  for (const auto& v : m.vertices) os << v.x() << ' ' << v.y() << ' ' << v.z() << '\n';
  for (const auto& t : m.triangles) os << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
}

}  // namespace

MeshFormat mesh_format_from_path(const std::string& path) {
  const std::string e = lower_extension(path);
  if (e == ".ply") return MeshFormat::kPly;
  if (e == ".stl") return MeshFormat::kStl;
  if (e == ".obj") return MeshFormat::kObj;
  if (e == ".off") return MeshFormat::kOff;
  throw InputError(path + ": unknown mesh format '" + e + "' (use .ply, .stl, .obj or .off)");
}

TriangleMesh parse_mesh(const std::string& bytes, MeshFormat format, const std::string& name) {
  if (bytes.empty()) throw InputError(name + ": file is empty");
  TriangleMesh m;
  switch (format) {
    case MeshFormat::kPly: m = detail::parse_ply(bytes, name, nullptr); break;
    case MeshFormat::kStl: m = parse_stl(bytes, name); break;
    case MeshFormat::kObj: m = parse_obj(bytes, name); break;
    case MeshFormat::kOff: m = parse_off(bytes, name); break;
  }
  check_finite(m, name);
  return m;
}

TriangleMesh read_mesh(const std::string& path) {
  const MeshFormat f = mesh_format_from_path(path);
  return parse_mesh(read_file(path), f, path);
}

void write_mesh(const TriangleMesh& mesh, const std::string& path) {
  const MeshFormat f = mesh_format_from_path(path);
  for (const auto& t : mesh.triangles)
    for (uint32_t i : t) MPUMESH_ASSERT(i < mesh.vertices.size(), "mesh index out of range");
  AtomicFile out(path);
  {
    std::ofstream os(out.temp_path(), std::ios::binary);
    if (!os) throw InputError(path + ": cannot open for writing");
    switch (f) {
      case MeshFormat::kPly: write_ply(mesh, os); break;
      case MeshFormat::kStl: write_stl(mesh, os); break;
      case MeshFormat::kObj: write_obj(mesh, os); break;
      case MeshFormat::kOff: write_off(mesh, os); break;
    }
    os.flush();
    if (!os) throw InputError(path + ": write failed (disk full?)");
  }
  out.commit();
}

}  // namespace mpumesh
