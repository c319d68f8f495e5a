#include "io/vtu_arrays.h"

#include <zlib.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "common/error.h"

namespace mpumesh {
namespace {

[[noreturn]] void bad(const std::string& path, const std::string& what) {
  throw InputError(path + ": not a volume mesh mpumesh can read: " + what);
}

// The value of attribute `name` in the tag text `tag` ("" when absent).
std::string attribute(const std::string& tag, const std::string& name) {
  const std::string key = " " + name + "=\"";
  const size_t at = tag.find(key);
  if (at == std::string::npos) return "";
  const size_t start = at + key.size(), end = tag.find('"', start);
  return end == std::string::npos ? "" : tag.substr(start, end - start);
}

int base64_value(char c) {
  if (c >= 'A' && c <= 'Z') return c - 'A';
  if (c >= 'a' && c <= 'z') return c - 'a' + 26;
  if (c >= '0' && c <= '9') return c - '0' + 52;
  if (c == '+') return 62;
  if (c == '/') return 63;
  return -1;
}

// Base64 decoded group by group, so that a header and values encoded one after the other
// (each with its own padding, as VTK writes them) decode to their bytes in order.
bool base64_decode(const std::string& in, size_t begin, size_t end, std::string& out) {
  int group[4], n = 0, pad = 0;
  for (size_t i = begin; i < end; ++i) {
    const char c = in[i];
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    if (c == '=') {
      group[n++] = 0;
      ++pad;
    } else {
      const int v = base64_value(c);
      if (v < 0 || pad > 0) return false;
      group[n++] = v;
    }
    if (n < 4) continue;
    const uint32_t bits = uint32_t(group[0]) << 18 | uint32_t(group[1]) << 12 | uint32_t(group[2]) << 6 | uint32_t(group[3]);
    const char bytes[3] = {char(bits >> 16), char(bits >> 8), char(bits)};
    if (pad > 2) return false;
    out.append(bytes, size_t(3 - pad));
    n = pad = 0;
  }
  return n == 0;
}

// The size in bytes of a value of VTK type `type`, 0 when not a type read here.
size_t type_size(const std::string& type) {
  if (type == "Int8" || type == "UInt8") return 1;
  if (type == "Int16" || type == "UInt16") return 2;
  if (type == "Int32" || type == "UInt32" || type == "Float32") return 4;
  if (type == "Int64" || type == "UInt64" || type == "Float64") return 8;
  return 0;
}

template <class T>
double load(const char* p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return double(v);
}

double value_of(const std::string& type, const char* p) {
  if (type == "Int8") return load<int8_t>(p);
  if (type == "UInt8") return load<uint8_t>(p);
  if (type == "Int16") return load<int16_t>(p);
  if (type == "UInt16") return load<uint16_t>(p);
  if (type == "Int32") return load<int32_t>(p);
  if (type == "UInt32") return load<uint32_t>(p);
  if (type == "Float32") return load<float>(p);
  if (type == "Int64") return load<int64_t>(p);
  if (type == "UInt64") return load<uint64_t>(p);
  return load<double>(p);
}

}  // namespace

VtuArrays::VtuArrays(const std::string& text, std::string path) : text_(text), path_(std::move(path)) {
  const size_t at = text_.find("<VTKFile");
  if (at == std::string::npos) bad(path_, "no <VTKFile>");
  const std::string tag = text_.substr(at, text_.find('>', at) - at);
  const std::string header = attribute(tag, "header_type"), compressor = attribute(tag, "compressor");
  if (!header.empty() && header != "UInt32" && header != "UInt64") bad(path_, "header_type " + header);
  header64_ = header == "UInt64";
  if (!compressor.empty() && compressor != "vtkZLibDataCompressor")
    bad(path_, "compressor " + compressor + " (zlib is read)");
  zlib_ = !compressor.empty();
}

bool VtuArrays::has(const std::string& name) const {
  return text_.find("Name=\"" + name + "\"") != std::string::npos;
}

std::vector<double> VtuArrays::numbers(const std::string& name) const {
  size_t at;
  if (name.empty()) {
    const size_t points = text_.find("<Points>");
    if (points == std::string::npos) bad(path_, "no <Points>");
    at = text_.find("<DataArray", points);
  } else {
    const size_t named = text_.find("Name=\"" + name + "\"");
    if (named == std::string::npos) bad(path_, "no array " + name);
    at = text_.rfind("<DataArray", named);
  }
  if (at == std::string::npos) bad(path_, "array " + (name.empty() ? std::string("of the points") : name) + " has no tag");
  return decode(at);
}

std::vector<double> VtuArrays::decode(size_t tag_at) const {
  const size_t tag_end = text_.find('>', tag_at), end = text_.find("</DataArray>", tag_at);
  if (tag_end == std::string::npos || end == std::string::npos || end < tag_end) bad(path_, "a data array not closed");
  const std::string tag = text_.substr(tag_at, tag_end - tag_at), format = attribute(tag, "format"),
                    type = attribute(tag, "type"), name = attribute(tag, "Name");
  std::vector<double> out;
  if (format == "ascii") {
    const std::string body = text_.substr(tag_end + 1, end - tag_end - 1);
    const char* p = body.c_str();
    for (char* next;; p = next) {
      const double v = std::strtod(p, &next);
      if (next == p) break;
      out.push_back(v);
    }
    return out;
  }
  if (format != "binary") bad(path_, "array " + name + " is " + (format.empty() ? "appended" : format) + " (ascii and inline binary are read)");
  const size_t size = type_size(type);
  if (size == 0) bad(path_, "array " + name + " has type " + type);
  std::string bytes;
  if (!base64_decode(text_, tag_end + 1, end, bytes)) bad(path_, "array " + name + " is not base64");
  const size_t word = header64_ ? 8 : 4;
  auto header_at = [&](size_t k) -> uint64_t {
    if ((k + 1) * word > bytes.size()) bad(path_, "array " + name + "'s header cut short");
    return header64_ ? uint64_t(load<uint64_t>(bytes.data() + k * word)) : uint64_t(load<uint32_t>(bytes.data() + k * word));
  };
  std::string raw;
  if (!zlib_) {
    const uint64_t n = header_at(0);
    if (n > bytes.size() - word) bad(path_, "array " + name + " cut short");
    raw = bytes.substr(word, n);
  } else {
    const uint64_t blocks = header_at(0), block = header_at(1), last = header_at(2);
    if (blocks > bytes.size() / word) bad(path_, "array " + name + "'s header names too many blocks");
    size_t offset = (3 + blocks) * word;
    for (uint64_t b = 0; b < blocks; ++b) {
      const uint64_t packed = header_at(3 + b), full = b + 1 == blocks && last != 0 ? last : block;
      if (packed > bytes.size() - std::min<size_t>(offset, bytes.size())) bad(path_, "array " + name + " cut short");
      // zlib packs at most about 1032 bytes into one.
      if (full > 1100 * packed + 64) bad(path_, "array " + name + "'s block claims more than its data can hold");
      std::string unpacked(full, '\0');
      uLongf got = uLongf(full);
      if (uncompress(reinterpret_cast<Bytef*>(unpacked.data()), &got,
                     reinterpret_cast<const Bytef*>(bytes.data() + offset), uLong(packed)) != Z_OK ||
          got != full)
        bad(path_, "array " + name + "'s compressed data is damaged");
      raw += unpacked;
      offset += packed;
    }
  }
  if (raw.size() % size != 0) bad(path_, "array " + name + " has a partial value");
  out.reserve(raw.size() / size);
  for (size_t i = 0; i < raw.size(); i += size) out.push_back(value_of(type, raw.data() + i));
  return out;
}

}  // namespace mpumesh
