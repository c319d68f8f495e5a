#include "io/dicom_pixel_check.h"

#include <algorithm>
#include <cstdint>

#include "common/error.h"
#include "io/read_file.h"

namespace mpumesh {
namespace {

bool is_pixel_vr(const char* p) {
  return p[0] == 'O' && (p[1] == 'B' || p[1] == 'W') && p[2] == 0 && p[3] == 0;
}

uint32_t read_u32(const char* p, bool big) {
  const auto* u = reinterpret_cast<const unsigned char*>(p);
  return big ? (uint32_t(u[0]) << 24 | uint32_t(u[1]) << 16 | uint32_t(u[2]) << 8 | u[3])
             : (uint32_t(u[3]) << 24 | uint32_t(u[2]) << 16 | uint32_t(u[1]) << 8 | u[0]);
}

// The first little-endian US element (group, element) with its value, explicit or implicit
// VR; 0 when absent. Group 0028 precedes any icon image's (inside group 0088).
uint32_t find_us(const std::string& b, uint16_t group, uint16_t element, size_t before) {
  const char tag[4] = {char(group & 0xff), char(group >> 8), char(element & 0xff), char(element >> 8)};
  for (size_t at = b.find(std::string(tag, 4)); at != std::string::npos && at < before;
       at = b.find(std::string(tag, 4), at + 1)) {
    if (at + 10 > b.size()) break;
    const char* p = b.data() + at + 4;
    if (p[0] == 'U' && p[1] == 'S' && p[2] == 2 && p[3] == 0) return uint8_t(p[4]) | uint32_t(uint8_t(p[5])) << 8;
    if (p[0] == 2 && p[1] == 0 && p[2] == 0 && p[3] == 0) return uint8_t(p[4]) | uint32_t(uint8_t(p[5])) << 8;
  }
  return 0;
}

}  // namespace

void check_dicom_pixel_data(const std::string& b, const std::string& name) {
  // The last header of (7FE0,0010) that parses is the image's pixel data (icon images in
  // sequences come before it). Little-endian tag bytes E0 7F 10 00, big-endian 7F E0 00 10.
  size_t value_start = 0;
  uint64_t declared = 0;
  bool found = false;
  for (bool big : {false, true}) {
    const std::string tag = big ? std::string("\x7f\xe0\x00\x10", 4) : std::string("\xe0\x7f\x10\x00", 4);
    for (size_t at = b.find(tag); at != std::string::npos; at = b.find(tag, at + 1)) {
      if (at + 8 > b.size()) break;
      size_t start;
      uint32_t len;
      if (at + 12 <= b.size() && is_pixel_vr(b.data() + at + 4)) {  // explicit VR
        start = at + 12;
        len = read_u32(b.data() + at + 8, big);
      } else if (!big) {  // implicit VR little endian
        start = at + 8;
        len = read_u32(b.data() + at + 4, false);
        if (len % 2 != 0 && len != 0xFFFFFFFFu) continue;
      } else {
        continue;
      }
      // A match inside the value of the pixel data already found is payload, not a header.
      if (found && declared != 0xFFFFFFFFu && at < value_start + declared) continue;
      value_start = start;
      declared = len;
      found = true;
    }
  }
  if (!found || declared == 0xFFFFFFFFu) return;  // none, or encapsulated (compressed)
  if (value_start + declared > b.size())
    throw InputError(name + ": truncated DICOM: the pixel data declares " + std::to_string(declared) +
                     " bytes but the file holds only " + std::to_string(b.size() - value_start));
  // Native pixel data shorter than one frame of Rows x Columns x samples x bytes: the
  // element was written short (ITK would read the rest as zeros, or garbage).
  const uint64_t rows = find_us(b, 0x0028, 0x0010, value_start), cols = find_us(b, 0x0028, 0x0011, value_start);
  const uint64_t bits = find_us(b, 0x0028, 0x0100, value_start);
  const uint64_t spp = std::max<uint64_t>(1, find_us(b, 0x0028, 0x0002, value_start));
  // 1-bit pixels (a segmentation) are packed; 4:2:2 colour holds two samples a pixel, not three.
  const std::string head = b.substr(0, value_start);
  const bool ybr422 = head.find("YBR_FULL_422") != std::string::npos || head.find("YBR_PARTIAL_422") != std::string::npos;
  const uint64_t frame = (rows * cols * (ybr422 && spp == 3 ? 2 : spp) * bits + 7) / 8;
  if (rows && cols && bits && declared < frame)
    throw InputError(name + ": truncated DICOM: the pixel data holds " + std::to_string(declared) + " bytes, but " +
                     std::to_string(rows) + " x " + std::to_string(cols) + " pixels of " + std::to_string(bits) +
                     " bits need " + std::to_string(frame));
}

void check_dicom_pixel_data_file(const std::string& path) { check_dicom_pixel_data(read_file(path), path); }

}  // namespace mpumesh
