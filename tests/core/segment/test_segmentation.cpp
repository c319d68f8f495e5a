// Segmentation: the window, Chan-Vese's parameters, and threshold and Chan-Vese on noisy
// shell phantoms whose true surface is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "segment/segmentation.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(Window, MapsToIntegerGreyLevels) {
  Volume v;
  v.dims = {4, 1, 1};
  v.voxels = {-1000.0f, 100.0f, 800.0f, 3000.0f};
  const auto u = seg::window_image(v, {100, 1500});
  EXPECT_EQ(u[0], 0.0f);
  EXPECT_EQ(u[1], 0.0f);
  EXPECT_EQ(u[2], std::round(700.0f * 255.0f / 1400.0f));
  EXPECT_EQ(u[3], 255.0f);
  EXPECT_THROW(seg::parse_window("5:5"), InputError);
  EXPECT_THROW(seg::parse_window("abc"), InputError);
  EXPECT_EQ(seg::parse_window("-100:300").hi, 300.0);
}

TEST(ChanVese, RejectsBadParameters) {
  seg::ChanVeseParams p;
  p.dt = 0;
  EXPECT_THROW(seg::validate(p), InputError);
  p = {};
  p.lambda2 = std::nan("");
  EXPECT_THROW(seg::validate(p), InputError);
}

struct PhantomCase {
  const char* name;
  Eigen::Vector3d radii;
};

class SegmentPhantom : public ::testing::TestWithParam<PhantomCase> {};

TEST_P(SegmentPhantom, BoundaryWithinOnePixelAndNoSpecks) {
  CpuBackend cpu;
  test::ShellPhantom ph;
  ph.radii = GetParam().radii;
  seg::SegmentOptions opt;
  opt.threshold = {500};  // half the contrast of the outer edge: the partial-volume boundary
  {
    opt.method = seg::Method::kThreshold;
    const Volume clean = ph.volume();
    test::expect_boundary_within_one_pixel(ph, clean, seg::segment(clean, opt, cpu), "threshold, no noise");
  }
  ph.noise_hu = 60;
  const Volume vol = ph.volume();
  opt.method = seg::Method::kChanVese;
  const seg::Segmentation s = seg::segment(vol, opt, cpu);
  test::expect_boundary_within_one_pixel(ph, vol, s, "chan-vese, noise 60 HU");
  for (const auto& v : s.field.values) ASSERT_TRUE(std::isfinite(v));
  for (size_t k = 0; k < s.c1.size(); ++k) ASSERT_TRUE(std::isfinite(s.c1[k]) && std::isfinite(s.c2[k]));

  // Specks: the default threshold (226 HU, 3.8 sigma of the noise) leaves some in the
  // background; Chan-Vese, started from it, leaves one component.
  const seg::Segmentation d = seg::segment(vol, seg::SegmentOptions{}, cpu);
  std::printf("[ components ] threshold %lld, Chan-Vese %lld\n", (long long)d.threshold_components.count,
              (long long)d.components.count);
  EXPECT_GT(d.threshold_components.count, 5);
  EXPECT_EQ(d.components.count, 1);
}

INSTANTIATE_TEST_SUITE_P(Shapes, SegmentPhantom,
                         ::testing::Values(PhantomCase{"sphere", {20, 20, 20}}, PhantomCase{"ellipsoid", {24, 16, 12}}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Segment, NothingInsideIsAnError) {
  test::ShellPhantom ph;
  ph.radii = {5, 5, 5};
  const Volume vol = ph.volume();
  CpuBackend cpu;
  seg::SegmentOptions opt;
  opt.threshold = {5000};
  EXPECT_THROW(seg::segment(vol, opt, cpu), InputError);
}

}  // namespace
}  // namespace mpumesh
