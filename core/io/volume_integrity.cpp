#include "io/volume_integrity.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "common/error.h"
#include "common/text.h"

namespace mpumesh {
namespace {

namespace fs = std::filesystem;

constexpr uint64_t kMaxDataBytes = uint64_t(1) << 40;  // a header promising more is not a scan

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r\n");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r\n") - a + 1);
}

uint64_t file_size_of(const std::string& path, const std::string& name) {
  std::error_code ec;
  const auto n = fs::file_size(path, ec);
  if (ec) throw InputError(name + ": cannot read the data file " + path + " (" + ec.message() + ")");
  return n;
}

std::string read_prefix(const std::string& path, size_t max_bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the file");
  std::string s(max_bytes, '\0');
  in.read(s.data(), std::streamsize(max_bytes));
  s.resize(size_t(in.gcount()));
  return s;
}

// The data's promised size: the product of the sizes times the voxel's bytes, with the
// sizes checked on the way (a size of 0, a negative one, an overflowing product).
VolumeFileLayout layout_of(const std::string& name, const std::vector<int64_t>& dims, int bytes_per_voxel) {
  VolumeFileLayout l;
  l.dims = dims;
  l.bytes_per_voxel = bytes_per_voxel;
  if (bytes_per_voxel <= 0) throw InputError(name + ": the header gives no usable voxel type");
  uint64_t n = uint64_t(bytes_per_voxel);
  for (size_t a = 0; a < dims.size(); ++a) {
    if (dims[a] < 1)
      throw InputError(name + ": the header gives axis " + std::to_string(a + 1) + " a size of " +
                       std::to_string(dims[a]));
    if (uint64_t(dims[a]) > kMaxDataBytes / n)
      throw InputError(name + ": the header promises more than 1 TiB of voxels");
    n *= uint64_t(dims[a]);
  }
  l.data_bytes = n;
  return l;
}

std::string dims_text(const std::vector<int64_t>& dims) {
  std::string s;
  for (size_t a = 0; a < dims.size(); ++a) s += (a ? " x " : "") + std::to_string(dims[a]);
  return s;
}

// A volume with a fourth axis longer than one (a time series, diffusion directions) is
// not one surface: refuse it rather than mesh its first frame without saying so.
void refuse_beyond_3d(const std::string& name, const std::vector<int64_t>& spatial) {
  for (size_t a = 3; a < spatial.size(); ++a)
    if (spatial[a] > 1)
      throw InputError(name + ": a " + std::to_string(spatial.size()) + "-D volume (" + dims_text(spatial) +
                       "); mpumesh meshes one 3-D volume: extract the frame you want first");
}

void require_bytes(const std::string& name, uint64_t have, uint64_t need, const char* why) {
  if (have < need)
    throw InputError(name + ": data end after " + with_thousands(have) + " of " + with_thousands(need) + " bytes" +
                     why);
}

// Inflates a gzip or zlib stream (told apart by its header) from `offset` to its end,
// counting the bytes and keeping the first `keep` of them. Concatenated gzip members are
// one stream, as gzip(1) reads them. A stream whose check fails is "corrupt"; one that
// stops before its end marker is cut short: `complete` is false and the count is what
// came out before the cut.
struct Inflated {
  uint64_t bytes = 0;
  std::string head;
  bool complete = false;
};

