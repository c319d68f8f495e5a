// The particle shaders (particle_step_grid_*.comp, particle_step_repulsion.comp,
// particle_step_project.comp; float32) against the double-precision CPU reference
// (core/particles/particle_step_ref.cpp), with validation on: one step from the same
// state (positions, σ, energies, curvature, and the fission/death decisions made from
// each), and whole runs on both backends (count within 2%, spacing statistics within 5%).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "mpu/mpu_fit.h"
#include "mesh/restricted_delaunay.h"
#include "mesh/topology.h"
#include "mpu/mpu_eval_ref.h"
#include "particles/particle_system.h"
#include "particles/spacing_stats.h"
#include "backends.h"
#include "error_stats.h"
#include "test_support.h"

namespace mpumesh {
namespace {

using particles::ParticleState;

struct Fitted {
  test::AnalyticShape shape;
  PointCloud cloud;
  mpu::MpuSurface surface;
};

Fitted fitted_ellipsoid() {
  Fitted f;
  f.shape = test::AnalyticShape{test::AnalyticShape::kEllipsoid, 30, 20, 10};
  f.cloud = test::sample_shape(f.shape, 0.5, 0.5, true);
  f.surface = mpu::fit_mpu(f.cloud, {});
  return f;
}

// A state mid-run: `count` particles seeded and iterated `iterations` times on the CPU,
// with the options that made it and the step parameters of its next batch.
struct Seeded {
  particles::SampleOptions o;
  ParticleState start;
  particles::StepParams p;
};
Seeded seeded_on_cpu(const Fitted& f, int64_t count, int iterations) {
  CpuBackend cpu;
  Seeded s;
  s.o.particles = count;
  s.o.iterations = iterations;
  s.start = particles::sample_surface(f.surface, f.cloud.positions, s.o, cpu);
  s.p = particles::batch_params(s.o.step, s.start);
  return s;
}

// A surface that turns to NaN after seeding (a broken kernel or fit): both backends mark
// the NaN evaluations and the finiteness check reports them with the iteration, instead of
// treating the particles as merely lost.
TEST(ParticlesVk, NanEvaluationIsReportedOnBothBackends) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Fitted f = fitted_ellipsoid();
  CpuBackend cpu;
  const auto [o, start, p] = seeded_on_cpu(f, 1500, 5);
  mpu::MpuSurface broken = f.surface;
  for (auto& leaf : broken.leaves)
    if (leaf.centre.x() > 20) leaf.coeffs.fill(std::numeric_limits<double>::quiet_NaN());
  for (ComputeBackend* b : {static_cast<ComputeBackend*>(&cpu), static_cast<ComputeBackend*>(gpu.get())}) {
    ParticleState st = start;
    b->particle_iterations(broken, st, p, 5);
    EXPECT_THROW(particles::check_finite(st, 10, b->device()), NumericalError) << b->device();
    st = start;
    b->particle_iterations(f.surface, st, p, 5);
    EXPECT_NO_THROW(particles::check_finite(st, 10, b->device())) << b->device();
  }
  test::expect_no_validation_messages(*gpu);
}

TEST(ParticlesVk, OneStepMatchesTheReference) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Fitted f = fitted_ellipsoid();
  CpuBackend cpu;
  // A state mid-run: seeded and iterated a little on the CPU, with its targets.
  const auto [o, start, p] = seeded_on_cpu(f, 3000, 10);
  ParticleState a = start, b = start;
  cpu.particle_iterations(f.surface, a, p, 1);
  gpu->particle_iterations(f.surface, b, p, 1);
  test::expect_no_validation_messages(*gpu);
  test::ErrorStats dx, dsigma, denergy, dnormal, dgauss;  // dx in sigmas, dE in E^
  for (size_t i = 0; i < a.size(); ++i) {
    dx.add_error((a.x[i] - b.x[i]).norm() / a.sigma[i]);
    dsigma.add(b.sigma[i], a.sigma[i], 0);
    denergy.add_error(std::abs(a.energy[i] - b.energy[i]) / o.step.desired_energy);
    dnormal.add_error((a.normal[i] - b.normal[i]).norm());
    dgauss.add(b.curv[i].gauss, a.curv[i].gauss, 1e-4);
  }
  std::printf("one step, %zu particles: %s; %s; %s; %s; %s\n", a.size(), dx.line("x / sigma").c_str(),
              dsigma.line("sigma").c_str(), denergy.line("E / E^").c_str(), dnormal.line("normal").c_str(),
              dgauss.line("K").c_str());
  EXPECT_LT(dx.max_abs, 1e-4);
  EXPECT_LT(dsigma.max_rel, 1e-4);
  EXPECT_LT(denergy.max_abs, 1e-4);
  EXPECT_LT(dnormal.max_abs, 1e-4);
  EXPECT_LT(dgauss.max_rel, 1e-3);
  // The population step decides from either state alike.
  const auto fa = particles::decide_population(a, o, 10, 1 << 20), fb = particles::decide_population(b, o, 10, 1 << 20);
  int64_t changes = 0, differ = 0;
  for (size_t i = 0; i < fa.size(); ++i) {
    changes += fa[i] != particles::kKeep;
    differ += fa[i] != fb[i];
  }
  std::printf("decisions: %lld splits or deaths, %lld differ\n", (long long)changes, (long long)differ);
  EXPECT_EQ(differ, 0);
}

