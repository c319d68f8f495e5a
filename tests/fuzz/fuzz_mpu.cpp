// .mpu surface files (core/mpu/mpu_io.cpp). Each input is parsed as it is, then with its
// trailing CRC-32 recomputed, so that mutations reach the header, leaf and grid checks
// behind the CRC.
#include <zlib.h>

#include <cstring>

#include "fuzz_common.h"
#include "mpu/mpu_io.h"

MPUMESH_FUZZ_TARGET({
  try {
    mpumesh::mpu::parse_mpu(bytes, "fuzz.mpu");
  } catch (const mpumesh::InputError&) {
  }
  if (bytes.size() < 4) return 0;
  std::string fixed = bytes;
  const uint32_t crc = uint32_t(crc32(crc32(0L, Z_NULL, 0), reinterpret_cast<const Bytef*>(fixed.data()),
                                      uInt(fixed.size() - 4)));
  std::memcpy(fixed.data() + fixed.size() - 4, &crc, 4);
  mpumesh::mpu::parse_mpu(fixed, "fuzz.mpu");
})