Inflated inflate_file(const std::string& path, uint64_t offset, size_t keep, const std::string& name) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(name + ": cannot open " + path);
  in.seekg(std::streamoff(offset));
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK) throw InputError(name + ": zlib initialisation failed");
  Inflated r;
  std::vector<char> src(1 << 16), dst(1 << 16);
  bool member_start = true;
  int rc = Z_OK;
  while (true) {
    if (zs.avail_in == 0) {
      in.read(src.data(), std::streamsize(src.size()));
      zs.next_in = reinterpret_cast<Bytef*>(src.data());
      zs.avail_in = uInt(in.gcount());
      if (zs.avail_in == 0) break;  // the input ends before the stream does
    }
    if (member_start && r.bytes > 0 && uint8_t(*zs.next_in) != 0x1f) {
      r.complete = true;  // bytes after the last gzip member: not part of the stream
      break;
    }
    member_start = false;
    zs.next_out = reinterpret_cast<Bytef*>(dst.data());
    zs.avail_out = uInt(dst.size());
    rc = inflate(&zs, Z_NO_FLUSH);
    const size_t got = dst.size() - zs.avail_out;
    if (r.head.size() < keep) r.head.append(dst.data(), std::min(got, keep - r.head.size()));
    r.bytes += got;
    if (rc == Z_STREAM_END) {
      r.complete = true;
      if (zs.avail_in == 0 && in.peek() == std::char_traits<char>::eof()) break;
      inflateReset(&zs);
      member_start = true;
      continue;
    }
    if (rc == Z_NEED_DICT || rc == Z_DATA_ERROR || rc == Z_MEM_ERROR) {
      const std::string why = zs.msg ? zs.msg : "invalid deflate data";
      inflateEnd(&zs);
      throw InputError(name + ": compressed data corrupt after " + with_thousands(r.bytes) + " bytes (" + why + ")");
    }
    if (rc == Z_BUF_ERROR && zs.avail_in != 0) {
      inflateEnd(&zs);
      throw InputError(name + ": compressed data corrupt (no progress)");
    }
    r.complete = false;
  }
  inflateEnd(&zs);
  return r;
}

void check_inflated(const std::string& name, const Inflated& z, uint64_t need, uint64_t skip = 0) {
  const uint64_t have = z.bytes > skip ? z.bytes - skip : 0;
  if (!z.complete) {
    require_bytes(name, have, need, " (the compressed stream is cut short)");
    throw InputError(name + ": compressed stream cut short before its end and checksum");
  }
  require_bytes(name, have, need, "");
}

// ---- NIfTI-1 and NIfTI-2 ----------------------------------------------------------

template <class T>
T get(const std::string& h, size_t at, bool swap) {
  T v;
  std::memcpy(&v, h.data() + at, sizeof v);
  if (swap) {
    char b[sizeof v];
    std::memcpy(b, &v, sizeof v);
    std::reverse(b, b + sizeof v);
    std::memcpy(&v, b, sizeof v);
  }
  return v;
}

struct NiftiHeader {
  VolumeFileLayout layout;
  uint64_t data_offset = 0;
};

NiftiHeader parse_nifti(const std::string& h, const std::string& name) {
  if (h.size() < 348)
    throw InputError(name + ": the NIfTI header is cut short (" + std::to_string(h.size()) + " of 348 bytes)");
  const int32_t size_le = get<int32_t>(h, 0, false), size_be = get<int32_t>(h, 0, true);
  const bool swap = size_le != 348 && size_le != 540;
  const int32_t hdr = swap ? size_be : size_le;
  if (hdr != 348 && hdr != 540) throw InputError(name + ": not a NIfTI file (header size field " + std::to_string(size_le) + ")");
  if (hdr == 540 && h.size() < 540)
    throw InputError(name + ": the NIfTI-2 header is cut short (" + std::to_string(h.size()) + " of 540 bytes)");
  std::vector<int64_t> dim(8);
  int bitpix;
  double vox_offset;
  if (hdr == 348) {
    for (size_t i = 0; i < 8; ++i) dim[i] = get<int16_t>(h, 40 + 2 * i, swap);
    bitpix = get<int16_t>(h, 72, swap);
    vox_offset = get<float>(h, 108, swap);
  } else {
    for (size_t i = 0; i < 8; ++i) dim[i] = get<int64_t>(h, 16 + 8 * i, swap);
    bitpix = get<int16_t>(h, 14, swap);
    vox_offset = double(get<int64_t>(h, 168, swap));
  }
  if (dim[0] < 1 || dim[0] > 7)
    throw InputError(name + ": the NIfTI header gives " + std::to_string(dim[0]) + " dimensions (1 to 7 allowed)");
  if (bitpix <= 0 || bitpix % 8 != 0 || bitpix > 256)
    throw InputError(name + ": the NIfTI header gives " + std::to_string(bitpix) + " bits per voxel");
  if (!(vox_offset >= 0 && vox_offset < double(kMaxDataBytes)))
    throw InputError(name + ": the NIfTI header gives a data offset of " + std::to_string(vox_offset));
  NiftiHeader r;
  r.layout = layout_of(name, std::vector<int64_t>(dim.begin() + 1, dim.begin() + 1 + dim[0]), bitpix / 8);
  r.data_offset = std::max<uint64_t>(uint64_t(vox_offset), uint64_t(hdr));
  refuse_beyond_3d(name, r.layout.dims);
  return r;
}

