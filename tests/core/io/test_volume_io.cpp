// Volume files: the InVesalius reader's parts (plist, tar.gz), and on the real sample CT:
// .inv3, MetaImage, NIfTI, NRRD and a DICOM series give identical voxels and geometry.
#include <gtest/gtest.h>

#include <cstring>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "io/dicom_pixel_check.h"
#include "io/plist.h"
#include "io/read_file.h"
#include "io/targz.h"
#include "io/volume_io.h"
#include "test_support.h"

namespace mpumesh {
namespace {

void expect_same_volume(const Volume& a, const Volume& b) {
  ASSERT_EQ(a.dims, b.dims);
  EXPECT_LT((a.spacing - b.spacing).norm(), 1e-5);
  EXPECT_LT((a.origin - b.origin).norm(), 1e-4);
  EXPECT_LT((a.direction - b.direction).norm(), 1e-6);
  size_t differ = 0;
  for (size_t i = 0; i < a.voxels.size(); ++i) differ += a.voxels[i] != b.voxels[i];
  EXPECT_EQ(differ, 0u);
}

TEST(Plist, ParsesInVesaliusMain) {
  const auto v = plist::parse(
      "<?xml version=\"1.0\"?><plist version=\"1.0\"><dict><key>shape</key><array><integer>3</integer>"
      "<integer>4</integer></array><key>spacing</key><real>0.5</real><key>name</key><string>A &amp; B</string>"
      "<key>on</key><true/><key>empty</key><dict></dict></dict></plist>",
      "main.plist");
  EXPECT_EQ(v.at("shape", "d").array.size(), 2u);
  EXPECT_DOUBLE_EQ(v.at("spacing", "d").as_number("d"), 0.5);
  EXPECT_EQ(v.at("name", "d").as_string("d"), "A & B");
  EXPECT_THROW(v.at("missing", "d"), InputError);
  EXPECT_THROW(plist::parse("<plist><dict><key>a</key><integer>x</integer></dict></plist>", "bad"), InputError);
  EXPECT_THROW(plist::parse("<plist><dict><key>a</key>", "cut"), InputError);
  EXPECT_THROW(plist::parse("not xml", "junk"), InputError);
}

TEST(TarGz, RefusesCorruptArchives) {
  EXPECT_THROW(gunzip("hello world, not gzip", "x.inv3", 1 << 20), InputError);
  std::string gz = "\x1f\x8b\x08\x00\x00\x00\x00\x00\x00\x03" + std::string(20, '\x55');
  EXPECT_THROW(gunzip(gz, "x.inv3", 1 << 20), InputError);
  EXPECT_THROW(untar(std::string(1024, 'x'), "x.tar"), InputError);
  EXPECT_THROW(parse_inv3("", "empty.inv3"), InputError);
}

TEST(TarGz, UnpacksWhateverItsTrailerSays) {
  // The trailer's size is only where the output starts: two members (the trailer gives
  // the second's size, a fifth of the whole) unpack whole; a trailer forged small or huge
  // is refused as corrupt (zlib checks it), naming the file; the cap still holds.
  std::string a(300000, '\0'), b(70000, '\0');
  for (size_t i = 0; i < a.size(); ++i) a[i] = char(i * 7 % 251);
  for (size_t i = 0; i < b.size(); ++i) b[i] = char(i % 13);
  EXPECT_EQ(gunzip(gzip(a) + gzip(b), "two.gz", 1 << 20), a + b);
  for (const uint32_t forged : {uint32_t(1), uint32_t(0xFFFFFFFF)}) {
    std::string gz = gzip(a);
    std::memcpy(gz.data() + gz.size() - 4, &forged, 4);
    EXPECT_THROW(gunzip(gz, "forged.gz", 1 << 20), InputError);  // zlib checks the trailer
    std::string out;
    try {
      gunzip(gz, "forged.gz", 1 << 20);
    } catch (const InputError& e) {
      out = e.what();
    }
    EXPECT_NE(out.find("forged.gz"), std::string::npos) << out;
  }
  EXPECT_THROW(gunzip(gzip(a), "big.gz", 100000), InputError);
  EXPECT_EQ(gunzip(gzip(""), "empty.gz", 100), "");
}

TEST(VolumeIo, MissingAndUnknownFiles) {
  EXPECT_THROW(read_volume("/nonexistent/ct.nii"), InputError);
  const std::string dir = test::temp_dir("unknown");
  {
    std::ofstream(dir + "/a.xyz") << "1 2 3\n";
    std::ofstream(dir + "/b.nii") << "";
    std::ofstream(dir + "/c.mha") << "this is not a MetaImage\n";
  }
  EXPECT_THROW(read_volume(dir + "/a.xyz"), InputError);
  EXPECT_THROW(read_volume(dir + "/b.nii"), InputError);
  EXPECT_THROW(read_volume(dir + "/c.mha"), InputError);
  EXPECT_THROW(read_volume(dir), InputError);  // a directory with no DICOM
}

TEST(VolumeIo, PhantomRoundTripsThroughEveryWriter) {
  Volume v = test::sphere_volume({17, 13, 9}, {0.5, 0.7, 2.0}, {4, 4, 8}, 3.0);
  v.origin = {-10, 20.5, 3};
  const std::string dir = test::temp_dir("phantom");
  for (const char* ext : {".mha", ".nii.gz", ".nrrd", ".nii"}) {
    const std::string p = dir + "/v" + ext;
    write_volume(v, p);
    SCOPED_TRACE(ext);
    expect_same_volume(v, read_volume(p));
  }
  EXPECT_THROW(write_volume(v, dir + "/v.mhd"), InputError);
}

// Files of 8-bit voxels (a label map's usual type), signed and unsigned, in the formats
// read as stored (MetaImage, NRRD): their values, 0-255 and -128-127.
TEST(VolumeIo, EightBitFilesReadAsTheirValues) {
  const std::string dir = test::temp_dir("eight_bit");
  std::string u8, s8;
  for (int i = 0; i < 4 * 8 * 8; ++i) u8 += char(uint8_t(i % 256)), s8 += char(int8_t(i % 256 - 128));
  {
    std::ofstream f(dir + "/u8.nrrd", std::ios::binary);
    f << "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 8 8 4\nspacings: 0.5 0.5 2\nencoding: raw\n\n" << u8;
  }
  {
    std::ofstream f(dir + "/s8.mha", std::ios::binary);
    f << "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\nDimSize = 8 8 4\n"
         "ElementSpacing = 0.5 0.5 2\nElementType = MET_CHAR\nElementDataFile = LOCAL\n"
      << s8;
  }
  const Volume u = read_volume(dir + "/u8.nrrd"), s = read_volume(dir + "/s8.mha");
  ASSERT_EQ(u.voxels.size(), 256u);
  ASSERT_EQ(s.voxels.size(), 256u);
  for (int i = 0; i < 256; ++i) {
    EXPECT_EQ(u.voxels[size_t(i)], float(i % 256)) << i;
    EXPECT_EQ(s.voxels[size_t(i)], float(i % 256 - 128)) << i;
  }
  EXPECT_EQ(u.spacing.z(), 2.0);
}

// The sample project's two masks are InVesalius thresholds of its CT: bone (226-3071 HU)
// inside a wider range (-142-2986 HU). As a label map the bone is label 1 and the rest
// of the wider mask label 2, voxel for voxel.
TEST(VolumeIo, SampleProjectMasksAreALabelMapOfTheirThresholds) {
  MPUMESH_SAMPLE_CT_OR_SKIP(ct);
  const Volume image = read_volume(ct);
  const Volume labels = parse_inv3_masks(read_file(ct), ct);
  ASSERT_EQ(labels.dims, image.dims);
  EXPECT_EQ(labels.spacing, image.spacing);
  int64_t bone = 0, soft = 0, wrong = 0;
  for (size_t i = 0; i < image.voxels.size(); ++i) {
    const float hu = image.voxels[i];
    const float expect = hu >= 226 && hu <= 3071 ? 1.f : hu >= -142 && hu <= 2986 ? 2.f : 0.f;
    wrong += labels.voxels[i] != expect;
    bone += labels.voxels[i] == 1.f;
    soft += labels.voxels[i] == 2.f;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(bone, 475759);
  EXPECT_EQ(soft, 2319106 - 475759);
  // A project with no masks says so.
  const std::string plist = "<?xml version=\"1.0\"?><plist version=\"1.0\"><dict><key>matrix</key><dict><key>shape"
                            "</key><array><integer>2</integer><integer>2</integer><integer>2</integer></array></dict>"
                            "<key>spacing</key><array><real>1</real><real>1</real><real>1</real></array></dict></plist>";
  std::string tar(512, '\0');
  std::memcpy(&tar[0], "main.plist", 10);
  std::snprintf(&tar[124], 12, "%011o", unsigned(plist.size()));
  tar[156] = '0';
  std::memcpy(&tar[257], "ustar", 5);
  tar += plist + std::string((512 - plist.size() % 512) % 512, '\0') + std::string(1024, '\0');
  try {
    parse_inv3_masks(gzip(tar), "none.inv3");
    FAIL() << "a project without masks was read";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "none.inv3: the project holds no masks");
  }
}

TEST(VolumeIo, SampleCtIsTheSameInEveryFormat) {
  MPUMESH_SAMPLE_CT_OR_SKIP(ct);
  const Volume inv3 = read_volume(ct);
  EXPECT_EQ(inv3.dims, (std::array<int64_t, 3>{256, 256, 108}));
  EXPECT_NEAR(inv3.spacing.x(), 0.957, 1e-3);
  EXPECT_NEAR(inv3.spacing.z(), 1.5, 1e-9);
  EXPECT_EQ(inv3.modality, "CT");
  EXPECT_EQ(*std::min_element(inv3.voxels.begin(), inv3.voxels.end()), -1024.0f);
  const std::string dir = test::temp_dir("sample");
  for (const char* ext : {".mha", ".nii.gz", ".nrrd"}) {
    SCOPED_TRACE(ext);
    write_volume(inv3, dir + "/ct" + ext);
    expect_same_volume(inv3, read_volume(dir + "/ct" + ext));
  }
  write_dicom_series(inv3, dir + "/dicom");
  const Volume dcm = read_volume(dir + "/dicom");
  expect_same_volume(inv3, dcm);
  EXPECT_EQ(dcm.modality, "CT");
  // Slices ordered by position, not by file name: reverse the names and read again.
  const std::string rev = dir + "/reversed";
  std::filesystem::create_directories(rev);
  for (int k = 0; k < 108; ++k) {
    char from[64], to[64];
    std::snprintf(from, sizeof from, "/dicom/slice%04d.dcm", k);
    std::snprintf(to, sizeof to, "/reversed/img%04d.dcm", 107 - k);
    std::filesystem::copy_file(dir + from, dir + to);
  }
  expect_same_volume(inv3, read_volume(rev));
  // A missing slice makes the spacing irregular: refused with a clear message.
  std::filesystem::remove(rev + "/img0050.dcm");
  try {
    read_volume(rev);
    FAIL() << "expected irregular spacing to be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("irregular slice spacing"), std::string::npos) << e.what();
  }
}

TEST(VolumeIo, RealDicomFileFromPydicom) {
  MPUMESH_DATA_OR_SKIP(f, test::pydicom_file("CT_small.dcm"), "python3-pydicom");
  const Volume v = read_volume(f);
  EXPECT_EQ(v.dims, (std::array<int64_t, 3>{128, 128, 1}));
  EXPECT_EQ(v.modality, "CT");
  EXPECT_NEAR(v.spacing.x(), 0.661468, 1e-5);
  // Rescale slope/intercept applied: HU, not stored values.
  EXPECT_LT(*std::min_element(v.voxels.begin(), v.voxels.end()), 0.0f);
}

}  // namespace
}  // namespace mpumesh

