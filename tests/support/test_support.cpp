#include "test_support.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>

#include "cpu/cpu_backend.h"
#include "io/volume_io.h"
#include "mpu/mpu_fit.h"
#include "phantom/ct_phantom.h"
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

Volume label_volume(std::array<int64_t, 3> dims, Eigen::Vector3d spacing,
                    const std::function<float(const Eigen::Vector3d&)>& label) {
  Volume v;
  v.dims = dims;
  v.spacing = spacing;
  v.voxels.assign(size_t(v.voxel_count()), 0.0f);
  for (int64_t k = 0; k < v.dims[2]; ++k)
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i)
        v.voxels[size_t(v.index(i, j, k))] = label(v.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k))));
  return v;
}

Volume LabelPhantom::volume() const {
  Volume v = label_volume({84, 46, 22}, {0.8, 0.8, 1.6}, [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - centre;
    float x = 0;
    if (q.cwiseQuotient(radii).squaredNorm() <= 1) x = q.dot(cut_normal) < 0 ? 1.0f : 2.0f;
    if ((p - ball_centre).norm() <= ball_radius) x = 3.0f;
    const double r = (p - nest_centre).norm();
    if (r <= nest_radius) x = r <= core_radius ? 5.0f : 6.0f;
    return x;
  });
  v.voxels[size_t(v.index(55, 40, 3))] = v.voxels[size_t(v.index(56, 40, 3))] = 4.0f;
  v.source = "label phantom";
  return v;
}

Volume ShellPhantom::volume() const {
  Volume v;
  v.spacing = spacing;
  const Eigen::Vector3d lo = centre - radii - Eigen::Vector3d::Constant(margin_mm);
  const Eigen::Vector3d hi = centre + radii + Eigen::Vector3d::Constant(margin_mm);
  for (int d = 0; d < 3; ++d) v.dims[size_t(d)] = int64_t(std::ceil((hi[d] - lo[d]) / spacing[d])) + 1;
  // Offset by a fraction of a pixel so that the centre is not on a pixel centre.
  v.origin = lo + Eigen::Vector3d(0.37 * spacing.x(), 0.21 * spacing.y(), 0.43 * spacing.z());
  v.voxels.resize(size_t(v.voxel_count()));
  const Eigen::Vector3d inner = radii - Eigen::Vector3d::Constant(shell_mm);
  auto level = [&](const Eigen::Vector3d& p) {
    const Eigen::Vector3d q = p - centre;
    if (q.cwiseQuotient(radii).squaredNorm() > 1) return 0.0;
    return q.cwiseQuotient(inner).squaredNorm() > 1 ? shell_hu : interior_hu;
  };
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  constexpr int kSub = 4;
  for (int64_t k = 0; k < v.dims[2]; ++k)
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i) {
        double sum = 0;
        for (int b = 0; b < kSub; ++b)
          for (int a = 0; a < kSub; ++a) {
            const Eigen::Vector3d ijk(double(i) + (a + 0.5) / kSub - 0.5, double(j) + (b + 0.5) / kSub - 0.5, double(k));
            sum += level(v.index_to_physical(ijk));
          }
        v.voxels[size_t(v.index(i, j, k))] = float(sum / (kSub * kSub) + noise_hu * noise(rng));
      }
  v.source = "shell phantom";
  v.modality = "CT";
  return v;
}

bool ShellPhantom::inside(const Eigen::Vector3d& p) const {
  return (p - centre).cwiseQuotient(radii).squaredNorm() <= 1.0;
}

double ShellPhantom::distance(const Eigen::Vector3d& p, Eigen::Vector3d* normal) const {
  const phantom::Shape outer{phantom::Shape::kEllipsoid, radii.x(), radii.y(), radii.z(),
                             Eigen::Matrix3d::Identity(), centre};
  return outer.distance(p, normal);
}

double AnalyticShape::value(const Eigen::Vector3d& p) const {
  switch (kind) {
    case kSphere: return p.norm() - a;
    case kEllipsoid: return std::sqrt(std::pow(p.x() / a, 2) + std::pow(p.y() / b, 2) + std::pow(p.z() / c, 2)) - 1;
    case kTorus: return std::hypot(std::hypot(p.x(), p.y()) - a, p.z()) - b;
  }
  return 0;
}

Eigen::Vector3d AnalyticShape::gradient(const Eigen::Vector3d& p) const {
  const double h = 1e-6;
  Eigen::Vector3d g;
  for (int d = 0; d < 3; ++d) {
    Eigen::Vector3d e = Eigen::Vector3d::Zero();
    e[d] = h;
    g[d] = (value(p + e) - value(p - e)) / (2 * h);
  }
  return g;
}