VolumeFileLayout check_nifti(const std::string& path, bool gz) {
  if (!gz) {
    const NiftiHeader n = parse_nifti(read_prefix(path, 540), path);
    const uint64_t size = file_size_of(path, path);
    require_bytes(path, size > n.data_offset ? size - n.data_offset : 0, n.layout.data_bytes, "");
    return n.layout;
  }
  const Inflated z = inflate_file(path, 0, 540, path);
  NiftiHeader n = parse_nifti(z.head, path);
  check_inflated(path, z, n.layout.data_bytes, n.data_offset);
  n.layout.compressed = true;
  return n.layout;
}

// ---- NRRD and MetaImage: text headers -----------------------------------------------

int bytes_of_nrrd_type(std::string t) {
  t = lower_case(trim(t));
  if (t == "block") return 0;
  if (t == "float") return 4;
  if (t == "double") return 8;
  if (t.find("char") != std::string::npos || t.find("int8") != std::string::npos) return 1;
  if (t.find("short") != std::string::npos || t.find("16") != std::string::npos) return 2;
  if (t.find("long") != std::string::npos || t.find("64") != std::string::npos) return 8;
  if (t.find("int") != std::string::npos || t.find("32") != std::string::npos) return 4;
  return 0;
}

int bytes_of_meta_type(std::string t) {
  t = trim(t);
  if (t.ends_with("_ARRAY")) t.resize(t.size() - 6);
  static const std::map<std::string, int> sizes = {
      {"MET_CHAR", 1},  {"MET_UCHAR", 1},     {"MET_SHORT", 2},      {"MET_USHORT", 2}, {"MET_INT", 4},
      {"MET_UINT", 4},  {"MET_LONG", 4},      {"MET_ULONG", 4},      {"MET_FLOAT", 4},  {"MET_DOUBLE", 8},
      {"MET_LONG_LONG", 8}, {"MET_ULONG_LONG", 8}};
  const auto it = sizes.find(t);
  return it == sizes.end() ? 0 : it->second;
}

std::vector<int64_t> parse_sizes(const std::string& s, const std::string& name, const char* field) {
  std::vector<int64_t> out;
  std::istringstream is(s);
  std::string tok;
  while (is >> tok) {
    char* end = nullptr;
    const long long v = std::strtoll(tok.c_str(), &end, 10);
    if (end == tok.c_str() || *end != '\0')
      throw InputError(name + ": the header's " + field + " '" + trim(s) + "' is not a list of sizes");
    out.push_back(v);
  }
  if (out.empty()) throw InputError(name + ": the header's " + field + " is empty");
  return out;
}

