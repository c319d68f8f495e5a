// Bad input and faults, as a user meets them: every case exits 1 with one "mpumesh:
// error:" line naming the file (or option) and the problem, before any long work, and
// leaves no output file or temporary behind (expect_failure in cli_support.h).
#include <gtest/gtest.h>
#include <signal.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <thread>

#include "cli_support.h"
#include "io/atomic_file.h"
#include "io/mesh_io.h"
#include "io/point_io.h"
#include "io/read_file.h"
#include "test_support.h"

namespace mpumesh {
namespace {

// A CT series with one defect, written by tests/support/make_dicom.py (pydicom).
std::string dicom_series(const std::string& dir, const std::string& name, const std::string& options) {
  const std::string out = dir + "/" + name;
  const std::string cmd = "/usr/bin/python3 " + std::string(MPUMESH_SOURCE_DIR) + "/tests/support/make_dicom.py " +
                          out + " " + options;
  EXPECT_EQ(std::system(cmd.c_str()), 0) << cmd;
  return out;
}

bool have_pydicom() { return std::system("/usr/bin/python3 -c 'import pydicom' 2>/dev/null") == 0; }

#define PYDICOM_OR_SKIP()                                                                          \
  if (!have_pydicom()) {                                                                           \
    if (test::env_flag("MPUMESH_REQUIRE_DATA")) FAIL() << "missing: install python3-pydicom";      \
    GTEST_SKIP() << "missing: install python3-pydicom";                                            \
  }

TEST(BadInput, DicomSeriesWithDefects) {
  PYDICOM_OR_SKIP();
  const std::string dir = test::temp_dir("bad_dicom");
  const std::string out = dir + "/out.ply";
  auto mc = [&](const std::string& in) { return "mc " + in + " --threshold 0 -o " + out + " --backend cpu"; };
  // The good series meshes; each defect is named.
  ASSERT_EQ(run(mc(dicom_series(dir, "good", "")) + " --quiet").code, 0);
  std::filesystem::remove(out);
  expect_failure(mc(dicom_series(dir, "tilt", "--tilt 12")), "gantry tilt of 12", out);
  expect_failure(mc(dicom_series(dir, "gap", "--drop 5")), "irregular slice spacing", out);
  expect_failure(mc(dicom_series(dir, "dup", "--dup 5")), "duplicate slice position", out);
  expect_failure(mc(dicom_series(dir, "mixed", "--resize 5")), "holds 2 DICOM series", out);
  expect_failure(mc(dicom_series(dir, "short", "--truncate 5")), "slice005.dcm: truncated DICOM", out);
  // A tilt under half a degree is rounding, not a tilt.
  EXPECT_EQ(run(mc(dicom_series(dir, "tiny_tilt", "--tilt 0.2")) + " --quiet").code, 0);
}

TEST(BadInput, FilesThatAreNotWhatTheyClaim) {
  const std::string dir = test::temp_dir("bad_files");
  const std::string out = dir + "/out.ply";
  {
    std::ofstream(dir + "/empty.nii");
    std::ofstream(dir + "/junk.nrrd") << "this is not a NRRD header\n";
    std::filesystem::create_directory(dir + "/nodicom");
    std::ofstream(dir + "/nodicom/readme.txt") << "no images here";
  }
  expect_failure("mc " + dir + "/empty.nii --threshold 0 -o " + out, "empty.nii: file is empty", out);
  expect_failure("mc " + dir + "/junk.nrrd --threshold 0 -o " + out, "junk.nrrd", out);
  expect_failure("mc " + dir + "/nodicom --threshold 0 -o " + out, "no DICOM series found", out);
  MPUMESH_DATA_OR_SKIP(truncated, test::pydicom_file("MR_truncated.dcm"), "python3-pydicom");
  expect_failure("run " + truncated + " -o " + out, "MR_truncated.dcm: truncated DICOM", out);
  MPUMESH_DATA_OR_SKIP(slice, test::pydicom_file("CT_small.dcm"), "python3-pydicom");
  expect_failure("run " + slice + " -o " + out, "a 2D image (128 x 128 x 1 voxels)", out);
  expect_failure("segment " + slice + " -o " + dir + "/m.nii", "a 2D image", dir + "/m.nii");
}

// A cut or corrupted volume is refused by every command that reads one, and the output a
// good run wrote before is left as it was.
TEST(BadInput, DamagedVolumesNeverReplaceAGoodOutput) {
  const std::string dir = test::temp_dir("damaged");
  const std::string out = dir + "/out.ply", report = dir + "/out.json";
  const Volume v = test::sphere_volume({30, 28, 12}, {0.6, 0.6, 2.0}, {9, 8, 12}, 6.0);
  write_volume(v, dir + "/ball.nii");
  write_volume(v, dir + "/ball.nii.gz");
  ASSERT_EQ(run("run " + dir + "/ball.nii --threshold 0 --backend cpu --quiet -o " + out + " --report " + report).code,
            0);
  const std::string good = read_file(out), good_report = read_file(report);
  auto damaged = [&](const std::string& from, const std::string& name, bool truncate) {
    std::string b = read_file(dir + "/" + from);
    if (truncate) b.resize(b.size() * 2 / 3);
    else
      for (size_t i = 0; i < 4; ++i) b[b.size() / 2 + i] = char(~b[b.size() / 2 + i]);
    std::ofstream(dir + "/" + name, std::ios::binary) << b;
    return dir + "/" + name;
  };
  const std::string cut = damaged("ball.nii", "cut.nii", true), flipped = damaged("ball.nii.gz", "flip.nii.gz", false);
  for (const auto& [in, words] : {std::pair{cut, std::string("cut.nii: data end after")},
                                  std::pair{flipped, std::string("flip.nii.gz: compressed data corrupt")}}) {
    for (const std::string cmd : {"run", "mc"}) {
      const Result r = run(cmd + " " + in + " --threshold 0 --backend cpu -o " + out +
                           (cmd == "run" ? " --report " + report : ""));
      EXPECT_EQ(r.code, 1) << r.out;
      EXPECT_NE(r.out.find("mpumesh: error: " + dir), std::string::npos) << r.out;
      EXPECT_NE(r.out.find(words), std::string::npos) << r.out;
      EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
      EXPECT_EQ(read_file(out), good) << cmd << " " << in;
      EXPECT_EQ(read_file(report), good_report) << cmd << " " << in;
    }
    expect_failure("convert " + in + " -o " + dir + "/copy.mha", words, dir + "/copy.mha");
    expect_failure("segment " + in + " --threshold 0 -o " + dir + "/mask.nii", words, dir + "/mask.nii");
  }
}

TEST(BadInput, VolumesWithoutASurface) {
  const std::string dir = test::temp_dir("bad_volumes");
  const std::string out = dir + "/out.ply";
  Volume v = test::sphere_volume({20, 20, 10}, {1, 1, 2}, {10, 10, 10}, 5);
  v.voxels[123] = std::numeric_limits<float>::quiet_NaN();
  write_volume(v, dir + "/nan.mha");
  v.voxels[123] = std::numeric_limits<float>::infinity();
  write_volume(v, dir + "/inf.mha");
  std::fill(v.voxels.begin(), v.voxels.end(), 40.0f);
  write_volume(v, dir + "/constant.mha");
  const std::string ball = ball_phantom(dir);
  expect_failure("run " + dir + "/nan.mha -o " + out, "nan.mha: the volume holds NaN or infinite values", out);
  expect_failure("run " + dir + "/inf.mha -o " + out, "inf.mha: the volume holds NaN or infinite values", out);
  expect_failure("run " + dir + "/constant.mha --threshold 0 -o " + out, "every voxel lies in the threshold range",
                 out);
  expect_failure("run " + dir + "/constant.mha --threshold 100 -o " + out, "no voxel lies in the threshold range",
                 out);
  expect_failure("run " + ball + " --threshold 5000 -o " + out, "no voxel lies in the threshold range", out);
  expect_failure("run " + ball + " --threshold -5000 -o " + out, "no surface inside the volume", out);
  expect_failure("mc " + ball + " --threshold -5000 -o " + out, "selects every voxel", out);
}

TEST(BadInput, SmallAndBorderStructures) {
  const std::string dir = test::temp_dir("small");
  // One bright voxel: too few contour points for a surface, said plainly.
  Volume v = test::sphere_volume({16, 16, 8}, {1, 1, 2}, {8, 8, 8}, 0.01);
  std::fill(v.voxels.begin(), v.voxels.end(), -1000.0f);
  v.voxels[size_t(4 * 16 * 16 + 8 * 16 + 8)] = 1000.0f;
  write_volume(v, dir + "/dot.mha");
  expect_failure("run " + dir + "/dot.mha --threshold 0 --method threshold -o " + dir + "/o.ply", "fewer than --nmin",
                 dir + "/o.ply");
  // A ball cut by the volume's border is capped there: a closed mesh.
  write_volume(test::sphere_volume({24, 24, 10}, {0.8, 0.8, 2.0}, {9.6, 9.6, 2.0}, 7.0), dir + "/cut.mha");
  const Result r = run("run " + dir + "/cut.mha --threshold 0 --particles 1500 -o " + dir +
                       "/cut.ply --backend cpu --json --no-self-intersections");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
  EXPECT_TRUE(j["quality"]["closed"].get<bool>());
  EXPECT_TRUE(j["quality"]["oriented"].get<bool>());
}

TEST(BadInput, PointClouds) {
  const std::string dir = test::temp_dir("bad_points");
  const std::string out = dir + "/s.mpu";
  {
    std::ofstream(dir + "/nonormals.xyz") << "0 0 0\n1 0 0\n0 1 0\n";
    std::ofstream zero(dir + "/zero.xyz"), nan(dir + "/nan.xyz"), plane(dir + "/plane.xyz");
    for (int i = 0; i < 300; ++i) {
      const double x = std::sin(i * 1.7) * 9, y = std::cos(i * 2.3) * 9, z = std::sin(i * 0.37) * 9;
      zero << x << ' ' << y << ' ' << z << " 0 0 0\n";
      nan << x << ' ' << y << ' ' << z << " nan 0 1\n";
      plane << x << ' ' << y << " 3 0 0 1\n";
    }
  }
  expect_failure("fit " + dir + "/nonormals.xyz -o " + out, "nonormals.xyz: line 1 is not 'x y z nx ny nz'", out);
  expect_failure("fit " + dir + "/zero.xyz -o " + out, "zero.xyz: point 0 has a non-finite position or a zero normal",
                 out);
  expect_failure("fit " + dir + "/nan.xyz -o " + out, "nan.xyz: line 1", out);
  expect_failure("fit " + dir + "/plane.xyz -o " + out, "the points lie on one plane", out);
  // Duplicates are dropped before the fit: the same surface as without them.
  const test::AnalyticShape sphere{test::AnalyticShape::kSphere, 6, 6, 6};
  PointCloud c = test::sample_shape(sphere, 0.5, 1.0, false);
  write_point_cloud(c, dir + "/once.ply");
  const size_t n = c.size();
  for (size_t i = 0; i < n; ++i) c.positions.push_back(c.positions[i]), c.normals.push_back(c.normals[i]);
  write_point_cloud(c, dir + "/twice.ply");
  const Result a = run("fit " + dir + "/once.ply -o " + dir + "/once.mpu --json");
  const Result b = run("fit " + dir + "/twice.ply -o " + dir + "/twice.mpu --json");
  ASSERT_EQ(a.code, 0) << a.out;
  ASSERT_EQ(b.code, 0) << b.out;
  EXPECT_EQ(nlohmann::json::parse(b.out)["duplicates_removed"].get<size_t>(), n);
  EXPECT_EQ(read_file(dir + "/once.mpu"), read_file(dir + "/twice.mpu"));
  // All points at one place: one distinct point.
  PointCloud one;
  for (int i = 0; i < 100; ++i) one.positions.push_back({1, 2, 3}), one.normals.push_back({0, 0, 1});
  write_point_cloud(one, dir + "/one.ply");
  expect_failure("fit " + dir + "/one.ply -o " + out, "1 distinct points, fewer than --nmin", out);
}

TEST(BadInput, MeshesAndSurfaces) {
  const std::string dir = test::temp_dir("bad_meshes");
  {
    std::ofstream(dir + "/range.off") << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
    std::ofstream(dir + "/bad.mpu") << "MPUMESH\0 but nothing else";
    // Two triangles sharing an edge with a third: a non-manifold edge; and a degenerate one.
    std::ofstream(dir + "/fin.off") << "OFF\n6 4 0\n0 0 0\n1 0 0\n0 1 0\n0 -1 0\n0 0 1\n2 0 0\n"
                                    << "3 0 1 2\n3 1 0 3\n3 0 1 4\n3 0 1 5\n";
  }
  expect_failure("quality " + dir + "/range.off", "range.off: face index 7 is out of range (3 vertices)",
                 dir + "/none");
  expect_failure("run " + dir + "/range.off -o " + dir + "/o.ply", "range.off: face index 7", dir + "/o.ply");
  expect_failure("polygonize " + dir + "/bad.mpu -o " + dir + "/o.ply", "bad.mpu: not a valid .mpu file",
                 dir + "/o.ply");
  // quality measures a broken mesh (that is its job) and says what is wrong with it.
  const Result q = run("quality " + dir + "/fin.off --json");
  ASSERT_EQ(q.code, 0) << q.out;
  const auto j = nlohmann::json::parse(q.out);
  EXPECT_FALSE(j["manifold"].get<bool>());
  EXPECT_EQ(j["nonmanifold_edges"].get<int>(), 1);
  EXPECT_EQ(j["zero_area_triangles"].get<int>(), 1);  // 0 1 5 lie on the x axis
  // run refuses to remesh it.
  expect_failure("run " + dir + "/fin.off -o " + dir + "/o.ply", "fin.off: the input mesh is not a closed manifold",
                 dir + "/o.ply");
  // Volume meshes whose counts promise more than the file holds are refused at once.
  std::ofstream(dir + "/huge.msh") << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n0 0 0 1\n"
                                      "1 0 0 0 1 1 1 99999999999999 1\n$EndEntities\n$Nodes\n1 3 1 3\n"
                                      "3 1 0 99999999999999\n1\n";
  std::ofstream(dir + "/huge.mesh") << "MeshVersionFormatted 2\nDimension 3\nVertices\n99999999999999\n0 0 0 1\n";
  expect_failure("quality " + dir + "/huge.msh", "huge.msh: not a volume mesh mpumesh can read", dir + "/none");
  expect_failure("quality " + dir + "/huge.mesh", "huge.mesh: not a volume mesh mpumesh can read", dir + "/none");
  std::ofstream(dir + "/far.mesh") << "MeshVersionFormatted 2\nDimension 3\nVertices\n4\n0 0 0 1\n1 0 0 1\n0 1 0 1\n"
                                      "0 0 1 1\nTetrahedra\n1\n1 2 3 4 1\nTriangles\n1\n1 2 9 1\nEnd\n";
  expect_failure("quality " + dir + "/far.mesh", "far.mesh: not a volume mesh mpumesh can read: a triangle names node 9",
                 dir + "/none");
}

TEST(BadInput, AbsurdParameters) {
  const std::string dir = test::temp_dir("bad_params");
  const std::string ball = ball_phantom(dir);
  const std::string out = dir + "/o.ply";
  const std::string base = "run " + ball + " --threshold 0 -o " + out + " ";
  expect_failure(base + "--particles -5", "--particles must be between 1 and 10^8", out);
  expect_failure(base + "--spacing -1", "--spacing must be positive", out);
  expect_failure(base + "--spacing nan", "--spacing", out);
  expect_failure(base + "--particle-iterations 0", "run: --particle-iterations must be between 1 and 100000", out);
  expect_failure(base + "--method chan-vese --iterations 0", "--iterations must be between 1 and 100000", out);
  expect_failure(base + "--nmin 0", "nmin", out);
  expect_failure(base + "--curvature-scale -1", "--curvature-scale", out);
  expect_failure("sample " + dir + "/none.mpu -o " + dir + "/p.ply --particles 0 --spacing 0 --iterations -3",
                 "--iterations", dir + "/p.ply");
  // More particles than the machine can hold: refused at once, with the estimate.
  const auto t0 = std::chrono::steady_clock::now();
  expect_failure(base + "--particles 90000000", "GiB, more than the", out);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 5.0);
  // The same check against a smaller machine (MPUMESH_MEMORY_LIMIT_GIB): after the points,
  // before the fit; the estimate is in the run's report.
  const Result r = run("run " + ball + " --threshold 0 -o " + out + " --backend cpu --json --no-self-intersections");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
  const double need = j["memory"]["estimate_gib"].get<double>();
  EXPECT_GT(j["memory"]["peak_rss_gib"].get<double>(), 0.0);
  std::filesystem::remove(out);
  expect_failure("run " + ball + " --threshold 0 -o " + out + " --backend cpu", "this job needs about", out,
                 "MPUMESH_MEMORY_LIMIT_GIB=" + std::to_string(need * 0.9));
}

TEST(Faults, NoVulkanDriver) {
  const std::string dir = test::temp_dir("novulkan");
  const std::string ball = ball_phantom(dir);
  const std::string env = "VK_DRIVER_FILES=/nonexistent.json VK_ICD_FILENAMES=/nonexistent.json";
  // auto falls back to the CPU and says so; gpu fails with the reason.
  const Result r = run("mc " + ball + " --threshold 0 -o " + dir + "/a.ply --backend auto", env);
  EXPECT_EQ(r.code, 0) << r.out;
  EXPECT_NE(r.out.find("using the native CPU path"), std::string::npos) << r.out;
  EXPECT_TRUE(std::filesystem::exists(dir + "/a.ply"));
  expect_failure("mc " + ball + " --threshold 0 -o " + dir + "/g.ply --backend gpu", "no Vulkan driver found",
                 dir + "/g.ply", env);
}

// SIGTERM and SIGINT in the middle of a run: exit 143 / 130, no output, no temporary.
TEST(Faults, InterruptedRunLeavesNothing) {
  const std::string dir = test::temp_dir("signal");
  // Large enough that the run (about 5 s here) is still going when the signal comes.
  write_volume(test::sphere_volume({120, 120, 60}, {0.5, 0.5, 1.0}, {30, 30, 30}, 25.0), dir + "/big.mha");
  for (const auto& [sig, code] : {std::pair{SIGTERM, 143}, std::pair{SIGINT, 130}}) {
    const std::string out = dir + "/o" + std::to_string(sig) + ".ply";
    const std::string cmd = std::string(MPUMESH_BIN) + " run " + dir + "/big.mha --threshold 0 --particles 40000 -o " +
                            out + " --html " + out + ".html --report " + out + ".json --backend cpu -q & pid=$!; "
                            "sleep 1; kill -" + std::to_string(sig) + " $pid; wait $pid; echo \"rc=$?\"";
    Result r;
    FILE* p = popen(("bash -c '" + cmd + "' 2>&1").c_str(), "r");
    char buf[4096];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
    pclose(p);
    EXPECT_NE(r.out.find("rc=" + std::to_string(code)), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("interrupted"), std::string::npos) << r.out;
    for (auto& e : std::filesystem::directory_iterator(dir))
      EXPECT_EQ(e.path().filename().string(), "big.mha") << "left behind: " << e.path();
  }
}

TEST(Faults, OutputsAreCheckedBeforeTheWork) {
  const std::string dir = test::temp_dir("outputs");
  { std::ofstream(dir + "/file.txt") << "x"; }
  // The input does not exist: an output error reported instead proves the outputs are
  // checked before anything is read, let alone fitted.
  const std::string in = dir + "/not-read-yet.mha";
  expect_failure("run " + in + " -o " + dir + "/missing/o.ply", "output directory", dir + "/missing/o.ply");
  expect_failure("run " + in + " -o " + dir + "/file.txt/o.ply", "does not exist", dir + "/file.txt/o.ply");
  expect_failure("run " + in + " -o " + dir + "/o.ply --report " + dir + "/missing/r.json", "missing/r.json",
                 dir + "/o.ply");
  expect_failure("run " + in + " -o " + dir + "/o.ply --html " + dir + "/r.htm", "must be a .html file",
                 dir + "/o.ply");
  expect_failure("run " + in + " -o " + dir + "/o.ply --html /proc/r.html", "not writable", dir + "/o.ply");
  expect_failure("render " + in + " -o /proc/v.png", "not writable", "/proc/v.png");
  expect_failure("convert " + in + " -o /proc/v.mha", "not writable", "/proc/v.mha");
}

// Every DICOM file of pydicom's test corpus (python3-pydicom's data/test_files/*.dcm)
// through `convert`: each reads, or is refused with one line that names it; none crashes
// the process (a third-party reader's crash comes back as that line: io/isolated_read.h)
// and none runs past the 60 s that `timeout` gives it. The kinds of file that hold no
// image say what they are.
TEST(BadInput, EveryFileOfPydicomsCorpusReadsOrIsRefusedWithOneLine) {
  MPUMESH_DATA_OR_SKIP(ct_small, test::pydicom_file("CT_small.dcm"), "python3-pydicom");
  const std::filesystem::path corpus = std::filesystem::path(ct_small).parent_path();
  const std::string dir = test::temp_dir("pydicom_corpus");
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(corpus))
    if (e.path().extension() == ".dcm") files.push_back(e.path().string());
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 60u);
  int read = 0, refused = 0;
  for (const std::string& f : files) {
    const std::string out = dir + "/" + std::filesystem::path(f).stem().string() + ".nii.gz";
    const Result r = run("convert " + f + " -o " + out + " --quiet", "timeout 60");
    ASSERT_TRUE(r.code == 0 || r.code == 1) << f << ": exit " << r.code << "\n" << r.out;
    if (r.code == 0) {
      ++read;
      EXPECT_TRUE(std::filesystem::exists(out)) << f;
      continue;
    }
    ++refused;
    EXPECT_EQ(std::count(r.out.begin(), r.out.end(), '\n'), 1) << r.out;
    EXPECT_EQ(r.out.rfind("mpumesh: error: " + f + ": ", 0), 0u) << r.out;
    EXPECT_FALSE(std::filesystem::exists(out)) << f;
  }
  std::printf("%zu files: %d read, %d refused\n", files.size(), read, refused);
  const std::vector<std::pair<const char*, const char*>> kinds = {
      {"rtplan.dcm", "holds no image to mesh: it is an RT plan"},
      {"rtstruct.dcm", "holds no image to mesh: it is an RT structure set"},
      {"test-SR.dcm", "holds no image to mesh: it is a structured report"},
      {"waveform_ecg.dcm", "holds no image to mesh: it is a waveform"},
      {"rtdose_1frame.dcm", "the DICOM reader crashed (abort)"}};
  for (const auto& [name, words] : kinds)
    expect_failure("convert " + (corpus / name).string() + " -o " + dir + "/k.nii.gz", words, dir + "/k.nii.gz");
}

// The reader's child killed on purpose (MPUMESH_READER_TEST=abort) and made to hang past
// the time limit: each is one line naming the file, and an existing output stays as it was.
TEST(Faults, TheReadersCrashOrHangIsAnErrorThatNamesTheFile) {
  const std::string dir = test::temp_dir("reader_faults");
  const std::string ball = ball_phantom(dir), out = dir + "/out.nii.gz";
  write_file_atomically("the old output", out);
  for (const auto& [env, words] :
       {std::pair<std::string, std::string>{"MPUMESH_READER_TEST=abort", "the MetaImage reader crashed (abort)"},
        {"MPUMESH_READER_TEST=hang MPUMESH_READER_TIMEOUT=1", "the MetaImage reader ran past its time limit of 1 s"}}) {
    const Result r = run("convert " + ball + " -o " + out, env);
    EXPECT_EQ(r.code, 1) << r.out;
    EXPECT_NE(r.out.find("mpumesh: error: " + ball + ": " + words), std::string::npos) << r.out;
    EXPECT_EQ(read_file(out), "the old output");
  }
}

}  // namespace
}  // namespace mpumesh
