// InVesalius projects (core/io/inv3_reader.cpp, targz.cpp): the input is the tar archive,
// gzipped here so that the fuzzer explores the tar, the plist, the matrix and the masks
// rather than the deflate stream (which zlib checks); inputs starting with the gzip magic
// go in as they are. Each input is read as a volume and as its masks' label map.
#include "fuzz_common.h"
#include "io/targz.h"
#include "io/volume_io.h"

MPUMESH_FUZZ_TARGET({
  const bool gz = bytes.size() >= 2 && uint8_t(bytes[0]) == 0x1f && uint8_t(bytes[1]) == 0x8b;
  const std::string archive = gz ? bytes : mpumesh::gzip(bytes);
  try {
    mpumesh::parse_inv3(archive, "fuzz.inv3");
  } catch (const mpumesh::InputError&) {
  }
  mpumesh::parse_inv3_masks(archive, "fuzz.inv3");
})
