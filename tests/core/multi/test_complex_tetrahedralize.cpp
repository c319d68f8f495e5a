// One volume mesh of a multi-material complex (core/multi/complex_tetrahedralize.h), on the
// material phantoms' complexes: every tetrahedron positive and labelled, the faces between
// tetrahedra of two labels exactly the complex's interface triangles, each label's
// tetrahedra filling exactly its boundary's volume, the quality of the single-region path
// next to the interfaces and junction curves too, the background in its box on request,
// and the groups kept by every format.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>
#include <set>

#include "common/error.h"
#include "cpu/cpu_backend.h"
#include "io/tet_io.h"
#include "multi/complex_figures.h"
#include "multi/complex_tetrahedralize.h"
#include "phantom/material_phantom.h"
#include "pipeline/complex_run.h"
#include "tet/tet_quality.h"
#include "test_support.h"

namespace mpumesh {
namespace {

using Face = std::array<uint32_t, 3>;
Face sorted(Face f) {
  std::ranges::sort(f);
  return f;
}

// The complex of a material phantom, meshed as `run --labels all` meshes it.
const TriangleMesh& phantom_complex(const std::string& name) {
  static std::map<std::string, TriangleMesh> cache;
  if (cache.count(name)) return cache.at(name);
  for (const phantom::MaterialPhantom& m : phantom::material_suite()) {
    if (m.name != name) continue;
    CpuBackend cpu;
    std::vector<int64_t> labels;
    for (int l : m.labels()) labels.push_back(l);
    const pipeline::ComplexResult r = pipeline::run_complex(
        phantom::material_scan(m), labels, false, pipeline::RunOptions{}, [&]() -> ComputeBackend& { return cpu; },
        nullptr, [](pipeline::LabelRun&) {});
    return cache[name] = r.complex.mesh;
  }
  ADD_FAILURE() << "no phantom " << name;
  static const TriangleMesh none;
  return none;
}

// Tolerances, once (the single-region path's targets): the smallest dihedral angle of
// every label, next to its interfaces and junction curves too, at least 10 degrees (15.8
// measured); at most 0.1% of the tetrahedra with one under 15 degrees (0 measured); mean
// radius ratio at least 0.75 (0.79); the tetrahedra's volume per label its boundary's to
// 1e-6 relative (1e-14 measured).
constexpr double kMinDihedral = 10, kBelow15Pct = 0.1, kRadiusRatio = 0.75, kVolume = 1e-6;

// Conformity, from the mesh alone: each face shared by tetrahedra of two labels is a
// triangle of the complex tagged with those labels; each triangle of the complex is a face
// of one tetrahedron of each of its labels (of b alone where a is the unmeshed background).
void expect_conforming(const TriangleMesh& c, const TetMesh& m, bool background) {
  std::map<Face, std::vector<int32_t>> sides;
  for (size_t t = 0; t < m.tets.size(); ++t)
    for (const auto& f : kTetFace)
      sides[sorted({m.tets[t][size_t(f[0])], m.tets[t][size_t(f[1])], m.tets[t][size_t(f[2])]})].push_back(m.region[t]);
  std::map<Face, std::array<int32_t, 2>> tags;
  for (size_t i = 0; i < c.triangles.size(); ++i) tags[sorted(c.triangles[i])] = c.face_labels[i];
  int64_t wrong = 0, between = 0;
  for (auto& [face, labels] : sides) {
    std::ranges::sort(labels);
    if (labels.size() == 2 && labels[0] != labels[1]) {
      ++between;
      const auto it = tags.find(face);
      wrong += it == tags.end() || it->second != std::array<int32_t, 2>{labels[0], labels[1]};
    }
  }
  int64_t shared = 0;  // the triangles between two meshed labels
  for (const auto& [face, l] : tags) {
    shared += l[0] > 0 || background;
    std::vector<int32_t> want;
    if (l[0] > 0 || background) want.push_back(l[0]);
    want.push_back(l[1]);
    const auto it = sides.find(face);
    wrong += it == sides.end() || it->second != want;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(between, shared);
}

void expect_label_volumes_and_quality(const TriangleMesh& c, const TetMesh& m, const TetStats& st) {
  EXPECT_EQ(st.boundary_points, 0);  // no node added on an interface
  std::map<int32_t, TetMesh> parts;
  for (size_t t = 0; t < m.tets.size(); ++t) parts[m.region[t]].tets.push_back(m.tets[t]);
  ASSERT_EQ(parts.size(), st.labels.size());
  for (auto& [label, part] : parts) {
    part.nodes = m.nodes;
    part.region.assign(part.tets.size(), 1);
    const TetQuality q = measure_tet_quality(part);
    EXPECT_EQ(q.inverted, 0) << "label " << label;
    EXPECT_GE(q.min_dihedral_deg, kMinDihedral) << "label " << label;
    EXPECT_LE(q.pct_min_dihedral_below_15, kBelow15Pct) << "label " << label;
    EXPECT_GE(q.radius_ratio_mean, kRadiusRatio) << "label " << label;
    if (label > 0) {
      const double boundary = enclosed_volume(multi::label_boundary(c, label));
      EXPECT_NEAR(q.volume_mm3 / boundary, 1, kVolume) << "label " << label;
    }
    const auto f = std::ranges::find_if(st.labels, [l = label](const LabelTetFigures& x) { return x.label == l; });
    ASSERT_NE(f, st.labels.end());
    EXPECT_EQ(f->quality.tets, q.tets);
    EXPECT_GE(f->min_dihedral_at_interfaces, kMinDihedral);
    EXPECT_GE(f->min_dihedral_at_junctions, kMinDihedral);
  }
}

class ComplexTets : public ::testing::TestWithParam<const char*> {};

TEST_P(ComplexTets, ConformRegionPerLabelExactVolumes) {
  const TriangleMesh& c = phantom_complex(GetParam());
  TetStats st;
  const TetMesh m = multi::tetrahedralize_complex(c, TetOptions{}, &st);
  std::printf("%s: %zu tetrahedra, %zu nodes, smallest dihedral %.2f, radius ratio %.3f, %.2f s\n", GetParam(),
              m.tets.size(), m.nodes.size(), st.quality.min_dihedral_deg, st.quality.radius_ratio_mean, st.seconds);
  std::set<int32_t> labels(m.region.begin(), m.region.end());
  const std::vector<int64_t> want = multi::complex_labels(c);  // with 0
  EXPECT_EQ(std::vector<int64_t>(labels.begin(), labels.end()), std::vector<int64_t>(want.begin() + 1, want.end()));
  EXPECT_EQ(m.regions, int32_t(labels.size()));
  EXPECT_EQ(m.boundary.size(), c.triangles.size());
  expect_conforming(c, m, false);
  expect_label_volumes_and_quality(c, m, st);
}

INSTANTIATE_TEST_SUITE_P(Phantoms, ComplexTets, ::testing::Values("split ball", "nested", "sectors", "joint"),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::ranges::replace(n, ' ', '_');
                           return n;
                         });

// With the background asked for: label 0 fills a box around the complex (10% of its
// extent or the inner size larger on every side), and the whole mesh the box's volume.
TEST(ComplexTetsBackground, FillsTheBoxAroundTheComplex) {
  const TriangleMesh& c = phantom_complex("split ball");
  TetOptions opt;
  opt.background = true;
  TetStats st;
  const TetMesh m = multi::tetrahedralize_complex(c, opt, &st);
  EXPECT_EQ(st.labels.front().label, 0);
  expect_conforming(c, m, true);
  expect_label_volumes_and_quality(c, m, st);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(INFINITY), hi = -lo, clo = lo, chi = hi;
  for (const auto& p : m.nodes) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  for (const auto& p : c.vertices) clo = clo.cwiseMin(p), chi = chi.cwiseMax(p);
  const double margin = std::max(st.size, 0.1 * (chi - clo).maxCoeff());  // at least the inner size
  EXPECT_NEAR((clo - lo).minCoeff(), margin, 1e-9);
  EXPECT_NEAR((hi - chi).minCoeff(), margin, 1e-9);
  EXPECT_NEAR(st.quality.volume_mm3 / (hi - lo).prod(), 1, kVolume);
  int64_t box = 0;
  for (const auto& l : m.boundary_labels) box += l == std::array<int32_t, 2>{0, 0};
  EXPECT_GT(box, 0);
  EXPECT_EQ(m.boundary.size(), c.triangles.size() + size_t(box));
}

// Every format keeps the labels of the tetrahedra; .msh, .vtu and .mesh the interfaces'
// triangles with their labels too (.inp keeps them as sets, read by meshio and CalculiX).
TEST(ComplexTetsFormats, GroupsSurviveEveryFormat) {
  const TriangleMesh& c = phantom_complex("sectors");
  const TetMesh m = multi::tetrahedralize_complex(c, TetOptions{});
  const std::string dir = test::temp_dir("complex-tets");
  for (const char* ext : {".msh", ".vtu", ".mesh", ".inp"}) {
    const std::string path = dir + "/sectors" + ext;
    write_tet_mesh(m, path);
    const TetMesh back = read_tet_mesh(path);
    EXPECT_EQ(back.nodes.size(), m.nodes.size()) << ext;
    EXPECT_EQ(back.regions, 3) << ext;
    auto labelled = [](const TetMesh& x) {  // .msh groups the tetrahedra by label
      std::map<std::array<uint32_t, 4>, int32_t> out;
      for (size_t t = 0; t < x.tets.size(); ++t) out[x.tets[t]] = x.region[t];
      return out;
    };
    EXPECT_EQ(labelled(back), labelled(m)) << ext;
    if (std::string(ext) == ".inp") continue;
    std::map<Face, std::array<int32_t, 2>> want, got;
    for (size_t i = 0; i < m.boundary.size(); ++i) want[sorted(m.boundary[i])] = m.boundary_labels[i];
    for (size_t i = 0; i < back.boundary.size(); ++i) got[sorted(back.boundary[i])] = back.boundary_labels[i];
    EXPECT_EQ(got, want) << ext;
  }
}

// A vertex no triangle uses (a PLY may hold one) changes nothing.
TEST(ComplexTetsInput, VerticesNoTriangleUsesAreIgnored) {
  const TriangleMesh& c = phantom_complex("nested");
  TriangleMesh extra = c;
  extra.vertices.insert(extra.vertices.begin(), Eigen::Vector3d(1, 2, 3));
  for (auto& t : extra.triangles)
    for (auto& v : t) ++v;
  TetStats a, b;
  const TetMesh ma = multi::tetrahedralize_complex(c, TetOptions{}, &a);
  const TetMesh mb = multi::tetrahedralize_complex(extra, TetOptions{}, &b);
  EXPECT_EQ(ma.tets, mb.tets);
  EXPECT_EQ(a.labels.size(), b.labels.size());
  EXPECT_EQ(a.labels.back().min_dihedral_at_interfaces, b.labels.back().min_dihedral_at_interfaces);
}

// A label whose boundary is open is refused, naming it; so is a mesh without labels.
TEST(ComplexTetsRefusal, OpenLabelBoundaryIsNamed) {
  TriangleMesh c = phantom_complex("nested");
  size_t k = 0;
  while (c.face_labels[k] != std::array<int32_t, 2>{1, 2}) ++k;
  c.triangles.erase(c.triangles.begin() + ptrdiff_t(k));
  c.face_labels.erase(c.face_labels.begin() + ptrdiff_t(k));
  try {
    multi::tetrahedralize_complex(c, TetOptions{});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("label 1's boundary"), std::string::npos) << e.what();
  }
  c.face_labels.clear();
  EXPECT_THROW(multi::tetrahedralize_complex(c, TetOptions{}), InputError);
}

}  // namespace
}  // namespace mpumesh
