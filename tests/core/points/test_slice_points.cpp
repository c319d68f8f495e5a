// Oriented points: the whole point stage on noisy shell phantoms (true surface and normals
// known), cap heights on a CT-like phantom, and point-cloud files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "io/point_io.h"
#include "phantom/ct_phantom.h"
#include "points/slice_points.h"
#include "segment/label_map.h"
#include "segment/segmentation.h"
#include "test_support.h"

namespace mpumesh {
namespace {

struct Errors {
  double p95_position_px = 0, p95_normal_deg = 0, worst_cap_mm = 0;
  int64_t flipped = 0, caps_up = 0, caps_down = 0, contour_points = 0;
};

Errors measure(const test::ShellPhantom& ph, const pts::SlicePoints& p, double pixel) {
  Errors e;
  std::vector<double> pos, ang;
  for (size_t i = 0; i < p.cloud.size(); ++i) {
    Eigen::Vector3d n;
    const double d = ph.distance(p.cloud.positions[i], &n);
    const double cosang = std::clamp(p.cloud.normals[i].dot(n), -1.0, 1.0);
    if (cosang < 0) ++e.flipped;
    ang.push_back(std::acos(cosang) * 180 / M_PI);
    if (p.is_cap[i]) {
      e.worst_cap_mm = std::max(e.worst_cap_mm, d);
      (p.cloud.normals[i].z() > 0 ? e.caps_up : e.caps_down) += (p.cloud.positions[i] - ph.centre).z() * p.cloud.normals[i].z() > 0;
    } else {
      pos.push_back(d / pixel);
    }
  }
  e.contour_points = int64_t(pos.size());
  auto p95 = [](std::vector<double>& v) {
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[size_t(0.95 * double(v.size() - 1))];
  };
  e.p95_position_px = p95(pos);
  e.p95_normal_deg = p95(ang);
  return e;
}

struct PhantomCase {
  const char* name;
  Eigen::Vector3d radii;
};
class PointsPhantom : public ::testing::TestWithParam<PhantomCase> {};

TEST_P(PointsPhantom, PositionsNormalsAndCaps) {
  test::ShellPhantom ph;
  ph.radii = GetParam().radii;
  CpuBackend cpu;
  // The threshold on the clean phantom; Chan-Vese on the noisy one (a plain threshold
  // leaves noise holes in the interior, whose contours face inward).
  for (auto method : {seg::Method::kThreshold, seg::Method::kChanVese}) {
    ph.noise_hu = method == seg::Method::kThreshold ? 0 : 60;
    const Volume vol = ph.volume();
    seg::SegmentOptions opt;
    opt.method = method;
    opt.threshold = {500};
    const seg::Segmentation s = seg::segment(vol, opt, cpu);
    const pts::SlicePoints p = pts::extract_points(s, vol);
    const Errors e = measure(ph, p, vol.spacing.x());
    std::printf(
        "[ %s ] %zu points (%lld contour, %lld cap), p95 position %.3f px, p95 normal %.2f deg, %lld flipped, caps "
        "up/down %lld/%lld, worst cap %.3f mm, %lld degenerate\n",
        seg::method_name(method), p.cloud.size(), (long long)p.stats.contour_points, (long long)p.stats.cap_points,
        e.p95_position_px, e.p95_normal_deg, (long long)e.flipped, (long long)e.caps_up, (long long)e.caps_down,
        e.worst_cap_mm, (long long)p.stats.degenerate_normals);
    EXPECT_LE(e.p95_position_px, 0.25) << seg::method_name(method);
    EXPECT_LE(e.p95_normal_deg, 10.0) << seg::method_name(method);
    EXPECT_EQ(e.flipped, 0) << seg::method_name(method);
    // Caps at both poles, facing away from the centre, no farther than half a slice
    // spacing (plus a pixel) from the surface.
    EXPECT_GT(e.caps_up, 10);
    EXPECT_GT(e.caps_down, 10);
    EXPECT_LE(e.worst_cap_mm, 0.5 * vol.spacing.z() + vol.spacing.x());
    EXPECT_EQ(p.stats.cap_points, e.caps_up + e.caps_down) << "a cap faces the centre";
  }
}

INSTANTIATE_TEST_SUITE_P(Shapes, PointsPhantom,
                         ::testing::Values(PhantomCase{"sphere", {20, 20, 20}}, PhantomCase{"ellipsoid", {24, 16, 12}}),
                         [](const auto& info) { return std::string(info.param.name); });

TEST(Points, CapHeightsFollowThePartialVolume) {
  // The suite's capsule: 12 mm hemispherical caps, tilted, in 2.5 mm slices of 0.7 mm
  // pixels with 40 HU of noise. The cap points from the two slabs' grey lie on the true
  // caps; the ruled surface between the contours lies inside them by its sagitta.
  phantom::Phantom capsule;
  for (const auto& ph : phantom::suite())
    if (ph.name == "capsule") capsule = ph;
  const Volume vol = phantom::scan(capsule.shape, capsule.scan);
  CpuBackend cpu;
  seg::SegmentOptions opt;
  opt.threshold = {phantom::half_level(capsule.scan)};
  const seg::Segmentation s = seg::segment(vol, opt, cpu);
  auto cap_distance = [&](bool partial_volume) {
    pts::PointOptions po;
    po.partial_volume_caps = partial_volume;
    const pts::SlicePoints p = pts::extract_points(s, vol, po);
    double sum = 0;
    int64_t n = 0;
    for (size_t i = 0; i < p.cloud.size(); ++i)
      if (p.is_cap[i]) sum += capsule.shape.distance(p.cloud.positions[i]), ++n;
    EXPECT_GT(n, 100);
    return sum / double(std::max<int64_t>(n, 1));
  };
  const double grey = cap_distance(true), ruled = cap_distance(false);
  std::printf("[ caps ] mean distance to the true caps: %.3f mm from the partial volume, %.3f mm ruled\n", grey, ruled);
  EXPECT_LE(grey, 0.1 * vol.in_plane_spacing() + 0.05);
  EXPECT_LT(grey, 0.5 * ruled);
}

// A label map's bowl: a slab (z < 18 mm) with a ball of 10 mm radius hollowed out of its
// top (its centre 20.6 mm up, so the bowl's bottom is at 10.6 mm), in 2 mm slices of
// 0.7 mm pixels. At the bottom the hole opens between the slices at 10 and 12 mm; the
// slice at 10 mm holds no hole, so its nearest contour is the slab's outer edge, another
// surface. The caps there take the hole's own height, as a dome top's rises from its
// slice: within 0.6 mm of the sphere on average (0.49 measured; 0.86 between the two
// slices' contours, the slab's edge taken for the bowl's).
TEST(Points, LabelMapBowlBottomTakesTheHolesHeight) {
  const Eigen::Vector3d c(14, 14, 20.6);
  const Volume map = test::label_volume({40, 40, 12}, {0.7, 0.7, 2.0}, [&](const Eigen::Vector3d& p) {
    return p.z() < 18 && (p - c).norm() > 10 ? 1.0f : 0.0f;
  });
  const Volume indicator = seg::label_indicator(map, 1, 0.0f);
  CpuBackend cpu;
  seg::SegmentOptions so;
  so.method = seg::Method::kThreshold;
  so.threshold = mc::ThresholdRange{0.5};
  pts::PointOptions po;  // as a label's run sets them (pipeline/run_pipeline.cpp)
  po.partial_volume_caps = false;
  po.curved_caps = true;
  po.caps_to_field_crossing = true;
  const pts::SlicePoints p = pts::extract_points(seg::segment(indicator, so, cpu), indicator, po);
  double sum = 0;
  int64_t n = 0;
  for (size_t i = 0; i < p.cloud.size(); ++i) {
    const Eigen::Vector3d& x = p.cloud.positions[i];
    if (!p.is_cap[i] || x.z() < 9 || x.z() > 13 || std::hypot(x.x() - c.x(), x.y() - c.y()) > 3) continue;
    sum += std::abs((x - c).norm() - 10), ++n;
  }
  std::printf("[ caps ] a bowl's bottom: %lld caps, %.3f mm from the sphere on average\n", (long long)n,
              sum / double(std::max<int64_t>(n, 1)));
  EXPECT_GT(n, 20);
  EXPECT_LT(sum / double(std::max<int64_t>(n, 1)), 0.6);
}

TEST(Points, StructureCutByTheScanIsCapped) {
  // A cylinder along z through the whole scan: caps between the first (last) slice and the
  // padding, at most half a slice outside, facing out.
  Volume v;
  v.dims = {30, 30, 6};
  v.spacing = {1, 1, 2};
  v.voxels.resize(size_t(v.voxel_count()));
  for (int64_t k = 0; k < 6; ++k)
    for (int64_t j = 0; j < 30; ++j)
      for (int64_t i = 0; i < 30; ++i) v.voxels[size_t(v.index(i, j, k))] = std::hypot(i - 14.5, j - 14.5) < 9 ? 1000.0f : 0.0f;
  CpuBackend cpu;
  seg::SegmentOptions opt;
  opt.method = seg::Method::kThreshold;
  opt.threshold = {500};
  const auto p = pts::extract_points(seg::segment(v, opt, cpu), v);
  int64_t bottom = 0, top = 0;
  for (size_t i = 0; i < p.cloud.size(); ++i) {
    if (!p.is_cap[i]) continue;
    const double z = p.cloud.positions[i].z();
    if (z >= -1.0 && z < 0.0 && p.cloud.normals[i].z() < -0.7) ++bottom;
    if (z > 10.0 && z <= 11.0 && p.cloud.normals[i].z() > 0.7) ++top;
  }
  EXPECT_EQ(bottom, p.stats.cap_points / 2);
  EXPECT_EQ(top, p.stats.cap_points / 2);
  EXPECT_GT(top, 200);  // the disk holds about 250 pixels
}

TEST(PointIo, RoundTripsAndRefusesBadFiles) {
  PointCloud c;
  c.positions = {{1, 2, 3}, {-4.5, 0.25, 1e3}};
  c.normals = {{0, 0, 1}, {0.6, 0.8, 0}};
  const std::string dir = test::temp_dir("point_io");
  for (const char* ext : {".ply", ".xyz"}) {
    const std::string path = dir + "/p" + ext;
    write_point_cloud(c, path);
    const PointCloud r = read_point_cloud(path);
    ASSERT_EQ(r.size(), 2u) << ext;
    for (size_t i = 0; i < 2; ++i) {
      EXPECT_LT((r.positions[i] - c.positions[i]).norm(), 1e-4) << ext;
      EXPECT_LT((r.normals[i] - c.normals[i]).norm(), 1e-6) << ext;
    }
  }
  EXPECT_THROW(parse_point_cloud("1 2 3 0 0\n", ".xyz", "short.xyz"), InputError);
  EXPECT_THROW(parse_point_cloud("1 2 3 0 0 0\n", ".xyz", "zero.xyz"), InputError);
  EXPECT_THROW(parse_point_cloud("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                                 "property float z\nend_header\n1 2 3\n",
                                 ".ply", "nonormal.ply"),
               InputError);
  EXPECT_THROW(read_point_cloud(dir + "/p.txt"), InputError);
}

}  // namespace
}  // namespace mpumesh