// The seeding's projection (particle_step_project.comp alone, 8 Newton steps, with the
// curvature) from points 0.4 mm off the surface, against project_step.
TEST(ParticlesVk, ProjectionMatchesTheReference) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Fitted f = fitted_ellipsoid();
  CpuBackend cpu;
  ParticleState a;
  for (size_t i = 0; i < f.cloud.size(); i += 17) {
    a.x.push_back(f.cloud.positions[i] + 0.4 * f.cloud.normals[i] * (i % 2 ? 1.0 : -1.0));
    a.sigma.push_back(1.0);
  }
  a.resize(a.x.size());
  ParticleState b = a;
  particles::StepParams p;
  p.newton_steps = 8;
  cpu.particle_project(f.surface, a, p, true);
  gpu->particle_project(f.surface, b, p, true);
  test::expect_no_validation_messages(*gpu);
  test::ErrorStats dx, dd, dn, dK;
  double truth = 0;
  for (size_t i = 0; i < a.size(); ++i) {
    dx.add_error((a.x[i] - b.x[i]).norm());
    dd.add(b.distance[i], a.distance[i]);
    dn.add_error((a.normal[i] - b.normal[i]).norm());
    dK.add(b.curv[i].gauss, a.curv[i].gauss, 1e-4);
    truth = std::max(truth, std::abs(f.shape.distance(a.x[i])));
  }
  std::printf("projection, %zu points: %s mm; %s mm; %s; %s; CPU result within %.2e mm of the true surface\n",
              a.size(), dx.line("x").c_str(), dd.line("distance").c_str(), dn.line("normal").c_str(),
              dK.line("K").c_str(), truth);
  EXPECT_LT(truth, 0.01);
  EXPECT_LT(dx.max_abs, 1e-3);
  EXPECT_LT(dd.max_abs, 1e-3);
  EXPECT_LT(dn.max_abs, 1e-4);
  EXPECT_LT(dK.max_rel, 1e-3);
}

// The local thickness (particle_step_thickness.comp against local_thickness) across a spherical
// shell 1.5 mm thick, from both its sheets, searched up to 4 mm: bisection toward f = 0 in
// float and in double may go either way where f is within float's error of 0 at a
// sample, after which both narrow onto the same crossing, so they agree to within two of
// the last brackets (4 mm / 4 / 32 each); and within 0.1 mm of the truth. Particles with
// no reach (lost) get infinity on both.
TEST(ParticlesVk, ThicknessMatchesTheReference) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const PointCloud shell = test::spherical_shell(20, 18.5);
  const mpu::MpuSurface s = mpu::fit_mpu(shell, {});
  CpuBackend cpu;
  std::vector<Eigen::Vector3d> x, n;
  std::vector<double> reach;
  for (size_t i = 0; i < shell.size(); i += 11) {
    x.push_back(shell.positions[i]);
    n.push_back(mpu::evaluate_fg(s, shell.positions[i]).g.normalized());
    reach.push_back(x.size() % 50 == 0 ? NAN : 4.0);
  }
  const std::vector<double> tc = cpu.thickness(s, x, n, reach), tg = gpu->thickness(s, x, n, reach);
  test::expect_no_validation_messages(*gpu);
  ASSERT_EQ(tc.size(), x.size());
  ASSERT_EQ(tg.size(), x.size());
  double diff = 0, err = 0;
  int64_t lost = 0, mismatched = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::isnan(reach[i])) {
      ++lost;
      mismatched += !(std::isinf(tc[i]) && std::isinf(tg[i]));
      continue;
    }
    mismatched += std::isfinite(tc[i]) != std::isfinite(tg[i]);
    diff = std::max(diff, std::abs(tc[i] - tg[i]));
    err = std::max(err, std::abs(tc[i] - 1.5));
  }
  std::printf("thickness, %zu points (%lld without reach): max |CPU - GPU| %.4f mm, max |CPU - 1.5| %.4f mm\n",
              x.size(), (long long)lost, diff, err);
  EXPECT_EQ(mismatched, 0);
  EXPECT_LE(diff, 2 * 4.0 / 4 / 32);
  EXPECT_LE(err, 0.1);
}