namespace mpumesh {
namespace {

TEST(VolumeIo, TruncatedDicomIsRefused) {
  MPUMESH_DATA_OR_SKIP(cut, test::pydicom_file("MR_truncated.dcm"), "python3-pydicom");
  MPUMESH_DATA_OR_SKIP(whole, test::pydicom_file("MR_small.dcm"), "python3-pydicom");
  MPUMESH_DATA_OR_SKIP(implicit, test::pydicom_file("MR_small_implicit.dcm"), "python3-pydicom");
  MPUMESH_DATA_OR_SKIP(big, test::pydicom_file("MR_small_bigendian.dcm"), "python3-pydicom");
  try {
    read_volume(cut);
    FAIL() << "expected the truncated file to be refused";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("MR_truncated.dcm: truncated DICOM"), std::string::npos) << e.what();
  }
  EXPECT_EQ(read_volume(whole).dims, (std::array<int64_t, 3>{64, 64, 1}));
  for (const std::string& f : {implicit, big}) EXPECT_NO_THROW(check_dicom_pixel_data(read_file(f), f)) << f;
  // Cutting any whole file short is caught, whatever the transfer syntax.
  for (const std::string& f : {whole, implicit, big}) {
    const std::string b = read_file(f);
    EXPECT_THROW(check_dicom_pixel_data(b.substr(0, b.size() - 300), f), InputError) << f;
  }
}

}  // namespace
}  // namespace mpumesh

