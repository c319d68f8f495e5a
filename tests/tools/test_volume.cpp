// Volume meshes from the command line (`mpumesh tetmesh`, `mpumesh run --volume`), of one
// surface and of a label map's multi-material complex, and a real finite-element solver on
// them: CalculiX (calculix-ccx) compresses a CT-like cylinder between its two ends, whose
// reaction force linear tetrahedra give exactly for a uniform stress (E A δ / L), the same
// cylinder as two labels of two materials in series and side by side, and takes the sample
// CT's skull.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "cli_support.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "io/tet_io.h"
#include "io/volume_io.h"
#include "phantom/material_phantom.h"
#include "tet/tet_quality.h"

namespace mpumesh {
namespace {

// CalculiX from Debian's calculix-ccx, or "" (MPUMESH_DATA_OR_SKIP then skips or fails).
std::string ccx_path() { return std::filesystem::exists("/usr/bin/ccx") ? "/usr/bin/ccx" : ""; }

// A ball's surface, meshed by run from the ball phantom.
std::string ball_surface(const std::string& dir) {
  const std::string out = dir + "/ball.ply";
  EXPECT_EQ(run("run " + ball_phantom(dir) + " --threshold 0 -o " + out + " --backend cpu --quiet").code, 0);
  return out;
}

TEST(Volume, TetmeshWritesEveryFormatAndRefusesWhatItCannotFill) {
  const std::string dir = test::temp_dir("tetmesh");
  const std::string surface = ball_surface(dir);
  const size_t surface_vertices = read_mesh(surface).vertices.size();
  for (const char* ext : {".msh", ".vtu", ".mesh", ".inp"}) {
    const std::string out = dir + "/ball" + ext;
    const Result r = run("tetmesh " + surface + " -o " + out + " --report " + dir + "/r.json");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("tetrahedra"), std::string::npos) << r.out;
    const auto j = nlohmann::json::parse(read_file(dir + "/r.json"));
    const TetMesh m = read_tet_mesh(out);
    EXPECT_EQ(int64_t(m.tets.size()), j["tetrahedra"].get<int64_t>()) << ext;
    EXPECT_EQ(int64_t(m.nodes.size()), j["nodes"].get<int64_t>()) << ext;
    EXPECT_EQ(j["regions"].get<int>(), 1);
    EXPECT_EQ(j["inverted"].get<int>(), 0);
    EXPECT_EQ(j["boundary_points_added"].get<int>(), 0);
    EXPECT_GT(m.nodes.size(), surface_vertices);
    EXPECT_LT(std::abs(j["volume_difference_pct"].get<double>()), 1e-6);
    // `quality` reads it back.
    const Result q = run("quality " + out + " --json");
    ASSERT_EQ(q.code, 0) << q.out;
    EXPECT_EQ(nlohmann::json::parse(q.out)["tetrahedra"].get<int64_t>(), j["tetrahedra"].get<int64_t>());
  }
  // An open surface, with its border edges counted; an unknown format; nothing written.
  TriangleMesh open = read_mesh(surface);
  open.triangles.pop_back();
  write_mesh(open, dir + "/open.ply");
  expect_failure("tetmesh " + dir + "/open.ply -o " + dir + "/open.msh", "3 border edges", dir + "/open.msh");
  expect_failure("tetmesh " + surface + " -o " + dir + "/x.stl", "unknown volume mesh format", dir + "/x.stl");
  expect_failure("tetmesh " + surface + " -o " + dir + "/x.msh --grading 0", "--grading", dir + "/x.msh");
}

TEST(Volume, RunWritesTheVolumeMeshAndReportsIt) {
  const std::string dir = test::temp_dir("run-volume");
  const std::string ball = ball_phantom(dir);
  const Result r = run("run " + ball + " --threshold 0 -o " + dir + "/ball.ply --volume " + dir + "/ball.vtu --report " +
                       dir + "/r.json --html " + dir + "/r.html --backend cpu");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(read_file(dir + "/r.json"));
  const auto& v = j["volume_mesh"];
  EXPECT_EQ(v["output"].get<std::string>(), dir + "/ball.vtu");
  EXPECT_EQ(read_tet_mesh(dir + "/ball.vtu").tets.size(), v["tetrahedra"].get<size_t>());
  EXPECT_NEAR(v["volume_mm3"].get<double>(), j["quality"]["volume_mm3"].get<double>(),
              1e-6 * j["quality"]["volume_mm3"].get<double>());
  EXPECT_EQ(v["dihedral_histogram_5deg"].size(), 36u);
  EXPECT_GE(v["min_dihedral_deg"].get<double>(), 10);
  EXPECT_LE(v["pct_min_dihedral_below_15"].get<double>(), 1.0);
  EXPECT_GE(v["radius_ratio_mean"].get<double>(), 0.7);
  EXPECT_EQ(v["inverted"].get<int64_t>(), 0);
  EXPECT_GT(j["stage_seconds"]["volume mesh"].get<double>(), 0);
  const std::string html = read_file(dir + "/r.html");
  EXPECT_NE(html.find("Volume mesh"), std::string::npos);
  EXPECT_NE(html.find("Dihedral angles of the tetrahedra"), std::string::npos);
  // With the background: the ball is label 1 in a box of label 0.
  const Result b = run("run " + ball + " --threshold 0 -o " + dir + "/bb.ply --volume " + dir +
                       "/bb.msh --volume-background --backend cpu --quiet");
  ASSERT_EQ(b.code, 0) << b.out;
  const TetMesh bb = read_tet_mesh(dir + "/bb.msh");
  EXPECT_EQ(std::set<int32_t>(bb.region.begin(), bb.region.end()), (std::set<int32_t>{0, 1}));
  // Refused before any work: a volume with --separate, a background without a volume, an
  // unknown format.
  expect_failure("run " + ball + " --labels all --separate -o " + dir + "/l_{label}.ply --volume " + dir + "/l.msh",
                 "--volume: one volume mesh of the labels", dir + "/l.msh");
  expect_failure("run " + ball + " --threshold 0 -o " + dir + "/b1.ply --volume-background",
                 "--volume-background: applies to --volume", dir + "/b1.ply");
  expect_failure("run " + ball + " --threshold 0 -o " + dir + "/b2.ply --volume " + dir + "/b2.xyz",
                 "unknown volume mesh format", dir + "/b2.ply");
}

// A cylinder of radius 8 mm along z, cut by the scan's box at z = ±20 mm (so its ends are
// flat), scanned as a CT scans it: partial volume in plane (4 x 4 samples a pixel),
// 0.5 x 0.5 x 1 mm voxels, 30 HU of noise at 1000 HU of contrast.
Volume cut_cylinder() {
  Volume v;
  v.spacing = {0.5, 0.5, 1.0};
  v.dims = {49, 49, 41};
  v.origin = {-12, -12, -20};
  v.modality = "CT";
  v.voxels.assign(size_t(v.voxel_count()), 0.0f);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0, 30);
  for (int64_t k = 0; k < v.dims[2]; ++k)
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i) {
        int in = 0;
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b) {
            const double x = -12 + 0.5 * (double(i) + (a + 0.5) / 4 - 0.5), y = -12 + 0.5 * (double(j) + (b + 0.5) / 4 - 0.5);
            in += x * x + y * y <= 64;
          }
        v.voxels[size_t(v.index(i, j, k))] = float(std::round(1000.0 * in / 16 + noise(rng)));
      }
  return v;
}

