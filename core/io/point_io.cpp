#include "io/point_io.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "io/atomic_file.h"
#include "io/read_file.h"
#include "geometry/triangle_mesh.h"

namespace mpumesh {
namespace detail {
TriangleMesh parse_ply(const std::string& b, const std::string& name, std::vector<Eigen::Vector3d>* normals);
}

namespace {

void finish(PointCloud& c, const std::string& name) {
  for (size_t i = 0; i < c.size(); ++i) {
    const double len = c.normals[i].norm();
    if (!c.positions[i].allFinite() || !std::isfinite(len) || len == 0)
      throw InputError(name + ": point " + std::to_string(i) + " has a non-finite position or a zero normal");
    c.normals[i] /= len;
  }
  if (c.size() == 0) throw InputError(name + ": no points");
}

// Calls fn(line number, line) for each line with data ('#' comments and blank lines
// dropped).
template <class F>
void for_each_data_line(const std::string& b, F&& fn) {
  std::istringstream in(b);
  std::string line;
  for (int64_t no = 1; std::getline(in, line); ++no) {
    const auto hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    fn(no, line);
  }
}

PointCloud parse_xyz(const std::string& b, const std::string& name) {
  PointCloud c;
  for_each_data_line(b, [&](int64_t no, const std::string& line) {
    std::istringstream ls(line);
    double v[6];
    for (double& x : v)
      if (!(ls >> x)) throw InputError(name + ": line " + std::to_string(no) + " is not 'x y z nx ny nz'");
    std::string rest;
    if (ls >> rest) throw InputError(name + ": line " + std::to_string(no) + " has more than six numbers");
    c.positions.emplace_back(v[0], v[1], v[2]);
    c.normals.emplace_back(v[3], v[4], v[5]);
  });
  return c;
}

}  // namespace

PointCloud parse_point_cloud(const std::string& bytes, const std::string& ext, const std::string& name) {
  if (bytes.empty()) throw InputError(name + ": file is empty");
  PointCloud c;
  if (ext == ".ply") {
    TriangleMesh m = detail::parse_ply(bytes, name, &c.normals);
    c.positions = std::move(m.vertices);
  } else if (ext == ".xyz") {
    c = parse_xyz(bytes, name);
  } else {
    throw InputError(name + ": unknown point-cloud format '" + ext + "' (use .ply or .xyz)");
  }
  finish(c, name);
  return c;
}

std::vector<Eigen::Vector3d> parse_positions(const std::string& b, const std::string& name) {
  std::vector<Eigen::Vector3d> out;
  for_each_data_line(b, [&](int64_t no, const std::string& line) {
    std::istringstream ls(line);
    Eigen::Vector3d p;
    if (!(ls >> p.x() >> p.y() >> p.z()) || !p.allFinite())
      throw InputError(name + ": line " + std::to_string(no) + " does not start with three finite numbers x y z");
    out.push_back(p);
  });
  if (out.empty()) throw InputError(name + ": no points");
  return out;
}

std::vector<Eigen::Vector3d> read_positions(const std::string& path) { return parse_positions(read_file(path), path); }

PointCloud read_point_cloud(const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".ply" && ext != ".xyz")
    throw InputError(path + ": unknown point-cloud format '" + ext + "' (use .ply or .xyz)");
  return parse_point_cloud(read_file(path), ext, path);
}

void write_point_cloud(const PointCloud& cloud, const std::string& path) {
  const std::string ext = lower_extension(path);
  if (ext != ".ply" && ext != ".xyz")
    throw InputError(path + ": unknown point-cloud format '" + ext + "' (use .ply or .xyz)");
  AtomicFile out(path);
  {
    std::ofstream os(out.temp_path(), std::ios::binary);
    if (!os) throw InputError(path + ": cannot open for writing");
    if (ext == ".ply") {
      os << "ply\nformat binary_little_endian 1.0\ncomment mpumesh oriented points, units mm\nelement vertex "
         << cloud.size()
         << "\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\n"
            "property float nz\nend_header\n";
      std::vector<float> buf(6 * cloud.size());
      for (size_t i = 0; i < cloud.size(); ++i)
        for (int d = 0; d < 3; ++d) {
          buf[6 * i + size_t(d)] = float(cloud.positions[i][d]);
          buf[6 * i + 3 + size_t(d)] = float(cloud.normals[i][d]);
        }
      os.write(reinterpret_cast<const char*>(buf.data()), std::streamsize(buf.size() * sizeof(float)));
    } else {
      char line[256];
      for (size_t i = 0; i < cloud.size(); ++i) {
        const auto& p = cloud.positions[i];
        const auto& n = cloud.normals[i];
        std::snprintf(line, sizeof line, "%.9g %.9g %.9g %.9g %.9g %.9g\n", p.x(), p.y(), p.z(), n.x(), n.y(), n.z());
        os << line;
      }
    }
    os.flush();
    if (!os) throw InputError(path + ": write failed (disk full?)");
  }
  out.commit();
}

}  // namespace mpumesh