Eigen::Vector3d AnalyticShape::half_extent() const {
  if (kind == kTorus) return {a + b, a + b, b};
  return {a, kind == kSphere ? a : b, kind == kSphere ? a : c};
}

double AnalyticShape::distance(const Eigen::Vector3d& p, Eigen::Vector3d* normal, double* gauss) const {
  if (kind == kSphere) {
    if (normal) *normal = p.normalized();
    if (gauss) *gauss = 1 / (a * a);
    return std::abs(p.norm() - a);
  }
  if (kind == kTorus) {
    const double rho = std::hypot(p.x(), p.y());
    const Eigen::Vector3d ring = rho > 0 ? Eigen::Vector3d(a * p.x() / rho, a * p.y() / rho, 0) : Eigen::Vector3d(a, 0, 0);
    const Eigen::Vector3d n = (p - ring).normalized();
    if (normal) *normal = n;
    const double cosv = n.head<2>().norm() * ((rho >= a) ? 1 : -1);
    if (gauss) *gauss = cosv / (b * (a + b * cosv));
    return std::abs((p - ring).norm() - b);
  }
  ShellPhantom e;
  e.radii = {a, b, c};
  Eigen::Vector3d n;
  const double d = e.distance(p, &n);
  if (normal) *normal = n;
  if (gauss) {
    // The closest point x, from the normal: n ∝ x / e², so x = e² n / |e n|... solved
    // through the distance: x = p - d * n (outside) or p + d * n (inside).
    const Eigen::Vector3d x = value(p) > 0 ? Eigen::Vector3d(p - d * n) : Eigen::Vector3d(p + d * n);
    const double s = std::pow(x.x() / (a * a * a * a) * x.x() + x.y() * x.y() / (b * b * b * b) +
                                  x.z() * x.z() / (c * c * c * c),
                              2);
    *gauss = 1 / (a * a * b * b * c * c * s);
  }
  return d;
}

PointCloud spherical_shell(double r_outer, double r_inner) {
  PointCloud shell =
      sample_shape(AnalyticShape{AnalyticShape::kSphere, r_outer, r_outer, r_outer}, 0.5, 0.5, true);
  const PointCloud inner =
      sample_shape(AnalyticShape{AnalyticShape::kSphere, r_inner, r_inner, r_inner}, 0.5, 0.5, true);
  for (size_t i = 0; i < inner.size(); ++i) {
    shell.positions.push_back(inner.positions[i]);
    shell.normals.push_back(-inner.normals[i]);
  }
  return shell;
}