// An Abaqus node set of 1-based ids.
std::string nset(const std::string& name, const std::vector<uint32_t>& ids) {
  std::string s = "*NSET, NSET=" + name + "\n";
  for (size_t k = 0; k < ids.size(); ++k) s += std::to_string(ids[k] + 1) + ((k + 1) % 16 == 0 || k + 1 == ids.size() ? "\n" : ", ");
  return s;
}

// The z component of the "total force" CalculiX prints for a set.
double total_force_z(const std::string& dat) {
  std::istringstream in(dat);
  for (std::string line; std::getline(in, line);)
    if (line.find("total force") != std::string::npos) {
      double fx = 0, fy = 0, fz = NAN;
      in >> fx >> fy >> fz;
      return fz;
    }
  return NAN;
}

// A cylinder's ends in its volume mesh: the nodes within half a slice (0.5 mm) of the
// lowest and the highest, their mean heights; the bottom's node nearest the axis and the
// one farthest along x.
struct Ends {
  std::vector<uint32_t> top, bottom;
  double ztop = 0, zbottom = 0;
  uint32_t centre = 0, side = 0;
};
Ends cylinder_ends(const TetMesh& m) {
  double zmin = INFINITY, zmax = -INFINITY;
  for (const auto& p : m.nodes) zmin = std::min(zmin, p.z()), zmax = std::max(zmax, p.z());
  Ends e;
  for (uint32_t i = 0; i < m.nodes.size(); ++i) {
    if (m.nodes[i].z() > zmax - 0.5) e.top.push_back(i), e.ztop += m.nodes[i].z();
    if (m.nodes[i].z() < zmin + 0.5) e.bottom.push_back(i), e.zbottom += m.nodes[i].z();
  }
  e.ztop /= double(e.top.size()), e.zbottom /= double(e.bottom.size());
  e.centre = e.side = e.bottom[0];
  for (uint32_t i : e.bottom) {
    if (std::hypot(m.nodes[i].x(), m.nodes[i].y()) < std::hypot(m.nodes[e.centre].x(), m.nodes[e.centre].y()))
      e.centre = i;
    if (m.nodes[i].x() > m.nodes[e.side].x()) e.side = i;
  }
  return e;
}

