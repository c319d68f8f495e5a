// Volume files' integrity check (core/io/volume_integrity.cpp), the gate in front of
// ITK's NIfTI, NRRD and MetaImage readers: the first byte picks the format (.nii,
// .nii.gz, .nrrd, .mha), the rest is the file, written to a temporary path since the
// check reads files (a detached header may name another one). For .nii.gz the rest is
// gzipped here unless it starts with the gzip magic, so that the fuzzer explores the
// header rather than the deflate stream.
#include <unistd.h>

#include <cstdio>
#include <fstream>

#include "fuzz_common.h"
#include "io/targz.h"
#include "io/volume_integrity.h"

namespace {

void check_as_file(const std::string& bytes) {
  if (bytes.empty()) return;
  static const char* const kExt[] = {".nii", ".nii.gz", ".nrrd", ".mha"};
  const int format = uint8_t(bytes[0]) % 4;
  std::string file = bytes.substr(1);
  if (format == 1 && !(file.size() >= 2 && uint8_t(file[0]) == 0x1f && uint8_t(file[1]) == 0x8b))
    file = mpumesh::gzip(file);
  const std::string path = "/tmp/mpumesh_fuzz_volume_" + std::to_string(getpid()) + kExt[format];
  std::ofstream(path, std::ios::binary) << file;
  mpumesh::check_volume_file(path);
}

}  // namespace

MPUMESH_FUZZ_TARGET(check_as_file(bytes))