namespace mpumesh {
namespace {

// Trilinear resampling reproduces a linear field at the new voxel centres (inside the old
// grid's centres), keeps the extent, and rounds whole-number (HU) input.
TEST(Resample, LinearFieldAndExtentAreKept) {
  Volume v;
  v.dims = {10, 8, 6};
  v.spacing = {0.8, 0.9, 2.0};
  v.origin = {-3, 4, 10};
  v.voxels.resize(size_t(v.voxel_count()));
  auto field = [](const Eigen::Vector3d& p) { return 0.5 * p.x() - 0.25 * p.y() + 0.125 * p.z(); };
  for (int64_t k = 0; k < 6; ++k)
    for (int64_t j = 0; j < 8; ++j)
      for (int64_t i = 0; i < 10; ++i)
        v.voxels[size_t(v.index(i, j, k))] = float(field(v.index_to_physical(Eigen::Vector3d(i, j, k))));
  const Volume r = resample(v, {20, 16, 18});
  EXPECT_NEAR(r.spacing.x(), 0.4, 1e-12);
  EXPECT_NEAR(r.spacing.z(), 2.0 / 3.0, 1e-12);
  // The extent (outer faces of the voxels) is the same.
  const Eigen::Vector3d lo_v = v.origin - v.spacing / 2, lo_r = r.origin - r.spacing / 2;
  EXPECT_LT((lo_v - lo_r).norm(), 1e-9);
  int checked = 0;
  for (int64_t k = 0; k < 18; ++k)
    for (int64_t j = 0; j < 16; ++j)
      for (int64_t i = 0; i < 20; ++i) {
        const Eigen::Vector3d p = r.index_to_physical(Eigen::Vector3d(i, j, k));
        const Eigen::Vector3d u = (p - v.origin).cwiseQuotient(v.spacing);
        if ((u.array() < 0).any() || u.x() > 9 || u.y() > 7 || u.z() > 5) continue;  // clamped at the border
        EXPECT_NEAR(r.at(i, j, k), field(p), 1e-5);
        ++checked;
      }
  EXPECT_GT(checked, 3000);
  // Whole numbers in, whole numbers out.
  Volume hu = v;
  for (float& x : hu.voxels) x = std::round(x * 100);
  for (float x : resample(hu, {7, 9, 11}).voxels) EXPECT_EQ(x, std::round(x));
  EXPECT_THROW(resample(v, {0, 4, 4}), InputError);
}

}  // namespace
}  // namespace mpumesh
