// The fuzzers' seed corpora and the inputs they once failed on (tests/fuzz/corpus,
// tests/fuzz/regressions), replayed through the same parsers in the ordinary build: every
// file parses or is refused with an InputError, and the seeds are what they claim.
#include <gtest/gtest.h>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "io/dicom_pixel_check.h"
#include "io/mesh_io.h"
#include "io/plist.h"
#include "io/point_io.h"
#include "io/read_file.h"
#include "io/targz.h"
#include "io/tet_io.h"
#include "io/volume_integrity.h"
#include "io/volume_io.h"
#include "mpu/mpu_io.h"

namespace mpumesh {
namespace {

namespace fs = std::filesystem;
const fs::path kFuzz = fs::path(MPUMESH_SOURCE_DIR) / "tests" / "fuzz";

// The fuzz targets' dispatch (tests/fuzz/fuzz_*.cpp); true when the input parsed.
bool parse(const std::string& target, const std::string& b) {
  try {
    if (target == "mpu") mpu::parse_mpu(b, "f.mpu");
    else if (target == "mesh") parse_mesh(b.substr(1), static_cast<MeshFormat>(uint8_t(b.at(0)) % 4), "f");
    else if (target == "points") {
      const std::string rest = b.substr(1);
      switch (uint8_t(b.at(0)) % 3) {
        case 0: parse_point_cloud(rest, ".ply", "f.ply"); break;
        case 1: parse_point_cloud(rest, ".xyz", "f.xyz"); break;
        default: parse_positions(rest, "f");
      }
    } else if (target == "plist") plist::parse(b, "f.plist");
    else if (target == "inv3") parse_inv3(gzip(b), "f.inv3");
    else if (target == "dicom") check_dicom_pixel_data(b, "f.dcm");
    else if (target == "volume") {
      static const char* const kExt[] = {".nii", ".nii.gz", ".nrrd", ".mha"};
      const std::string rest = b.substr(1), ext = kExt[uint8_t(b.at(0)) % 4];
      const bool gz = rest.size() >= 2 && uint8_t(rest[0]) == 0x1f && uint8_t(rest[1]) == 0x8b;
      const std::string path = (fs::temp_directory_path() / ("mpumesh_corpus_volume" + ext)).string();
      std::ofstream(path, std::ios::binary) << (ext == ".nii.gz" && !gz ? gzip(rest) : rest);
      check_volume_file(path);
    }
    else if (target == "tet") parse_tet_mesh(b.substr(1), static_cast<TetFormat>(uint8_t(b.at(0)) % 4), "f");
    else ADD_FAILURE() << "unknown target " << target;
    return true;
  } catch (const InputError&) {
    return false;
  }
}

// Seeds named *_cut* or *_flip* (truncated and bit-flipped variants) and pydicom's
// truncated MR are damaged on purpose: they must be refused; every other seed parses.
bool damaged_on_purpose(const std::string& name) {
  return name.find("_cut") != std::string::npos || name.find("_flip") != std::string::npos ||
         name.find("truncated") != std::string::npos;
}

TEST(FuzzCorpus, SeedsAndRegressionsParseOrAreRefused) {
  int files = 0;
  for (const char* dir : {"corpus", "regressions"}) {
    if (!fs::is_directory(kFuzz / dir)) continue;
    for (const auto& t : fs::directory_iterator(kFuzz / dir))
      for (const auto& f : fs::directory_iterator(t.path())) {
        ++files;
        const bool parsed = parse(t.path().filename().string(), read_file(f.path().string()));
        if (std::string(dir) == "corpus")
          EXPECT_EQ(parsed, !damaged_on_purpose(f.path().filename().string())) << f.path();
      }
  }
  EXPECT_GE(files, 26);
}

TEST(FuzzCorpus, SeedsAreWhatTheyClaim) {
  // The volume mesh seeds: one mesh of the icosahedron, in every format mpumesh writes and
  // as meshio writes .vtu (zlib blocks; raw with 64-bit headers).
  for (const char* name : {"ico_msh", "ico_vtu", "ico_mesh", "ico_inp", "ico_meshio_zlib_vtu", "ico_meshio_raw64_vtu"}) {
    const std::string b = read_file((kFuzz / "corpus/tet" / name).string());
    const TetMesh m = parse_tet_mesh(b.substr(1), static_cast<TetFormat>(uint8_t(b.at(0)) % 4), name);
    EXPECT_EQ(m.nodes.size(), 12u) << name;
    EXPECT_EQ(m.tets.size(), 15u) << name;
  }
  EXPECT_EQ(parse_mesh(read_file((kFuzz / "corpus/mesh/ico.off").string()).substr(1), MeshFormat::kOff, "ico")
                .triangles.size(),
            20u);
  const Volume v = parse_inv3(gzip(read_file((kFuzz / "corpus/inv3/project.tar").string())), "project");
  EXPECT_EQ(v.dims[0] * v.dims[1] * v.dims[2], 48);
  EXPECT_EQ(v.modality, "CT");
  EXPECT_GT(mpu::parse_mpu(read_file((kFuzz / "corpus/mpu/sphere.mpu").string()), "sphere").leaves.size(), 8u);
  EXPECT_THROW(check_dicom_pixel_data(read_file((kFuzz / "corpus/dicom/MR_truncated.dcm").string()), "mr"),
               InputError);
}

}  // namespace
}  // namespace mpumesh
