#include "test_support.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>

#include "vk/vk_check.h"

namespace mpumesh::test {

bool env_flag(const char* name) {
  const char* v = std::getenv(name);
  return v && *v && std::string(v) != "0";
}

std::unique_ptr<vk::VulkanBackend> try_vulkan(std::string& why) {
  vk::ContextOptions opt;
  opt.validation = true;
  try {
    return std::make_unique<vk::VulkanBackend>(opt);
  } catch (const vk::NoVulkanDevice& e) {
    why = std::string("no Vulkan device: ") + e.what();
  }
  return nullptr;
}

void expect_no_validation_messages(vk::VulkanBackend& b) {
  ASSERT_TRUE(b.context().validation_enabled());
  const auto msgs = b.context().validation_messages();
  EXPECT_TRUE(msgs.empty()) << msgs.size() << " validation message(s), first: " << (msgs.empty() ? "" : msgs[0]);
}

Volume sphere_volume(std::array<int64_t, 3> dims, Eigen::Vector3d spacing, Eigen::Vector3d centre, double r) {
  Volume v;
  v.dims = dims;
  v.spacing = spacing;
  v.voxels.resize(size_t(v.voxel_count()));
  const double h = spacing.minCoeff();
  for (int64_t k = 0; k < dims[2]; ++k)
    for (int64_t j = 0; j < dims[1]; ++j)
      for (int64_t i = 0; i < dims[0]; ++i) {
        const Eigen::Vector3d p = v.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k)));
        const double d = (r - (p - centre).norm()) / h;  // signed distance in voxels, > 0 inside
        v.voxels[size_t(v.index(i, j, k))] = float(1000.0 * std::clamp(d, -1.0, 1.0));
      }
  v.source = "sphere phantom";
  return v;
}

Volume random_volume(std::array<int64_t, 3> dims, double fill, uint32_t seed) {
  Volume v;
  v.dims = dims;
  v.voxels.resize(size_t(v.voxel_count()));
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
  for (auto& x : v.voxels) x = u(rng) < fill ? float(50 + 100 * u(rng)) : float(-50 - 100 * u(rng));
  v.source = "random phantom";
  return v;
}

TriangleMesh icosahedron(double edge) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0, s = edge / 2.0;
  TriangleMesh m;
  m.vertices = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  for (auto& v : m.vertices) v *= s;
  m.triangles = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  return m;
}

TriangleMesh unit_cube() {
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) m.vertices.emplace_back(k & 1, (k >> 1) & 1, (k >> 2) & 1);
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return m;
}

TriangleMesh icosphere(double r, int subdivisions) {
  TriangleMesh m = icosahedron(2.0);
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      m.vertices.push_back(0.5 * (m.vertices[a] + m.vertices[b]));
      return mid[key] = uint32_t(m.vertices.size() - 1);
    };
    std::vector<std::array<uint32_t, 3>> next;
    for (const auto& t : m.triangles) {
      uint32_t a = midpoint(t[0], t[1]), b = midpoint(t[1], t[2]), c = midpoint(t[2], t[0]);
      next.push_back({t[0], a, c});
      next.push_back({t[1], b, a});
      next.push_back({t[2], c, b});
      next.push_back({a, b, c});
    }
    m.triangles = next;
  }
  for (auto& v : m.vertices) v = r * v.normalized();
  return m;
}

std::string sample_ct_path() {
  const char* env = std::getenv("MPUMESH_SAMPLE_CT");
  const std::string path = env && *env ? env : "/usr/share/doc/invesalius-examples/examples/Cranium.inv3";
  if (std::filesystem::exists(path)) return path;
  return "";
}

std::string pydicom_file(const std::string& name) {
  const std::string p = "/usr/lib/python3/dist-packages/pydicom/data/test_files/" + name;
  return std::filesystem::exists(p) ? p : "";
}

std::string temp_dir(const std::string& name) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::filesystem::path p = std::filesystem::temp_directory_path() / "mpumesh-tests" /
                            (std::string(info ? info->name() : "x") + "-" + name);
  std::filesystem::remove_all(p);
  std::filesystem::create_directories(p);
  return p.string();
}

}  // namespace mpumesh::test
