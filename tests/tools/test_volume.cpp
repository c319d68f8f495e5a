// Volume meshes from the command line (`mpumesh tetmesh`, `mpumesh run --volume`) and a
// real finite-element solver on them: CalculiX (calculix-ccx) compresses a CT-like
// cylinder between its two ends, whose reaction force linear tetrahedra give exactly for a
// uniform stress (E A δ / L), and takes the sample CT's skull.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "cli_support.h"
#include "io/mesh_io.h"
#include "io/read_file.h"
#include "io/tet_io.h"
#include "io/volume_io.h"
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
  // Refused before any work: a volume per label, an unknown format.
  expect_failure("run " + ball + " --labels all -o " + dir + "/l_{label}.ply --volume " + dir + "/l.msh", "--volume",
                 dir + "/l.msh");
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
  // The ends: the nodes within half a slice (0.5 mm) of the lowest and the highest; their
  // mean heights set the length. The cross-section: from the surface's radius halfway up.
  double zmin = INFINITY, zmax = -INFINITY;
  for (const auto& p : m.nodes) zmin = std::min(zmin, p.z()), zmax = std::max(zmax, p.z());
  std::vector<uint32_t> top, bottom;
  double ztop = 0, zbottom = 0;
  for (uint32_t i = 0; i < m.nodes.size(); ++i) {
    if (m.nodes[i].z() > zmax - 0.5) top.push_back(i), ztop += m.nodes[i].z();
    if (m.nodes[i].z() < zmin + 0.5) bottom.push_back(i), zbottom += m.nodes[i].z();
  }
  ASSERT_GT(top.size(), 100u);
  ASSERT_GT(bottom.size(), 100u);
  const double L = ztop / double(top.size()) - zbottom / double(bottom.size());
  const TriangleMesh surface = read_mesh(dir + "/cyl.ply");
  double radius = 0;
  int n = 0;
  for (const auto& p : surface.vertices)
    if (std::abs(p.z()) < 15) radius += std::hypot(p.x(), p.y()), ++n;
  radius /= n;
  const double E = 1000, delta = 0.01 * L, A = M_PI * radius * radius;
  // Uniaxial stress: the ends held in z only (the one nearest the axis at the bottom also
  // in x and y, one more in y, against moving and turning as a whole).
  uint32_t centre = bottom[0], side = bottom[0];
  for (uint32_t i : bottom) {
    if (std::hypot(m.nodes[i].x(), m.nodes[i].y()) < std::hypot(m.nodes[centre].x(), m.nodes[centre].y())) centre = i;
    if (m.nodes[i].x() > m.nodes[side].x()) side = i;
  }
  std::ofstream(dir + "/deck.inp") << "*INCLUDE, INPUT=cyl.inp\n" + nset("TOP", top) + nset("BOT", bottom) +
                                          "*MATERIAL, NAME=M\n*ELASTIC\n" + std::to_string(E) +
                                          ", 0.3\n*SOLID SECTION, ELSET=EALL, MATERIAL=M\n*STEP\n*STATIC\n*BOUNDARY\n"
                                          "BOT, 3, 3, 0.\nTOP, 3, 3, " + std::to_string(-delta) + "\n" +
                                          std::to_string(centre + 1) + ", 1, 2, 0.\n" + std::to_string(side + 1) +
                                          ", 2, 2, 0.\n*NODE PRINT, NSET=TOP, TOTALS=ONLY\nRF\n*END STEP\n";
  const int code = std::system(("cd " + dir + " && " + ccx + " -i deck > ccx.log 2>&1").c_str());
  ASSERT_EQ(code, 0) << read_file(dir + "/ccx.log");
  const double F = -total_force_z(read_file(dir + "/deck.dat")), expected = E * A * delta / L;
  std::printf("%zu tetrahedra; L %.3f mm, r %.3f mm, delta %.4f mm: reaction %.2f N, E A delta / L %.2f N (%+.2f%%)\n",
              m.tets.size(), L, radius, delta, F, expected, 100 * (F / expected - 1));
  EXPECT_NEAR(F / expected, 1.0, 0.02);
}

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