// Reads header lines up to (not including) the blank line or the line that `last`
// accepts; returns the fields and sets `data_at` to the byte after the header.
template <class Split>
std::map<std::string, std::string> read_text_header(const std::string& path, const std::string& name, Split split,
                                                    bool stop_at_blank, const std::string& last_key,
                                                    uint64_t& data_at) {
  const std::string text = read_prefix(path, 1 << 20);
  std::map<std::string, std::string> fields;
  size_t at = 0;
  while (true) {
    const size_t nl = text.find('\n', at);
    if (nl == std::string::npos) throw InputError(name + ": the header is cut short (no end of header)");
    const std::string line = text.substr(at, nl - at);
    at = nl + 1;
    if (stop_at_blank && trim(line).empty()) break;
    std::string key, value;
    if (!split(line, key, value)) continue;
    fields[key] = value;
    if (!last_key.empty() && key == last_key) break;
  }
  data_at = at;
  return fields;
}

std::string beside(const std::string& header, const std::string& file) {
  const fs::path p(file);
  return p.is_absolute() ? file : (fs::path(header).parent_path() / p).string();
}

// A detached data file named as a pattern or a list is read by ITK slice by slice; it is
// left to ITK's own checks.
bool is_file_list(const std::string& v) {
  return v.find('%') != std::string::npos || v.rfind("LIST", 0) == 0 || v.find(' ') != std::string::npos;
}

uint64_t skip_lines(const std::string& path, uint64_t from, int64_t lines) {
  std::ifstream in(path, std::ios::binary);
  in.seekg(std::streamoff(from));
  uint64_t at = from;
  for (int64_t l = 0; l < lines && in; ++l) {
    std::string skipped;
    std::getline(in, skipped);
    at += skipped.size() + 1;
  }
  return at;
}

VolumeFileLayout check_nrrd(const std::string& path) {
  if (read_prefix(path, 7) != "NRRD000") throw InputError(path + ": not a NRRD file (no NRRD000 magic)");
  uint64_t data_at = 0;
  auto split = [](const std::string& line, std::string& k, std::string& v) {
    if (line.empty() || line[0] == '#' || line.find(":=") != std::string::npos) return false;
    const auto c = line.find(": ");
    if (c == std::string::npos) return false;
    k = lower_case(trim(line.substr(0, c)));
    k.erase(std::remove(k.begin(), k.end(), ' '), k.end());
    v = trim(line.substr(c + 2));
    return true;
  };
  auto f = read_text_header(path, path, split, true, "", data_at);
  if (!f.count("sizes") || !f.count("type") || !f.count("encoding"))
    throw InputError(path + ": the NRRD header lacks sizes, type or encoding");
  std::vector<int64_t> sizes = parse_sizes(f["sizes"], path, "sizes");
  int bytes = bytes_of_nrrd_type(f["type"]);
  if (bytes == 0) throw InputError(path + ": NRRD type '" + f["type"] + "' is not a voxel type");
  // A leading non-spatial axis (kinds: vector, RGB-color, ...) holds components.
  std::vector<int64_t> spatial = sizes;
  if (f.count("kinds")) {
    std::istringstream is(f["kinds"]);
    std::string first;
    is >> first;
    first = lower_case(first);
    if (!first.empty() && first != "domain" && first != "space" && first != "none" && first != "???" &&
        first != "time" && spatial.size() > 1) {
      bytes *= int(std::min<int64_t>(std::max<int64_t>(spatial[0], 1), 1 << 16));
      spatial.erase(spatial.begin());
    }
  }
  VolumeFileLayout l = layout_of(path, spatial, bytes);
  refuse_beyond_3d(path, spatial);
  std::string data = path;
  const std::string df = f.count("datafile") ? f["datafile"] : "";  // "data file" with its space dropped
  if (!df.empty()) {
    if (is_file_list(df)) return l;
    data = beside(path, df);
    data_at = 0;
  }
  const int64_t line_skip = f.count("lineskip") ? std::atoll(f["lineskip"].c_str()) : 0;
  const int64_t byte_skip = f.count("byteskip") ? std::atoll(f["byteskip"].c_str()) : 0;
  if (line_skip > 0) data_at = skip_lines(data, data_at, line_skip);
  const std::string enc = lower_case(f["encoding"]);
  if (enc == "raw") {
    const uint64_t size = file_size_of(data, path);
    if (byte_skip == -1) require_bytes(path, size > data_at ? size - data_at : 0, l.data_bytes, "");
    else require_bytes(path, size > data_at + uint64_t(std::max<int64_t>(byte_skip, 0)) ?
                                 size - data_at - uint64_t(std::max<int64_t>(byte_skip, 0)) : 0,
                       l.data_bytes, "");
  } else if (enc == "gzip" || enc == "gz") {
    l.compressed = true;
    check_inflated(path, inflate_file(data, data_at, 0, path), l.data_bytes, uint64_t(std::max<int64_t>(byte_skip, 0)));
  }
  // ascii and hex: ITK's NRRD reader parses every value and fails on a short file.
  return l;
}

