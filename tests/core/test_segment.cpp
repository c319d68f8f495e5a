// Segmentation: the distance transform and component count against brute force, and
// threshold and Chan-Vese on noisy shell phantoms whose true surface is known.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "segment/components.h"
#include "segment/distance_transform.h"
#include "segment/label_map.h"
#include "segment/segmentation.h"
#include "test_support.h"

namespace mpumesh {
namespace {

TEST(DistanceTransform, MatchesBruteForceWithAnisotropicPixels) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 20; ++trial) {
    const int64_t nx = 5 + int64_t(rng() % 30), ny = 5 + int64_t(rng() % 30);
    const double wx = 0.3 + (rng() % 100) / 50.0, wy = 0.3 + (rng() % 100) / 50.0;
    std::vector<uint8_t> m(size_t(nx * ny));
    for (auto& v : m) v = rng() % 10 == 0;
    for (const uint8_t target : {1, 0}) {  // sparse targets (rows without one), and dense
      const auto d2 = seg::squared_distance_2d(m.data(), nx, ny, target, wx, wy);
      for (int64_t j = 0; j < ny; ++j)
        for (int64_t i = 0; i < nx; ++i) {
          double best = INFINITY;
          for (int64_t b = 0; b < ny; ++b)
            for (int64_t a = 0; a < nx; ++a)
              if (m[size_t(a + nx * b)] == target)
                best = std::min(best, std::pow(wx * (a - i), 2) + std::pow(wy * (b - j), 2));
          ASSERT_NEAR(d2[size_t(i + nx * j)], best, 1e-4 * (1 + best)) << "trial " << trial;
        }
    }
  }
  std::vector<uint8_t> empty(16, 0);
  EXPECT_TRUE(std::isinf(seg::squared_distance_2d(empty.data(), 4, 4, 1)[5]));
}

TEST(Components, CountsFaceConnectedRegions) {
  // Two voxels touching only along an edge are two components (6-connectivity).
  std::vector<uint8_t> m(27, 0);
  m[0] = 1;                  // (0,0,0)
  m[1 + 3 * 1] = 1;          // (1,1,0): edge-adjacent to (0,0,0)
  m[2 + 3 * (2 + 3 * 2)] = 1;  // (2,2,2)
  m[2 + 3 * (2 + 3 * 1)] = 1;  // (2,2,1): face-adjacent to (2,2,2)
  const auto c = seg::mask_components(m, {3, 3, 3});
  EXPECT_EQ(c.count, 3);
  EXPECT_EQ(c.sizes.front(), 2);
}

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

// Every pixel the segmentation labels differently from the truth lies within one in-plane
// pixel of the true surface.
void expect_boundary_within_one_pixel(const test::ShellPhantom& ph, const Volume& vol, const seg::Segmentation& s,
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
    expect_boundary_within_one_pixel(ph, clean, seg::segment(clean, opt, cpu), "threshold, no noise");
  }
  ph.noise_hu = 60;
  const Volume vol = ph.volume();
  opt.method = seg::Method::kChanVese;
  const seg::Segmentation s = seg::segment(vol, opt, cpu);
  expect_boundary_within_one_pixel(ph, vol, s, "chan-vese, noise 60 HU");
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

namespace mpumesh {
namespace {

TEST(LabelMap, TheIndicatorIsOneOnTheLabelZeroOnTheBackgroundMinusOneOnOtherLabels) {
  Volume v;
  v.dims = {12, 1, 1};
  v.voxels = {0, 3, 7, 3, 7, 7, 7, 7, 7, 7, 7, 0};
  v.source = "map.nii";
  const Volume ind = seg::label_indicator(v, 7);
  EXPECT_EQ(ind.voxels, (std::vector<float>{0, -1, 1, -1, 1, 1, 1, 1, 1, 1, 1, 0}));
  EXPECT_EQ(ind.source, "map.nii (label 7)");
  EXPECT_THROW(
      {
        try {
          seg::label_indicator(v, 5);
        } catch (const InputError& e) {
          EXPECT_STREQ(e.what(), "map.nii (label 5): no voxel holds this label");
          throw;
        }
      },
      InputError);
  try {
    seg::label_indicator(v, 3);
    ADD_FAILURE() << "2 voxels are too few";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "map.nii (label 3): 2 voxels, too small to mesh (a label needs at least 8)");
  }
}

TEST(LabelMap, CountsTheLabelsAndRefusesWhatIsNoLabelMap) {
  Volume v;
  v.dims = {5, 1, 1};
  v.voxels = {0, 3, 7, 3, 0};
  v.source = "map.nii";
  EXPECT_EQ(seg::label_voxel_counts(v), (std::map<int64_t, int64_t>{{3, 2}, {7, 1}}));
  v.voxels[1] = 2.5f;
  EXPECT_THROW(seg::label_voxel_counts(v), InputError);
  v.dims = {int64_t(seg::kMaxLabels) + 1, 1, 1};
  v.voxels.resize(size_t(v.dims[0]));
  for (size_t i = 0; i < v.voxels.size(); ++i) v.voxels[i] = float(i + 1);
  EXPECT_THROW(seg::label_voxel_counts(v), InputError);
}

TEST(LabelMap, ParsesAllOrAListOfLabels) {
  EXPECT_TRUE(seg::parse_label_list("all").empty());
  EXPECT_EQ(seg::parse_label_list("3,7,12"), (std::vector<int64_t>{3, 7, 12}));
  for (const char* bad : {"", "0", "-2", "3,", "3,,4", "x", "3.5", "3,3"})
    EXPECT_THROW(seg::parse_label_list(bad), InputError) << bad;
}

}  // namespace
}  // namespace mpumesh
