#include "mpu/mpu_io.h"

#include <zlib.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <fstream>

#include "common/error.h"
#include "io/atomic_file.h"
#include "io/read_file.h"

namespace mpumesh::mpu {
namespace {

static_assert(std::endian::native == std::endian::little, "the .mpu reader and writer assume a little-endian host");

constexpr char kMagic[8] = {'\x89', 'M', 'P', 'U', '\r', '\n', '\x1a', '\n'};
constexpr size_t kHeaderBytes = 120;
// A leaf's record: 13 doubles of centre, radius and frame, the coefficients (19 in
// version 1, 22 since version 2), and 8 bytes of kind, degree, depth and count.
constexpr size_t leaf_bytes(uint32_t version) { return (13 + coefficients_in(version)) * 8 + 8; }

class Writer {
 public:
  template <class T>
  void put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out.append(b, sizeof(T));
  }
  std::string out;
};

class Reader {
 public:
  Reader(const std::string& b, const std::string& name) : b_(b), name_(name) {}
  template <class T>
  T get() {
    if (pos_ + sizeof(T) > b_.size()) fail("truncated at byte " + std::to_string(b_.size()));
    T v;
    std::memcpy(&v, b_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    return v;
  }
  double finite() {
    const double v = get<double>();
    if (!std::isfinite(v)) fail("a non-finite number at byte " + std::to_string(pos_ - 8));
    return v;
  }
  [[noreturn]] void fail(const std::string& what) const { throw InputError(name_ + ": not a valid .mpu file: " + what); }

 private:
  const std::string& b_;
  const std::string& name_;
  size_t pos_ = 0;
};

uint32_t crc32_of(const char* data, size_t n) {
  uLong crc = crc32(0L, Z_NULL, 0);
  while (n > 0) {
    const uInt chunk = uInt(std::min<size_t>(n, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(data), chunk);
    data += chunk;
    n -= chunk;
  }
  return uint32_t(crc);
}

}  // namespace

std::string serialize_mpu(const MpuSurface& s) {
  const auto& g = s.grid;
  const size_t cells = size_t(g.dims[0]) * g.dims[1] * g.dims[2];
  MPUMESH_ASSERT(g.offsets.size() == cells + 1, "lookup grid offsets");
  Writer w;
  w.out.reserve(kHeaderBytes + s.leaves.size() * leaf_bytes(kMpuFileVersion) + 4 * (cells + 1 + g.leaf_ids.size()) + 4);
  w.out.append(kMagic, 8);
  w.put<uint32_t>(kMpuFileVersion);
  w.put<uint32_t>(0);
  for (int d = 0; d < 3; ++d) w.put<double>(s.box_min[d]);
  w.put<double>(s.box_size);
  w.put<uint32_t>(uint32_t(s.leaves.size()));
  for (uint32_t d : g.dims) w.put<uint32_t>(d);
  w.put<uint32_t>(uint32_t(g.leaf_ids.size()));
  w.put<uint32_t>(0);
  for (int d = 0; d < 3; ++d) w.put<double>(s.data_min[d]);
  for (int d = 0; d < 3; ++d) w.put<double>(s.data_max[d]);
  for (const Leaf& l : s.leaves) {
    for (int d = 0; d < 3; ++d) w.put<double>(l.centre[d]);
    w.put<double>(l.radius);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) w.put<double>(l.frame(r, c));
    for (double c : l.coeffs) w.put<double>(c);
    w.put<uint8_t>(uint8_t(l.kind));
    w.put<uint8_t>(l.degree);
    w.put<uint8_t>(l.depth);
    w.put<uint8_t>(0);
    w.put<uint32_t>(l.points);
  }
  for (uint32_t o : g.offsets) w.put<uint32_t>(o);
  for (uint32_t id : g.leaf_ids) w.put<uint32_t>(id);
  w.put<uint32_t>(crc32_of(w.out.data(), w.out.size()));
  return std::move(w.out);
}

MpuSurface parse_mpu(const std::string& b, const std::string& name) {
  Reader r(b, name);
  if (b.empty()) throw InputError(name + ": file is empty");
  if (b.size() < 8 || std::memcmp(b.data(), kMagic, 8) != 0)
    r.fail("wrong magic (not written by mpumesh fit, or changed by a text-mode copy)");
  for (int i = 0; i < 8; ++i) r.get<char>();
  const uint32_t version = r.get<uint32_t>();
  if (version < 1 || version > kMpuFileVersion)
    r.fail("version " + std::to_string(version) + ", this build reads versions 1 to " + std::to_string(kMpuFileVersion));
  r.get<uint32_t>();  // flags
  MpuSurface s;
  for (int d = 0; d < 3; ++d) s.box_min[d] = r.finite();
  s.box_size = r.finite();
  if (!(s.box_size > 0)) r.fail("bounding cube of size " + std::to_string(s.box_size));
  const uint32_t leaves = r.get<uint32_t>();
  for (auto& d : s.grid.dims) {
    d = r.get<uint32_t>();
    if (d < 1 || d > 1024) r.fail("lookup grid dimension " + std::to_string(d) + " (1 to 1024)");
  }
  const uint32_t entries = r.get<uint32_t>();
  r.get<uint32_t>();
  for (int d = 0; d < 3; ++d) s.data_min[d] = r.finite();
  for (int d = 0; d < 3; ++d) s.data_max[d] = r.finite();
  for (int d = 0; d < 3; ++d)
    if (!(s.data_min[d] <= s.data_max[d]) || s.data_min[d] < s.box_min[d] || s.data_max[d] > s.box_min[d] + s.box_size)
      r.fail("the data bounding box is not inside the cube");
  const uint64_t cells = uint64_t(s.grid.dims[0]) * s.grid.dims[1] * s.grid.dims[2];
  // The size is checked before anything is allocated: a corrupt count cannot ask for
  // gigabytes.
  const uint64_t expect =
      kHeaderBytes + uint64_t(leaves) * leaf_bytes(version) + 4 * (cells + 1) + 4 * uint64_t(entries) + 4;
  if (b.size() < expect)
    r.fail("truncated: " + std::to_string(b.size()) + " bytes, the header announces " + std::to_string(expect));
  if (b.size() > expect)
    r.fail(std::to_string(b.size() - expect) + " bytes past the end the header announces");
  uint32_t stored_crc;
  std::memcpy(&stored_crc, b.data() + b.size() - 4, 4);
  if (crc32_of(b.data(), b.size() - 4) != stored_crc) r.fail("CRC mismatch (the file is corrupt)");
  if (leaves == 0) r.fail("no leaves");
  s.leaves.resize(leaves);
  for (uint32_t i = 0; i < leaves; ++i) {
    Leaf& l = s.leaves[i];
    for (int d = 0; d < 3; ++d) l.centre[d] = r.finite();
    l.radius = r.finite();
    if (!(l.radius > 0)) r.fail("leaf " + std::to_string(i) + " has radius " + std::to_string(l.radius));
    for (int row = 0; row < 3; ++row)
      for (int c = 0; c < 3; ++c) l.frame(row, c) = r.finite();
    for (size_t c = 0; c < coefficients_in(version); ++c) l.coeffs[c] = r.finite();
    const uint8_t kind = r.get<uint8_t>();
    if (kind > kind_limit(version)) r.fail("leaf " + std::to_string(i) + " has unknown fit kind " + std::to_string(kind));
    l.kind = FitKind(kind);
    l.degree = r.get<uint8_t>();
    if (l.degree > 4) r.fail("leaf " + std::to_string(i) + " has degree " + std::to_string(l.degree));
    l.depth = r.get<uint8_t>();
    r.get<uint8_t>();
    l.points = r.get<uint32_t>();
  }
  s.grid.offsets.resize(size_t(cells + 1));
  for (auto& o : s.grid.offsets) o = r.get<uint32_t>();
  if (s.grid.offsets.front() != 0 || s.grid.offsets.back() != entries)
    r.fail("lookup grid offsets do not span its " + std::to_string(entries) + " entries");
  for (size_t c = 0; c < cells; ++c)
    if (s.grid.offsets[c + 1] < s.grid.offsets[c]) r.fail("lookup grid offsets decrease at cell " + std::to_string(c));
  s.grid.leaf_ids.resize(entries);
  for (auto& id : s.grid.leaf_ids) {
    id = r.get<uint32_t>();
    if (id >= leaves) r.fail("lookup grid names leaf " + std::to_string(id) + " of " + std::to_string(leaves));
  }
  index_spheres(s);
  return s;
}

void write_mpu(const MpuSurface& s, const std::string& path) {
  const std::string bytes = serialize_mpu(s);
  AtomicFile f(path);
  {
    std::ofstream out(f.temp_path(), std::ios::binary);
    out.write(bytes.data(), std::streamsize(bytes.size()));
    out.close();
    if (!out) throw InputError(path + ": cannot write");
  }
  f.commit();
}

MpuSurface read_mpu(const std::string& path) { return parse_mpu(read_file(path), path); }

}  // namespace mpumesh::mpu