VolumeFileLayout check_metaimage(const std::string& path) {
  uint64_t data_at = 0;
  auto split = [](const std::string& line, std::string& k, std::string& v) {
    const auto eq = line.find('=');
    if (eq == std::string::npos) return false;
    k = trim(line.substr(0, eq));
    v = trim(line.substr(eq + 1));
    return !k.empty();
  };
  {
    const std::string first = read_prefix(path, 256);
    if (first.substr(0, first.find('\n')).find('=') == std::string::npos)
      throw InputError(path + ": not a MetaImage file (no 'Key = Value' header)");
  }
  auto f = read_text_header(path, path, split, false, "ElementDataFile", data_at);
  if (!f.count("ElementDataFile")) throw InputError(path + ": the MetaImage header has no ElementDataFile");
  if (!f.count("DimSize") || !f.count("ElementType"))
    throw InputError(path + ": the MetaImage header lacks DimSize or ElementType");
  const std::vector<int64_t> dims = parse_sizes(f["DimSize"], path, "DimSize");
  int bytes = bytes_of_meta_type(f["ElementType"]);
  if (bytes == 0) throw InputError(path + ": MetaImage ElementType '" + f["ElementType"] + "' is not a voxel type");
  if (f.count("ElementNumberOfChannels")) {
    const long long c = std::atoll(f["ElementNumberOfChannels"].c_str());
    if (c < 1 || c > 1 << 16) throw InputError(path + ": ElementNumberOfChannels " + f["ElementNumberOfChannels"]);
    bytes *= int(c);
  }
  VolumeFileLayout l = layout_of(path, dims, bytes);
  refuse_beyond_3d(path, dims);
  const std::string df = f["ElementDataFile"];
  std::string data = path;
  if (df != "LOCAL" && df != "Local" && df != "local") {
    if (is_file_list(df)) return l;
    data = beside(path, df);
    data_at = 0;
  }
  const bool compressed = f.count("CompressedData") && lower_case(f["CompressedData"]) == "true";
  if (compressed) {
    l.compressed = true;
    check_inflated(path, inflate_file(data, data_at, 0, path), l.data_bytes);
    return l;
  }
  const uint64_t size = file_size_of(data, path);
  const long long header_size = f.count("HeaderSize") ? std::atoll(f["HeaderSize"].c_str()) : 0;
  if (header_size > 0) data_at += uint64_t(header_size);
  require_bytes(path, size > data_at ? size - data_at : 0, l.data_bytes, "");
  return l;
}

}  // namespace

std::string with_thousands(uint64_t n) {
  const std::string digits = std::to_string(n);
  std::string s;
  for (size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) s += ',';
    s += digits[i];
  }
  return s;
}

VolumeFileLayout check_volume_file(const std::string& path) {
  const std::string p = lower_case(path);
  if (p.ends_with(".nii")) return check_nifti(path, false);
  if (p.ends_with(".nii.gz")) return check_nifti(path, true);
  if (p.ends_with(".nrrd") || p.ends_with(".nhdr")) return check_nrrd(path);
  if (p.ends_with(".mha") || p.ends_with(".mhd")) return check_metaimage(path);
  return {};
}

}  // namespace mpumesh