// A CalculiX deck that includes `mesh`, gives it `materials` (materials and sections) and
// compresses it by delta between its ends, uniaxially: the ends held in z only (the
// bottom's centre also in x and y, its side node in y, against moving and turning as a
// whole); the top's reaction printed. Returns the reaction along -z.
double compress(const std::string& ccx, const std::string& dir, const std::string& mesh, const Ends& e,
                const std::string& materials, double delta) {
  std::ofstream(dir + "/deck.inp") << "*INCLUDE, INPUT=" + mesh + "\n" + nset("TOP", e.top) + nset("BOT", e.bottom) +
                                          materials + "*STEP\n*STATIC\n*BOUNDARY\nBOT, 3, 3, 0.\nTOP, 3, 3, " +
                                          std::to_string(-delta) + "\n" + std::to_string(e.centre + 1) +
                                          ", 1, 2, 0.\n" + std::to_string(e.side + 1) +
                                          ", 2, 2, 0.\n*NODE PRINT, NSET=TOP, TOTALS=ONLY\nRF\n*END STEP\n";
  const int code = std::system(("cd " + dir + " && " + ccx + " -i deck > ccx.log 2>&1").c_str());
  EXPECT_EQ(code, 0) << read_file(dir + "/ccx.log");
  return -total_force_z(read_file(dir + "/deck.dat"));
}

