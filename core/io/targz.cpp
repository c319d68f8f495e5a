#include "io/targz.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "common/error.h"

namespace mpumesh {

std::string gzip(const std::string& in) {
  z_stream z{};
  if (deflateInit2(&z, 1, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK) throw std::runtime_error("deflateInit2");
  std::string out(deflateBound(&z, uLong(in.size())) + 32, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in.data()));
  z.avail_in = uInt(in.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = uInt(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

std::string gunzip(const std::string& gz, const std::string& name, uint64_t max_bytes) {
  if (gz.size() < 18 || uint8_t(gz[0]) != 0x1f || uint8_t(gz[1]) != 0x8b)
    throw InputError(name + ": not a gzip-compressed file (wrong magic)");
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK) throw InputError(name + ": zlib initialisation failed");
  zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz.data()));
  zs.avail_in = uInt(gz.size());
  // Inflated in place into the output, which starts at the size the last member's trailer
  // gives (ISIZE, the size modulo 2^32: a hint only, held to deflate's largest ratio,
  // 1032:1, so that a forged trailer cannot make it large) and doubles when that is short.
  uint32_t isize = 0;
  std::memcpy(&isize, gz.data() + gz.size() - 4, 4);  // little-endian, as gzip stores it
  const uint64_t hint = std::min<uint64_t>({isize, 1032 * uint64_t(gz.size()), max_bytes + 1});
  std::string out(size_t(std::max<uint64_t>(hint, 1 << 16)), '\0');
  size_t used = 0;
  int rc = Z_OK;
  while (true) {
    if (used == out.size()) out.resize(size_t(std::min<uint64_t>(2 * out.size(), max_bytes + 1)));
    zs.next_out = reinterpret_cast<Bytef*>(out.data() + used);
    zs.avail_out = uInt(std::min<size_t>(out.size() - used, 1u << 30));
    const size_t room = zs.avail_out;
    rc = inflate(&zs, Z_NO_FLUSH);
    if (rc != Z_OK && rc != Z_STREAM_END && rc != Z_BUF_ERROR) break;
    used += room - zs.avail_out;
    if (used > max_bytes) {
      inflateEnd(&zs);
      throw InputError(name + ": unpacks to more than " + std::to_string(max_bytes >> 20) + " MiB");
    }
    if (rc == Z_BUF_ERROR) {
      if (zs.avail_out == 0) continue;  // the output was full: it grows
      break;                            // the input ended within a member
    }
    if (rc == Z_STREAM_END) {
      if (zs.avail_in == 0) break;
      inflateReset(&zs);  // another gzip member follows
    }
  }
  inflateEnd(&zs);
  if (rc != Z_STREAM_END) throw InputError(name + ": corrupt or truncated gzip data");
  out.resize(used);
  return out;
}

std::map<std::string, std::string_view> untar(const std::string& tar, const std::string& name) {
  std::map<std::string, std::string_view> files;
  size_t at = 0;
  while (at + 512 <= tar.size()) {
    const char* h = tar.data() + at;
    if (h[0] == '\0') break;  // end-of-archive block
    if (std::memcmp(h + 257, "ustar", 5) != 0)
      throw InputError(name + ": not a tar archive (no ustar header at byte " + std::to_string(at) + ")");
    std::string fname(h, strnlen(h, 100));
    std::string prefix(h + 345, strnlen(h + 345, 155));
    if (!prefix.empty()) fname = prefix + "/" + fname;
    uint64_t size = 0;
    for (int i = 124; i < 136 && h[i]; ++i) {
      if (h[i] == ' ') continue;
      if (h[i] < '0' || h[i] > '7') throw InputError(name + ": corrupt tar header (size field)");
      size = size * 8 + uint64_t(h[i] - '0');
    }
    const char type = h[156];
    at += 512;
    if (size > tar.size() - at) throw InputError(name + ": truncated tar archive ('" + fname + "' is cut short)");
    if (type == '0' || type == '\0') {
      auto slash = fname.find_last_of('/');
      files[slash == std::string::npos ? fname : fname.substr(slash + 1)] = std::string_view(tar).substr(at, size);
    }
    at += (size + 511) / 512 * 512;
  }
  return files;
}

}  // namespace mpumesh
