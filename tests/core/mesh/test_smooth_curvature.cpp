// The curvature at a scale (mesh/surface_attributes.h smooth_curvature): a bumpy estimate
// on a sphere becomes the sphere's own, K and H follow from the mean principal
// curvatures, and the two faces of a shell thinner than the scale do not mix.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "mesh/surface_attributes.h"
#include "test_support.h"

namespace mpumesh {
namespace {

constexpr double kR = 15;  // mm

// A sphere's vertices with their outward normals and k1 = k2 = -1/r, each principal
// curvature off by up to `bump` of it, drawn at random for each vertex.
TriangleMesh bumpy_sphere(double bump) {
  TriangleMesh m = test::icosphere(kR, 4);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-bump, bump);
  for (const Eigen::Vector3d& v : m.vertices) {
    const double k = -1 / kR, b = u(rng);
    m.normals.push_back(v.normalized().cast<float>());
    m.curvature.push_back({float(k * (1 - b)), float(k * (1 + b)), float(k * k * (1 - b * b)), float(k)});
  }
  return m;
}

TEST(SmoothCurvature, BumpsAverageOutOnASphere) {
  TriangleMesh m = bumpy_sphere(0.3);
  double before = 0;
  for (const auto& c : m.curvature) before = std::max(before, std::abs(c[0] * kR + 1));
  ASSERT_GT(before, 0.25);
  smooth_curvature(m, 3.0);
  // The Gaussian's weights count as about 100 equal ones: the bumps' spread drops tenfold.
  for (const auto& c : m.curvature) {
    EXPECT_NEAR(c[0] * kR, -1, 0.1);
    EXPECT_NEAR(c[1] * kR, -1, 0.1);
    EXPECT_FLOAT_EQ(c[2], c[0] * c[1]);          // K of the means
    EXPECT_FLOAT_EQ(c[3], 0.5f * (c[0] + c[1]));  // H of the means
  }
}

TEST(SmoothCurvature, AShellsFacesStayApart) {
  // The outer sphere and, 1 mm inside it, the inner face (normals toward the centre,
  // concave from the shell: k = +1/(r - 1)), both within one scale of each other.
  TriangleMesh m = bumpy_sphere(0);
  const TriangleMesh outer = m;
  const uint32_t n = uint32_t(outer.vertices.size());
  const double inner_k = 1 / (kR - 1);
  for (size_t i = 0; i < n; ++i) {
    m.vertices.push_back(outer.vertices[i] * (kR - 1) / kR);
    m.normals.push_back(-outer.normals[i]);
    m.curvature.push_back({float(inner_k), float(inner_k), float(inner_k * inner_k), float(inner_k)});
  }
  for (const auto& t : outer.triangles) m.triangles.push_back({t[0] + n, t[2] + n, t[1] + n});
  smooth_curvature(m, 3.0);
  for (size_t i = 0; i < m.vertices.size(); ++i) {
    const double h = i < n ? -1 / kR : inner_k;
    EXPECT_NEAR(m.curvature[i][3], h, 1e-6) << i;
  }
}

}  // namespace
}  // namespace mpumesh