TEST(FiniteElements, ACutCylinderCompressedBetweenItsEndsGivesEADeltaOverL) {
  MPUMESH_DATA_OR_SKIP(ccx, ccx_path(), "calculix-ccx");
  const std::string dir = test::temp_dir("fe-cylinder");
  write_volume(cut_cylinder(), dir + "/cyl.nii.gz");
  const Result r = run("run " + dir + "/cyl.nii.gz --threshold 500 -o " + dir + "/cyl.ply --volume " + dir +
                       "/cyl.inp --backend cpu --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  const TetMesh m = read_tet_mesh(dir + "/cyl.inp");
  // The quality asked of a volume mesh, on this CT-like phantom as read back.
  const TetQuality q = measure_tet_quality(m);
  std::printf("cylinder: %lld tetrahedra, smallest dihedral %.2f deg, %.3f%% under 15, radius ratio %.3f\n",
              (long long)q.tets, q.min_dihedral_deg, q.pct_min_dihedral_below_15, q.radius_ratio_mean);
  EXPECT_GE(q.min_dihedral_deg, 10);
  EXPECT_LE(q.pct_min_dihedral_below_15, 1.0);
  EXPECT_GE(q.radius_ratio_mean, 0.7);
  EXPECT_EQ(q.inverted, 0);
  // The ends' mean heights set the length. The cross-section: from the surface's radius
  // halfway up.
  const Ends e = cylinder_ends(m);
  ASSERT_GT(e.top.size(), 100u);
  ASSERT_GT(e.bottom.size(), 100u);
  const double L = e.ztop - e.zbottom;
  const TriangleMesh surface = read_mesh(dir + "/cyl.ply");
  double radius = 0;
  int n = 0;
  for (const auto& p : surface.vertices)
    if (std::abs(p.z()) < 15) radius += std::hypot(p.x(), p.y()), ++n;
  radius /= n;
  const double E = 1000, delta = 0.01 * L, A = M_PI * radius * radius;
  const double F = compress(ccx, dir, "cyl.inp", e,
                            "*MATERIAL, NAME=M\n*ELASTIC\n" + std::to_string(E) +
                                ", 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=M\n",
                            delta);
  const double expected = E * A * delta / L;
  std::printf("%zu tetrahedra; L %.3f mm, r %.3f mm, delta %.4f mm: reaction %.2f N, E A delta / L %.2f N (%+.2f%%)\n",
              m.tets.size(), L, radius, delta, F, expected, 100 * (F / expected - 1));
  EXPECT_NEAR(F / expected, 1.0, 0.02);
}

// A label map of three labels to one volume mesh with a region per label, in one run; the
// complex's PLY to the same by `tetmesh`, with the background on request.
TEST(Volume, ALabelMapGivesOneVolumeMeshWithARegionPerLabel) {
  const std::string dir = test::temp_dir("label-volume");
  for (const phantom::MaterialPhantom& m : phantom::material_suite())
    if (m.name == "sectors") write_volume(phantom::material_scan(m), dir + "/sectors.nii.gz");
  const Result r = run("run " + dir + "/sectors.nii.gz --labels all -o " + dir + "/c.ply --volume " + dir +
                       "/c.msh --report " + dir + "/r.json --backend cpu");
  ASSERT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("c.msh: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("label 3 "), std::string::npos) << r.out;
  const auto j = nlohmann::json::parse(read_file(dir + "/r.json"));
  const auto& v = j["volume_mesh"];
  ASSERT_EQ(v["labels"].size(), 3u);
  EXPECT_EQ(v["inverted"], 0);
  EXPECT_EQ(v["boundary_points_added"], 0);
  for (const auto& l : v["labels"]) {
    EXPECT_NEAR(l["volume_mm3"].get<double>() / l["boundary_volume_mm3"].get<double>(), 1, 1e-6) << l.dump();
    EXPECT_GE(l["min_dihedral_at_junctions_deg"].get<double>(), 10) << l.dump();
  }
  for (const auto& l : j["complex"]["labels"])  // against the label's voxels
    EXPECT_LT(std::abs(l["tetrahedra_volume_vs_voxels"].get<double>()), 0.02) << l.dump();
  const TetMesh m = read_tet_mesh(dir + "/c.msh");
  EXPECT_EQ(std::set<int32_t>(m.region.begin(), m.region.end()), (std::set<int32_t>{1, 2, 3}));
  EXPECT_EQ(m.boundary.size(), read_mesh(dir + "/c.ply").triangles.size());
  // `tetmesh` takes the complex; with --background, label 0 around it.
  const Result t = run("tetmesh " + dir + "/c.ply -o " + dir + "/b.vtu --background");
  ASSERT_EQ(t.code, 0) << t.out;
  EXPECT_NE(t.out.find("label 0 "), std::string::npos) << t.out;
  const TetMesh b = read_tet_mesh(dir + "/b.vtu");
  EXPECT_EQ(std::set<int32_t>(b.region.begin(), b.region.end()), (std::set<int32_t>{0, 1, 2, 3}));
}

// A cylinder of radius 8 mm and length 40 mm along z in a label map of 0.5 x 0.5 x 1 mm
// voxels, its two halves labels 1 and 2: across its axis at z = 0 (`lengthwise` false),
// or along it at x = 0.
Volume two_label_cylinder(bool lengthwise) {
  Volume v;
  v.spacing = {0.5, 0.5, 1.0};
  v.dims = {49, 49, 47};
  v.origin = {-12, -12, -23};
  v.voxels.assign(size_t(v.voxel_count()), 0.0f);
  for (int64_t k = 0; k < v.dims[2]; ++k)
    for (int64_t j = 0; j < v.dims[1]; ++j)
      for (int64_t i = 0; i < v.dims[0]; ++i) {
        const Eigen::Vector3d p = v.index_to_physical({double(i), double(j), double(k)});
        if (p.x() * p.x() + p.y() * p.y() > 64 || std::abs(p.z()) >= 20) continue;
        v.voxels[size_t(v.index(i, j, k))] = (lengthwise ? p.x() : p.z()) < 0 ? 1.0f : 2.0f;
      }
  return v;
}

// An INP set's 1-based ids, 0-based.
std::vector<uint32_t> inp_set(const std::string& inp, const std::string& header) {
  const size_t at = inp.find(header + "\n");
  std::vector<uint32_t> ids;
  if (at == std::string::npos) return ids;
  std::string body = inp.substr(at + header.size() + 1);
  body = body.substr(0, body.find('*'));
  std::replace(body.begin(), body.end(), ',', ' ');
  std::istringstream in(body);
  for (uint32_t id; in >> id;) ids.push_back(id - 1);
  return ids;
}

// The two halves of two_label_cylinder as materials of E1 = 1,000 and E2 = 10,000 MPa
// (ν 0.3), compressed by 1% between the ends: in series (halves along the axis) the
// reaction is δ / (L1 / (E1 A1) + L2 / (E2 A2)), side by side (E1 A1 + E2 A2) δ / L, the
// lengths from the ends' and the interface's nodes, the areas from each label's volume.
// A gap or an overlap at the interface would change the force.
void two_materials(bool lengthwise) {
  MPUMESH_DATA_OR_SKIP(ccx, ccx_path(), "calculix-ccx");
  const std::string dir = test::temp_dir(lengthwise ? "fe-parallel" : "fe-series");
  write_volume(two_label_cylinder(lengthwise), dir + "/cyl.nii.gz");
  const Result r = run("run " + dir + "/cyl.nii.gz --labels all -o " + dir + "/cyl.ply --volume " + dir +
                       "/cyl.inp --backend cpu --quiet");
  ASSERT_EQ(r.code, 0) << r.out;
  const TetMesh m = read_tet_mesh(dir + "/cyl.inp");
  const std::string inp = read_file(dir + "/cyl.inp");
  double volume[3] = {0, 0, 0};
  for (size_t t = 0; t < m.tets.size(); ++t) {
    const auto& v = m.tets[t];
    volume[m.region[t]] += tet_shape(m.nodes[v[0]], m.nodes[v[1]], m.nodes[v[2]], m.nodes[v[3]]).volume;
  }
  const Ends e = cylinder_ends(m);
  const double L = e.ztop - e.zbottom, E1 = 1000, E2 = 10000, delta = 0.01 * L;
  double expected = 0;
  if (lengthwise) {
    expected = (E1 * volume[1] / L + E2 * volume[2] / L) * delta / L;
  } else {
    const std::vector<uint32_t> interface = inp_set(inp, "*NSET, NSET=INTERFACE_1_2");
    ASSERT_GT(interface.size(), 50u);
    double zi = 0;
    for (uint32_t i : interface) zi += m.nodes[i].z() / double(interface.size());
    const double L1 = zi - e.zbottom, L2 = e.ztop - zi;
    expected = delta / (L1 / (E1 * volume[1] / L1) + L2 / (E2 * volume[2] / L2));
  }
  const double F = compress(ccx, dir, "cyl.inp", e,
                            "*MATERIAL, NAME=M1\n*ELASTIC\n" + std::to_string(E1) + ", 0.3\n*MATERIAL, NAME=M2\n"
                                "*ELASTIC\n" + std::to_string(E2) + ", 0.3\n*SOLID SECTION, ELSET=LABEL_1, "
                                "MATERIAL=M1\n*SOLID SECTION, ELSET=LABEL_2, MATERIAL=M2\n",
                            delta);
  std::printf("%s: %zu tetrahedra; L %.3f mm, volumes %.1f and %.1f mm3: reaction %.2f N, expected %.2f N (%+.2f%%)\n",
              lengthwise ? "side by side" : "in series", m.tets.size(), L, volume[1], volume[2], F, expected,
              100 * (F / expected - 1));
  EXPECT_NEAR(F / expected, 1.0, 0.02);
}

TEST(FiniteElements, TwoMaterialsInSeriesGiveTheSeriesForce) { two_materials(false); }
TEST(FiniteElements, TwoMaterialsSideBySideGiveTheParallelForce) { two_materials(true); }

TEST(FiniteElements, CalculixTakesTheSampleCtsSkull) {
  MPUMESH_DATA_OR_SKIP(ccx, ccx_path(), "calculix-ccx");
  MPUMESH_SAMPLE_CT_OR_SKIP(ct);
  const std::string dir = test::temp_dir("fe-skull");
  const Result r = run("run " + ct + " --threshold 226 --particles 45000 --largest 1 -o " + dir +
                       "/skull.ply --volume " + dir + "/skull.inp --report " + dir +
                       "/r.json --backend cpu --quiet --no-self-intersections");
  ASSERT_EQ(r.code, 0) << r.out;
  // The skull under its own weight, held at its surface: bone's E, ν and density (N, mm, t).
  std::ofstream(dir + "/deck.inp") << "*INCLUDE, INPUT=skull.inp\n*MATERIAL, NAME=BONE\n*ELASTIC\n17000., 0.3\n"
                                      "*DENSITY\n1.9e-9\n*SOLID SECTION, ELSET=EALL, MATERIAL=BONE\n*STEP\n*STATIC\n"
                                      "*BOUNDARY\nBOUNDARY, 1, 3, 0.\n*DLOAD\nEALL, GRAV, 9810., 0., 0., -1.\n"
                                      "*NODE FILE\nU\n*END STEP\n";
  const int code = std::system(("cd " + dir + " && " + ccx + " -i deck > ccx.log 2>&1").c_str());
  const std::string log = read_file(dir + "/ccx.log");
  EXPECT_EQ(code, 0) << log;
  EXPECT_EQ(log.find("*ERROR"), std::string::npos) << log;
  EXPECT_NE(log.find("Job finished"), std::string::npos) << log;
  EXPECT_TRUE(std::filesystem::exists(dir + "/deck.frd"));
  const auto j = nlohmann::json::parse(read_file(dir + "/r.json"));
  std::printf("skull: %lld tetrahedra in %d regions, smallest dihedral %.2f deg (%lld points for flat tetrahedra), "
              "CalculiX finished\n",
              (long long)j["volume_mesh"]["tetrahedra"].get<int64_t>(), j["volume_mesh"]["regions"].get<int>(),
              j["volume_mesh"]["min_dihedral_deg"].get<double>(), (long long)j["volume_mesh"]["points_for_flat_tetrahedra"].get<int64_t>());
  // Without the points for flat tetrahedra, one flat under a fold of the skull kept 8.58°.
  EXPECT_GE(j["volume_mesh"]["min_dihedral_deg"].get<double>(), 10.0);
}

}  // namespace
}  // namespace mpumesh