PointCloud sample_shape(const AnalyticShape& s, double hxy, double hz, bool dense) {
  PointCloud out;
  const Eigen::Vector3d ext = s.half_extent() + Eigen::Vector3d::Constant(2 * std::max(hxy, hz));
  const Eigen::Vector3d h(hxy, hxy, hz);
  // Offsets keep grid lines off the shapes' symmetry planes.
  const Eigen::Vector3d o(0.137 * hxy, 0.291 * hxy, 0.373 * hz);
  std::array<int64_t, 3> n;
  for (int d = 0; d < 3; ++d) n[size_t(d)] = int64_t(std::ceil(2 * ext[d] / h[d])) + 1;
  auto at = [&](int64_t i, int64_t j, int64_t k) {
    return Eigen::Vector3d(-ext.x() + o.x() + double(i) * h.x(), -ext.y() + o.y() + double(j) * h.y(),
                           -ext.z() + o.z() + double(k) * h.z());
  };
  // cap_only: keep the root only where the surface is within 45° of the slice plane, as
  // the points stage adds caps (core/points/slice_points.h).
  auto root = [&](Eigen::Vector3d a, Eigen::Vector3d b, bool cap_only) {
    double fa = s.value(a);
    for (int it = 0; it < 60; ++it) {
      const Eigen::Vector3d m = 0.5 * (a + b);
      const double fm = s.value(m);
      if ((fm < 0) == (fa < 0)) {
        a = m;
        fa = fm;
      } else {
        b = m;
      }
    }
    const Eigen::Vector3d p = 0.5 * (a + b);
    const Eigen::Vector3d nrm = s.gradient(p).normalized();
    if (cap_only && std::abs(nrm.z()) < std::sqrt(0.5)) return;
    out.positions.push_back(p);
    out.normals.push_back(nrm);
  };
  for (int64_t k = 0; k < n[2]; ++k)
    for (int64_t j = 0; j < n[1]; ++j)
      for (int64_t i = 0; i < n[0]; ++i) {
        const Eigen::Vector3d p = at(i, j, k);
        const bool in = s.value(p) < 0;
        if (i + 1 < n[0] && (s.value(at(i + 1, j, k)) < 0) != in) root(p, at(i + 1, j, k), false);
        if (j + 1 < n[1] && (s.value(at(i, j + 1, k)) < 0) != in) root(p, at(i, j + 1, k), false);
        if (k + 1 < n[2] && (s.value(at(i, j, k + 1)) < 0) != in) root(p, at(i, j, k + 1), !dense);
      }
  return out;
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

Eigen::Vector3d fibonacci_direction(int k, int n) {
  const double z = 1 - (2 * k + 1.0) / n, r = std::sqrt(1 - z * z), phi = k * M_PI * (3 - std::sqrt(5.0));
  return {r * std::cos(phi), r * std::sin(phi), z};
}

ShapeRun run_shape(const AnalyticShape& shape, int64_t count, bool dense) {
  ShapeRun r;
  r.cloud = sample_shape(shape, 0.5, dense ? 0.5 : 2.0, dense);
  r.surface = mpu::fit_mpu(r.cloud, {});
  particles::SampleOptions o;
  o.particles = count;
  CpuBackend cpu;
  r.st = particles::sample_surface(r.surface, r.cloud.positions, o, cpu, &r.stats);
  std::vector<double> absk;
  for (size_t i = 0; i < r.st.size(); ++i) {
    double K;
    r.max_true_distance = std::max(r.max_true_distance, shape.distance(r.st.x[i], nullptr, &K));
    absk.push_back(std::abs(K));
  }
  r.spacing = particles::spacing_stats(particles::local_spacing(r.st.x), absk);
  return r;
}

void print_run(const char* name, const ShapeRun& r) {
  std::printf("%s: %lld particles (seeds %lld, pool %lld, births %lld, deaths %lld), %d iterations, converged %d, "
              "h %.3f mm, area %.0f mm2, thickness-bound %lld; spacing mean %.3f cv %.3f, high/low-K %.3f, rank %.3f; "
              "max distance %.2e mm; %.2f s seed, %.2f s iterate, %.2f s population\n",
              name, (long long)r.stats.particles, (long long)r.stats.seeds, (long long)r.stats.pool,
              (long long)r.stats.births, (long long)r.stats.deaths, r.stats.iterations, int(r.stats.converged),
              r.stats.spacing, r.stats.area, (long long)r.stats.thickness_bound, r.spacing.mean, r.spacing.cv,
              r.spacing.ratio, r.spacing.rank_correlation, r.max_true_distance, r.stats.seconds_seed,
              r.stats.seconds_iterate, r.stats.seconds_population);
  for (const auto& h : r.stats.history)
    std::printf("  it %d: %lld (+%lld -%lld) E %.2f move %.4f\n", h.iteration, (long long)h.count, (long long)h.births,
                (long long)h.deaths, h.mean_energy, h.mean_move);
}

void expect_boundary_within_one_pixel(const ShellPhantom& ph, const Volume& vol, const seg::Segmentation& s,
                                      const char* what) {
  int64_t wrong = 0, far = 0;
  double worst = 0;
  for (int64_t k = 0; k < vol.dims[2]; ++k)
    for (int64_t j = 0; j < vol.dims[1]; ++j)
      for (int64_t i = 0; i < vol.dims[0]; ++i) {
        const Eigen::Vector3d p = vol.index_to_physical(Eigen::Vector3d(double(i), double(j), double(k)));
        if (s.inside(i + 1, j + 1, k + 1) == ph.inside(p)) continue;
        ++wrong;
        const double d = ph.distance(p);
        worst = std::max(worst, d);
        if (d > vol.spacing.x()) ++far;
      }
  EXPECT_EQ(far, 0) << what << ": " << wrong << " pixels mislabelled, farthest " << worst << " mm from the surface";
  std::printf("[ %s ] %lld mislabelled pixels, farthest %.3f mm (pixel %.2f mm)\n", what, (long long)wrong, worst,
              vol.spacing.x());
}

std::string ball_phantom(const std::string& dir) {
  const std::string p = dir + "/ball.mha";
  write_volume(sphere_volume({30, 28, 12}, {0.6, 0.6, 2.0}, {9, 8, 12}, 6.0), p);
  return p;
}

pipeline::RunOptions ball_run_options() {
  pipeline::RunOptions o;  // the threshold alone: the threshold method
  o.segment.method = seg::Method::kThreshold;
  o.segment.threshold = {0};
  o.sample.particles = 1500;
  return o;
}

}  // namespace mpumesh::test
