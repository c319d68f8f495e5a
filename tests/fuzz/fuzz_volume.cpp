// Volume files read whole, as `mpumesh run` reads them (core/io/volume_io.h): the
// integrity check in front of ITK's NIfTI, NRRD and MetaImage readers, then ITK and GDCM
// themselves in the isolated reader's child (core/io/isolated_read.h), whose crash or hang
// must come back as an InputError. The first byte picks the format (.nii, .nii.gz, .nrrd,
// .mha, .dcm), the rest is the file, written to a temporary path. For .nii.gz the rest is
// gzipped here unless it starts with the gzip magic, so that the fuzzer explores the
// header rather than the deflate stream. scripts/fuzz.sh seeds the DICOM inputs from
// pydicom's test files and sets a short MPUMESH_READER_TIMEOUT.
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "fuzz_common.h"
#include "io/targz.h"
#include "io/volume_io.h"

namespace {

void read_as_file(const std::string& bytes) {
  if (bytes.empty()) return;
  static const char* const kExt[] = {".nii", ".nii.gz", ".nrrd", ".mha", ".dcm"};
  const int format = uint8_t(bytes[0]) % 5;
  std::string file = bytes.substr(1);
  if (format == 1 && !(file.size() >= 2 && uint8_t(file[0]) == 0x1f && uint8_t(file[1]) == 0x8b))
    file = mpumesh::gzip(file);
  const std::string path = "/tmp/mpumesh_fuzz_volume_" + std::to_string(getpid()) + kExt[format];
  std::ofstream(path, std::ios::binary) << file;
  mpumesh::read_volume(path);
}

}  // namespace

MPUMESH_FUZZ_TARGET(read_as_file(bytes))
