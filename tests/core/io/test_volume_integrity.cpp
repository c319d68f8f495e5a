// Damaged volume files: every format the tool reads refuses a file whose data are shorter
// than its header says, or whose compressed stream fails its check, with one message
// naming the file and the problem; a 4-D volume is refused with its sizes; what the
// libraries print while reading is caught (damage an error, the rest notes).
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "common/error.h"
#include "io/library_messages.h"
#include "io/read_file.h"
#include "io/targz.h"
#include "io/volume_integrity.h"
#include "io/volume_io.h"
#include "test_support.h"

namespace mpumesh {
namespace {

void write_bytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

// The first `keep` bytes of `from` into `to`.
std::string cut(const std::string& from, const std::string& to, double keep) {
  const std::string b = read_file(from);
  write_bytes(to, b.substr(0, size_t(double(b.size()) * keep)));
  return to;
}

// Four bytes inverted in the middle of the file.
std::string flip(const std::string& from, const std::string& to) {
  std::string b = read_file(from);
  for (size_t i = 0; i < 4; ++i) b[b.size() / 2 + i] = char(~b[b.size() / 2 + i]);
  write_bytes(to, b);
  return to;
}

// read_volume must refuse `path` with a message naming it and containing `words`.
void expect_refused(const std::string& path, const std::string& words) {
  try {
    read_volume(path);
    ADD_FAILURE() << path << ": read without complaint";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(path, 0), 0u) << m;
    EXPECT_NE(m.find(words), std::string::npos) << "want '" << words << "' in: " << m;
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
  }
}

Volume small_ct() {
  Volume v = test::sphere_volume({24, 22, 10}, {0.6, 0.6, 2.0}, {7, 6.6, 10}, 5.0);
  for (float& x : v.voxels) x = std::round(x);  // int16 on disk, as CT is
  return v;
}

std::string int16_bytes(const Volume& v) {
  std::string raw(v.voxels.size() * 2, '\0');
  for (size_t i = 0; i < v.voxels.size(); ++i) {
    const int16_t x = int16_t(v.voxels[i]);
    std::memcpy(&raw[2 * i], &x, 2);
  }
  return raw;
}

std::string sizes(const Volume& v) {
  return std::to_string(v.dims[0]) + " " + std::to_string(v.dims[1]) + " " + std::to_string(v.dims[2]);
}

// NRRD with raw encoding, data in the file.
std::string write_raw_nrrd(const Volume& v, const std::string& path) {
  write_bytes(path, "NRRD0004\n# raw, little-endian\ntype: short\ndimension: 3\nsizes: " + sizes(v) +
                        "\nspacings: 0.6 0.6 2\nencoding: raw\nendian: little\n\n" + int16_bytes(v));
  return path;
}

// NRRD header with its raw data in a file of its own (.nhdr).
std::string write_nhdr(const Volume& v, const std::string& dir, double keep = 1.0) {
  const std::string raw = int16_bytes(v);
  write_bytes(dir + "/v.raw", raw.substr(0, size_t(double(raw.size()) * keep)));
  write_bytes(dir + "/v.nhdr", "NRRD0004\ntype: short\ndimension: 3\nsizes: " + sizes(v) +
                                   "\nspacings: 0.6 0.6 2\nencoding: raw\nendian: little\ndata file: v.raw\n\n");
  return dir + "/v.nhdr";
}

// MetaImage header with detached data; `compressed` writes the data as a zlib/gzip stream.
std::string write_mhd(const Volume& v, const std::string& dir, bool compressed) {
  const std::string data = compressed ? gzip(int16_bytes(v)) : int16_bytes(v);
  const std::string name = compressed ? "v.zraw" : "v.raw";
  write_bytes(dir + "/" + name, data);
  std::string h = "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\n";
  if (compressed) h += "CompressedData = True\nCompressedDataSize = " + std::to_string(data.size()) + "\n";
  h += "ElementSpacing = 0.6 0.6 2\nDimSize = " + sizes(v) + "\nElementType = MET_SHORT\nElementDataFile = " + name + "\n";
  write_bytes(dir + "/v.mhd", h);
  return dir + "/v.mhd";
}

// A NIfTI-1 single file (n+1) by hand: int16 voxels, `dim` with as many sizes as given.
std::string write_nifti(const std::string& path, std::vector<int16_t> dim, const std::string& data) {
  std::string h(352, '\0');
  const int32_t hdr = 348;
  std::memcpy(&h[0], &hdr, 4);
  int16_t d[8] = {int16_t(dim.size()), 1, 1, 1, 1, 1, 1, 1};
  for (size_t i = 0; i < dim.size(); ++i) d[i + 1] = dim[i];
  std::memcpy(&h[40], d, 16);
  const int16_t datatype = 4, bitpix = 16;
  std::memcpy(&h[70], &datatype, 2);
  std::memcpy(&h[72], &bitpix, 2);
  float pixdim[8] = {1, 1, 1, 1, 1, 1, 1, 1};
  std::memcpy(&h[76], pixdim, 32);
  const float offset = 352;
  std::memcpy(&h[108], &offset, 4);
  std::memcpy(&h[344], "n+1\0", 4);
  write_bytes(path, h + data);
  return path;
}

TEST(VolumeIntegrity, IntactFilesOfEveryFormatRead) {
  const Volume v = small_ct();
  const std::string dir = test::temp_dir("intact");
  for (const char* ext : {".nii", ".nii.gz", ".nrrd", ".mha"}) {
    SCOPED_TRACE(ext);
    write_volume(v, dir + "/v" + ext);
    const VolumeFileLayout l = check_volume_file(dir + "/v" + ext);
    EXPECT_EQ(l.data_bytes, uint64_t(v.voxel_count()) * 2);
    EXPECT_EQ(read_volume(dir + "/v" + ext).voxels, v.voxels);
  }
  EXPECT_EQ(read_volume(write_raw_nrrd(v, dir + "/raw.nrrd")).voxels, v.voxels);
  EXPECT_EQ(read_volume(write_nhdr(v, test::temp_dir("intact_nhdr"))).voxels, v.voxels);
  const std::string raw_dir = test::temp_dir("intact_mhd"), z_dir = test::temp_dir("intact_mhd_z");
  EXPECT_EQ(read_volume(write_mhd(v, raw_dir, false)).voxels, v.voxels);
  EXPECT_EQ(read_volume(write_mhd(v, z_dir, true)).voxels, v.voxels);
  EXPECT_TRUE(check_volume_file(z_dir + "/v.mhd").compressed);
}

TEST(VolumeIntegrity, TruncatedFilesAreRefusedInEveryFormat) {
  const Volume v = small_ct();
  const std::string dir = test::temp_dir("truncated");
  const std::string need = with_thousands(uint64_t(v.voxel_count()) * 2);
  for (const char* ext : {".nii", ".mha"}) {  // ITK writes .mha compressed: both kinds
    SCOPED_TRACE(ext);
    write_volume(v, dir + "/v" + ext);
    expect_refused(cut(dir + "/v" + ext, dir + "/cut" + ext, 0.6), "data end after");
  }
  write_volume(v, dir + "/v.nii.gz");
  expect_refused(cut(dir + "/v.nii.gz", dir + "/cut.nii.gz", 0.6), "cut short");
  write_volume(v, dir + "/v.nrrd");  // gzip encoding
  expect_refused(cut(dir + "/v.nrrd", dir + "/cut.nrrd", 0.6), "cut short");
  expect_refused(cut(write_raw_nrrd(v, dir + "/raw.nrrd"), dir + "/cutraw.nrrd", 0.6), " of " + need + " bytes");
  expect_refused(write_nhdr(v, test::temp_dir("cut_nhdr"), 0.5), "data end after");
  // .mhd: the detached raw file cut, and the detached compressed one.
  for (bool z : {false, true}) {
    SCOPED_TRACE(z ? "zraw" : "raw");
    const std::string d = test::temp_dir(z ? "cut_mhd_z" : "cut_mhd");
    const std::string mhd = write_mhd(v, d, z);
    const std::string data = d + (z ? "/v.zraw" : "/v.raw");
    cut(data, data, 0.5);
    expect_refused(mhd, z ? "cut short" : "data end after " + with_thousands(uint64_t(v.voxel_count())) + " of " + need);
  }
  // A header cut inside itself.
  expect_refused(cut(dir + "/v.nii", dir + "/head.nii", 200.0 / double(read_file(dir + "/v.nii").size())),
                 "header is cut short");
}

TEST(VolumeIntegrity, CorruptCompressedStreamsAreRefused) {
  const Volume v = small_ct();
  const std::string dir = test::temp_dir("corrupt");
  for (const char* ext : {".nii.gz", ".nrrd", ".mha"}) {
    SCOPED_TRACE(ext);
    write_volume(v, dir + "/v" + ext);
    expect_refused(flip(dir + "/v" + ext, dir + "/flip" + ext), "corrupt");
  }
  const std::string d = test::temp_dir("corrupt_mhd");
  const std::string mhd = write_mhd(v, d, true);
  flip(d + "/v.zraw", d + "/v.zraw");
  expect_refused(mhd, "corrupt");
  // A gzip stream whose CRC alone fails (the deflate data intact): the last 8 bytes hold
  // CRC-32 and length.
  std::string gz = read_file(dir + "/v.nii.gz");
  gz[gz.size() - 6] = char(~gz[gz.size() - 6]);
  write_bytes(dir + "/crc.nii.gz", gz);
  expect_refused(dir + "/crc.nii.gz", "corrupt");
}

TEST(VolumeIntegrity, DamagedInVesaliusProjectsAreRefused) {
  const Volume v = small_ct();
  const std::string raw = int16_bytes(v);
  const std::string dir = test::temp_dir("inv3");
  auto project = [&](const std::string& matrix) {
    const std::string plist =
        "<?xml version=\"1.0\"?><plist version=\"1.0\"><dict><key>matrix</key><dict><key>dtype</key>"
        "<string>int16</string><key>filename</key><string>matrix.dat</string><key>shape</key><array><integer>" +
        std::to_string(v.dims[2]) + "</integer><integer>" + std::to_string(v.dims[1]) + "</integer><integer>" +
        std::to_string(v.dims[0]) +
        "</integer></array></dict><key>spacing</key><array><real>0.6</real><real>0.6</real><real>2</real></array>"
        "</dict></plist>";
    std::string tar;
    for (auto [name, body] : {std::pair{std::string("main.plist"), plist}, std::pair{std::string("matrix.dat"), matrix}}) {
      std::string h(512, '\0');
      std::memcpy(&h[0], name.data(), name.size());
      std::snprintf(&h[124], 12, "%011o", unsigned(body.size()));
      h[156] = '0';
      std::memcpy(&h[257], "ustar", 5);
      tar += h + body + std::string((512 - body.size() % 512) % 512, '\0');
    }
    return gzip(tar + std::string(1024, '\0'));
  };
  write_bytes(dir + "/good.inv3", project(raw));
  EXPECT_EQ(read_volume(dir + "/good.inv3").voxels, v.voxels);
  expect_refused(cut(dir + "/good.inv3", dir + "/cut.inv3", 0.6), "corrupt or truncated gzip");
  expect_refused(flip(dir + "/good.inv3", dir + "/flip.inv3"), "gzip");
  write_bytes(dir + "/short.inv3", project(raw.substr(0, raw.size() / 2)));
  expect_refused(dir + "/short.inv3", "matrix.dat holds");
}

TEST(VolumeIntegrity, FourDimensionalVolumesAreRefusedWithTheirSizes) {
  const std::string dir = test::temp_dir("4d");
  const std::string data(4 * 4 * 4 * 3 * 2, '\0');
  expect_refused(write_nifti(dir + "/t.nii", {4, 4, 4, 3}, data), "4-D volume (4 x 4 x 4 x 3)");
  // A fourth axis of one is a 3-D volume.
  write_nifti(dir + "/one.nii", {4, 4, 4, 1}, std::string(4 * 4 * 4 * 2, '\0'));
  EXPECT_EQ(check_volume_file(dir + "/one.nii").data_bytes, 128u);
  write_bytes(dir + "/t.mha", "ObjectType = Image\nNDims = 4\nDimSize = 4 4 4 2\nElementType = MET_SHORT\n"
                              "ElementDataFile = LOCAL\n" + std::string(256, '\0'));
  expect_refused(dir + "/t.mha", "4-D volume (4 x 4 x 4 x 2)");
  write_bytes(dir + "/t.nrrd", "NRRD0004\ntype: short\ndimension: 4\nsizes: 4 4 4 5\nencoding: raw\n\n" +
                                   std::string(640, '\0'));
  expect_refused(dir + "/t.nrrd", "4-D volume (4 x 4 x 4 x 5)");
  // Absurd headers are named, not allocated.
  write_nifti(dir + "/neg.nii", {4, -4, 4}, data);
  expect_refused(dir + "/neg.nii", "axis 2 a size of -4");
}

TEST(LibraryMessages, DamageIsAnErrorAndTheRestAreNotes) {
  EXPECT_TRUE(reports_damage("MetaImage: M_ReadElementsData: data not read completely"));
  EXPECT_TRUE(reports_damage("** ERROR: nifti_image_read: short read"));
  EXPECT_FALSE(reports_damage("qform and sform differ; using sform"));
  {
    LibraryMessages m;
    std::cerr << "MetaImage: M_ReadElementsData: data not read completely\n";
    try {
      m.take("x.mhd");
      ADD_FAILURE() << "expected the damage to be an error";
    } catch (const InputError& e) {
      EXPECT_STREQ(e.what(), "x.mhd: the reader reports damage: MetaImage: M_ReadElementsData: data not read completely");
    }
  }
  {
    LibraryMessages m;
    std::fprintf(stderr, "qform and sform differ;\n   using sform\n");
    const auto notes = m.take("x.nii");
    ASSERT_EQ(notes.size(), 2u);
    EXPECT_EQ(notes[0], "ITK: qform and sform differ;");
  }
  // After the scope, stderr is the process's own again (nothing was swallowed for good).
  LibraryMessages m;
  EXPECT_TRUE(m.take("y.nii").empty());
}

// A real file whose decoder complains on stderr (12-bit lossy JPEG, which GDCM's JPEG
// codec cannot decode) would read as garbage without a word: the complaint is the error.
TEST(VolumeIntegrity, DecoderComplaintsAreErrors) {
  MPUMESH_DATA_OR_SKIP(f, test::pydicom_file("JPEG-lossy.dcm"), "python3-pydicom");
  expect_refused(f, "the reader reports damage: ");
}

// The rows of the table in which damaged copies of the sample CT became meshes.
TEST(VolumeIntegrity, DamagedCopiesOfTheSampleCt) {
  MPUMESH_SAMPLE_CT_OR_SKIP(ct);
  const Volume v = read_volume(ct);
  const std::string dir = test::temp_dir("sample_damaged");
  write_volume(v, dir + "/ct.nii");
  write_volume(v, dir + "/ct.nii.gz");
  const uint64_t need = uint64_t(v.voxel_count()) * 2;
  expect_refused(cut(dir + "/ct.nii", dir + "/cut.nii", 9.0 / 14.0), " of " + with_thousands(need) + " bytes");
  expect_refused(cut(dir + "/ct.nii.gz", dir + "/cut.nii.gz", 3.0 / 7.5), "cut short");
  expect_refused(flip(dir + "/ct.nii.gz", dir + "/flip.nii.gz"), "corrupt");
  const std::string d = test::temp_dir("sample_mhd");
  const std::string mhd = write_mhd(v, d, false);
  cut(d + "/v.raw", d + "/v.raw", 3.0 / 14.0);
  expect_refused(mhd, "data end after");
}

}  // namespace
}  // namespace mpumesh
