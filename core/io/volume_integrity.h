// The check every volume file passes before ITK reads it: the header is parsed here, the
// number of data bytes it promises is computed, and the bytes are counted: a raw payload
// must be as long as the header says, a compressed one must inflate to that length and
// end with its checksum intact (gzip CRC-32 or zlib Adler-32). ITK reports neither a
// short payload nor a failed checksum as an error (it fills with what it read and warns
// on stderr, or not at all), so without this a cut download became half a mesh.
// A volume of more than three dimensions (a time series) is refused with its sizes.
// Formats: NIfTI-1/-2 (.nii, .nii.gz), NRRD (.nrrd, .nhdr; raw and gzip encodings),
// MetaImage (.mha inline, .mhd detached; raw and zlib-compressed).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace mpumesh {

// What the header promised and what was found, for tests and the JSON report.
struct VolumeFileLayout {
  std::vector<int64_t> dims;  // as many as the file has
  int bytes_per_voxel = 0;    // times components
  uint64_t data_bytes = 0;    // dims product x bytes_per_voxel
  bool compressed = false;
};

// Throws InputError naming `path` and the problem ("data end after 2,999,808 of
// 14,155,776 bytes", "gzip stream corrupt (incorrect data check)", "4-D volume ...").
// Extensions it does not know pass unchecked (DICOM and .inv3 have readers of their own).
VolumeFileLayout check_volume_file(const std::string& path);

// "14,155,776": byte counts in messages.
std::string with_thousands(uint64_t n);

}  // namespace mpumesh
