#include "io/targz.h"

#include <libdeflate.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <memory>
#include <new>
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
  // libdeflate inflates a whole member in one call, about twice as fast as zlib's
  // streaming inflate, and checks each
  // member's CRC and size. The output starts at the size the last member's trailer gives
  // (ISIZE, the size modulo 2^32: a hint only, held to deflate's largest ratio, 1032:1,
  // so that a forged trailer cannot make it large) and doubles while a member does not
  // fit, that member then inflated again.
  uint32_t isize = 0;
  std::memcpy(&isize, gz.data() + gz.size() - 4, 4);  // little-endian, as gzip stores it
  const uint64_t hint = std::min<uint64_t>({isize, 1032 * uint64_t(gz.size()), max_bytes + 1});
  std::string out(size_t(std::max<uint64_t>(hint, 1 << 16)), '\0');
  const std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> d(
      libdeflate_alloc_decompressor(), libdeflate_free_decompressor);
  if (!d) throw std::bad_alloc();
  size_t in_at = 0, used = 0;
  while (in_at < gz.size()) {  // one member a pass
    size_t in_used = 0, out_made = 0;
    const libdeflate_result rc = libdeflate_gzip_decompress_ex(d.get(), gz.data() + in_at, gz.size() - in_at,
                                                               out.data() + used, out.size() - used, &in_used, &out_made);
    if (rc == LIBDEFLATE_INSUFFICIENT_SPACE) {
      if (out.size() > max_bytes)
        throw InputError(name + ": unpacks to more than " + std::to_string(max_bytes >> 20) + " MiB");
      out.resize(size_t(std::min<uint64_t>(2 * uint64_t(out.size()), max_bytes + 1)));
      continue;
    }
    if (rc != LIBDEFLATE_SUCCESS) throw InputError(name + ": corrupt or truncated gzip data");
    in_at += in_used;
    used += out_made;
    if (used > max_bytes) throw InputError(name + ": unpacks to more than " + std::to_string(max_bytes >> 20) + " MiB");
  }
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