TEST(ParticlesVk, WholeRunMatchesTheReference) {
  MPUMESH_VULKAN_OR_SKIP(gpu);
  const Fitted f = fitted_ellipsoid();
  CpuBackend cpu;
  particles::SampleOptions o;
  o.particles = 3000;
  particles::SampleStats sa, sb;
  const ParticleState a = particles::sample_surface(f.surface, f.cloud.positions, o, cpu, &sa);
  const ParticleState b = particles::sample_surface(f.surface, f.cloud.positions, o, *gpu, &sb);
  test::expect_no_validation_messages(*gpu);
  auto stats = [&](const ParticleState& st) {
    std::vector<double> absk;
    for (const auto& x : st.x) {
      double K;
      f.shape.distance(x, nullptr, &K);
      absk.push_back(std::abs(K));
    }
    return particles::spacing_stats(particles::local_spacing(st.x), absk);
  };
  const auto ka = stats(a), kb = stats(b);
  std::printf("cpu: %zu particles, %d iterations, spacing mean %.4f cv %.4f high/low %.4f rank %.4f\n", a.size(),
              sa.iterations, ka.mean, ka.cv, ka.ratio, ka.rank_correlation);
  std::printf("gpu: %zu particles, %d iterations, spacing mean %.4f cv %.4f high/low %.4f rank %.4f\n", b.size(),
              sb.iterations, kb.mean, kb.cv, kb.ratio, kb.rank_correlation);
  EXPECT_NEAR(double(b.size()) / double(a.size()), 1.0, 0.02);
  EXPECT_NEAR(kb.mean / ka.mean, 1.0, 0.05);
  EXPECT_NEAR(kb.cv / ka.cv, 1.0, 0.05);
  EXPECT_NEAR(kb.ratio / ka.ratio, 1.0, 0.05);
  EXPECT_NEAR(kb.rank_correlation / ka.rank_correlation, 1.0, 0.05);
  // The GPU's particles triangulated with f at the Voronoi vertices from the GPU, and from
  // the CPU: both closed oriented manifolds, nearly the same mesh (a vertex within float's
  // error of f = 0 may change sides).
  RestrictedDelaunayStats ra, rb;
  const TriangleMesh ma = restricted_delaunay(f.surface, b.x, &ra), mb = restricted_delaunay(f.surface, b.x, &rb, 0, gpu.get());
  test::expect_no_validation_messages(*gpu);
  const Topology ta = analyze_topology(ma), tb = analyze_topology(mb);
  std::printf("triangulation of the gpu's particles, f on the cpu: %zu triangles; on the gpu: %zu triangles\n",
              ma.triangles.size(), mb.triangles.size());
  EXPECT_TRUE(tb.closed && tb.oriented);
  EXPECT_EQ(tb.components, ta.components);
  EXPECT_NEAR(double(mb.triangles.size()) / double(ma.triangles.size()), 1.0, 0.001);
}

// One body on both backends against the truth: particles on a fitted sphere lie on the
// true surface, as many as asked (within 10%), evenly spaced (cv under 0.15).
class ParticleBackends : public test::BackendTest {};

TEST_P(ParticleBackends, SpreadEvenlyOverTheFittedSphere) {
  MPUMESH_BACKEND_OR_SKIP(backend);
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 20, 20, 20};
  const PointCloud cloud = test::sample_shape(sphere, 0.5, 0.5, true);
  const mpu::MpuSurface s = mpu::fit_mpu(cloud, {});
  particles::SampleOptions o;
  o.particles = 3000;
  const ParticleState st = particles::sample_surface(s, cloud.positions, o, backend);
  test::ErrorStats off;
  for (const auto& x : st.x) off.add_error(sphere.distance(x));
  const std::vector<double> spacing = particles::local_spacing(st.x);
  const particles::SpacingStats k = particles::spacing_stats(spacing, std::vector<double>(spacing.size(), 1.0));
  std::printf("[ %s ] %zu particles, spacing mean %.3f mm cv %.3f; %s mm\n", GetParam().c_str(), st.size(), k.mean,
              k.cv, off.line("off the sphere").c_str());
  EXPECT_NEAR(double(st.size()), 3000, 300);
  EXPECT_LT(k.cv, 0.15);
  EXPECT_LT(off.max_abs, 0.01);
}
MPUMESH_INSTANTIATE_BACKENDS(ParticleBackends);

}  // namespace
}  // namespace mpumesh
