#include "io/isolated_read.h"

#include <fmt/format.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <new>
#include <thread>

#include "common/error.h"

namespace mpumesh {
namespace {

constexpr uint32_t kMagic = 0x5256504du;  // "MPVR"
enum Kind : uint8_t { kVolume = 0, kInputError = 1, kOtherError = 2 };
// The voxels start at a multiple of this from the record's start, so that the parent's
// mapping of the record reads them in place.
constexpr size_t kVoxelAlign = 8;

// ---- the child's record, written to the shared file
class Writer {
 public:
  explicit Writer(int fd) : fd_(fd) {}
  template <class T>
  void put(const T& x) {
    raw(&x, sizeof x);
  }
  void put_string(const std::string& s) {
    put(uint32_t(s.size()));
    raw(s.data(), s.size());
  }
  void raw(const void* p, size_t n) {
    const char* c = static_cast<const char*>(p);
    written_ += n;
    while (n > 0) {
      const ssize_t w = ::write(fd_, c, n);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) ::_exit(3);  // the parent sees no complete record
      c += w, n -= size_t(w);
    }
  }
  // Zero bytes up to the next multiple of kVoxelAlign from the record's start.
  void align() {
    const char zeros[kVoxelAlign] = {};
    raw(zeros, (kVoxelAlign - written_ % kVoxelAlign) % kVoxelAlign);
  }

 private:
  int fd_;
  size_t written_ = 0;
};

// Whether every voxel is an int16 exactly (a CT's, an MR's, a label map's usually; not
// -0): they then travel as int16, half the bytes to write, map and convert.
bool integral_int16(const std::vector<float>& v) {
  for (const float x : v) {
    if (!(x >= -32768.0f && x <= 32767.0f)) return false;
    const float back = float(int16_t(x));
    if (std::memcmp(&back, &x, sizeof x) != 0) return false;
  }
  return true;
}

// The voxels as int16, a block at a time.
void write_packed(Writer& w, const std::vector<float>& v) {
  constexpr size_t kBlock = size_t(1) << 16;
  std::vector<int16_t> block(kBlock);
  for (size_t at = 0; at < v.size(); at += kBlock) {
    const size_t n = std::min(kBlock, v.size() - at);
    for (size_t k = 0; k < n; ++k) block[k] = int16_t(v[at + k]);
    w.raw(block.data(), n * sizeof(int16_t));
  }
}

void write_volume(int fd, const PlainVolume& v) {
  Writer w(fd);
  w.put(kMagic);
  w.put(uint8_t(kVolume));
  w.raw(v.dims.data(), sizeof v.dims);
  w.raw(v.spacing.data(), sizeof v.spacing);
  w.raw(v.origin.data(), sizeof v.origin);
  w.raw(v.direction.data(), sizeof v.direction);
  w.put_string(v.modality);
  w.put(uint32_t(v.notes.size()));
  for (const std::string& n : v.notes) w.put_string(n);
  const bool native = !v.voxels16.empty(), packed = native || integral_int16(v.voxels);
  w.put(uint8_t(packed));
  w.put(uint64_t(native ? v.voxels16.size() : v.voxels.size()));
  w.align();
  if (native) w.raw(v.voxels16.data(), v.voxels16.size() * sizeof(int16_t));
  else if (packed) write_packed(w, v.voxels);
  else w.raw(v.voxels.data(), v.voxels.size() * sizeof(float));
}

void write_error(int fd, Kind kind, const std::string& message) {
  Writer w(fd);
  w.put(kMagic);
  w.put(uint8_t(kind));
  w.put_string(message);
}

// ---- the parent's reading of it
class Reader {
 public:
  Reader(int fd, const std::string& path) : fd_(fd), path_(path) {}
  template <class T>
  T get() {
    T x;
    raw(&x, sizeof x);
    return x;
  }
  std::string get_string() {
    const uint32_t n = get<uint32_t>();
    std::string s(n, '\0');
    raw(s.data(), n);
    return s;
  }
  void raw(void* p, size_t n) {
    char* c = static_cast<char*>(p);
    while (n > 0) {
      const ssize_t r = ::pread(fd_, c, n, off_t(at_));
      if (r < 0 && errno == EINTR) continue;
      if (r <= 0) throw InputError(path_ + ": the volume reader's record is cut short");
      c += r, n -= size_t(r), at_ += size_t(r);
    }
  }
  size_t at() const { return at_; }
  void align() { at_ += (kVoxelAlign - at_ % kVoxelAlign) % kVoxelAlign; }

 private:
  int fd_;
  const std::string& path_;
  size_t at_ = 0;
};

// The voxels, `count` of them from byte `at` of the record (int16 when `packed`, else
// float), read from a mapping of it and converted as they are copied once into `out`
// (no copy through read(), no zero-filling of the vector first).
void map_voxels(int fd, size_t at, uint64_t count, bool packed, const std::string& path, std::vector<float>& out) {
  const size_t bytes = size_t(count) * (packed ? sizeof(int16_t) : sizeof(float));
  struct stat st;
  if (::fstat(fd, &st) != 0 || count > uint64_t(st.st_size) || size_t(st.st_size) < at + bytes)
    throw InputError(path + ": the volume reader's record is cut short");
  if (count == 0) return out.clear();
  void* map = ::mmap(nullptr, at + bytes, PROT_READ, MAP_PRIVATE | MAP_POPULATE, fd, 0);
  if (map == MAP_FAILED) throw InputError(path + ": cannot map the volume reader's record: " + std::strerror(errno));
  const char* data = static_cast<const char*>(map) + at;
  try {
    if (packed) {
      const auto* v = reinterpret_cast<const int16_t*>(data);
      out.assign(v, v + count);
    } else {
      const auto* v = reinterpret_cast<const float*>(data);
      out.assign(v, v + count);
    }
  } catch (...) {
    ::munmap(map, at + bytes);
    throw;
  }
  ::munmap(map, at + bytes);
}

PlainVolume read_record(int fd, const std::string& path) {
  Reader r(fd, path);
  if (r.get<uint32_t>() != kMagic) throw InputError(path + ": the volume reader left no record");
  const uint8_t kind = r.get<uint8_t>();
  if (kind == kInputError) throw InputError(r.get_string());
  if (kind != kVolume) throw InputError(path + ": " + r.get_string());
  PlainVolume v;
  r.raw(v.dims.data(), sizeof v.dims);
  r.raw(v.spacing.data(), sizeof v.spacing);
  r.raw(v.origin.data(), sizeof v.origin);
  r.raw(v.direction.data(), sizeof v.direction);
  v.modality = r.get_string();
  const uint32_t notes = r.get<uint32_t>();
  for (uint32_t k = 0; k < notes; ++k) v.notes.push_back(r.get_string());
  const bool packed = r.get<uint8_t>() != 0;
  const uint64_t n = r.get<uint64_t>();
  r.align();
  map_voxels(fd, r.at(), n, packed, path, v.voxels);
  return v;
}

std::string signal_name(int sig) {
  switch (sig) {
    case SIGABRT: return "abort";
    case SIGSEGV: return "segmentation fault";
    case SIGBUS: return "bus error";
    case SIGFPE: return "arithmetic fault";
    case SIGILL: return "illegal instruction";
    case SIGKILL: return "killed";
    default: return "signal " + std::to_string(sig);
  }
}

double timeout_seconds() {
  const char* t = std::getenv("MPUMESH_READER_TIMEOUT");
  const double s = t ? std::atof(t) : 0.0;
  return s > 0 ? s : 600.0;
}

// A closed file descriptor on every path out.
struct Fd {
  int fd = -1;
  ~Fd() {
    if (fd >= 0) ::close(fd);
  }
};

// The child: reads, writes its record to `out`, exits without running the process's exit
// handlers (they are the parent's: an interpreter's, a test runner's).
[[noreturn]] void child(int out, const std::function<PlainVolume()>& read) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  // The parent's handlers are not the child's: a crash ends the child as the signal's
  // default does (the parent reads it from the wait status), and an interrupt ends it
  // without running the parent's clean-up (its temporary files are the parent's).
  for (const int sig : {SIGABRT, SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGINT, SIGTERM, SIGPIPE}) ::signal(sig, SIG_DFL);
  if (const char* test = std::getenv("MPUMESH_READER_TEST")) {
    if (std::strcmp(test, "abort") == 0) std::abort();
    if (std::strcmp(test, "hang") == 0)
      for (;;) ::pause();
  }
  try {
    write_volume(out, read());
  } catch (const InputError& e) {
    write_error(out, kInputError, e.what());
  } catch (const std::bad_alloc&) {
    write_error(out, kOtherError, "out of memory while reading");
  } catch (const std::exception& e) {
    write_error(out, kOtherError, e.what());
  }
  ::_exit(0);
}

// Waits for the child to end (its end of `alive` closes), up to the time limit; returns
// its wait status, or kills it and throws past the limit.
int wait_for(pid_t pid, int alive, const std::string& path, const std::string& reader) {
  const double limit = timeout_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  for (;;) {
    const double left = limit - std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    pollfd p{alive, POLLIN, 0};
    const int r = left > 0 ? ::poll(&p, 1, int(std::min(left * 1000, 3.6e6)) + 1) : 0;
    if (r < 0 && errno == EINTR) continue;
    if (r == 0) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, nullptr, 0);
      throw InputError(fmt::format("{}: {} ran past its time limit of {:g} s; the file is probably malformed "
                                   "(MPUMESH_READER_TIMEOUT sets the limit)",
                                   path, reader, limit));
    }
    break;  // hung up: the child has ended
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return status;
}

}  // namespace

PlainVolume read_isolated(const std::string& path, const std::string& reader,
                          const std::function<PlainVolume()>& read) {
#ifdef MPUMESH_READ_IN_PROCESS
  (void)path, (void)reader;
  return read();
#endif
  Fd record;
  record.fd = ::memfd_create("mpumesh-volume", MFD_CLOEXEC);
  if (record.fd < 0) throw InputError(path + ": cannot make a shared file for the reader: " + std::strerror(errno));
  int alive[2];
  if (::pipe2(alive, O_CLOEXEC) != 0) throw InputError(path + ": cannot make a pipe for the reader: " + std::strerror(errno));
  Fd alive_read{alive[0]}, alive_write{alive[1]};
  const pid_t pid = ::fork();
  if (pid < 0) throw InputError(path + ": cannot start the reader's process: " + std::strerror(errno));
  if (pid == 0) {
    ::close(alive[0]);
    child(record.fd, read);
  }
  ::close(alive_write.fd);
  alive_write.fd = -1;
  const int status = wait_for(pid, alive_read.fd, path, reader);
  if (WIFSIGNALED(status))
    throw InputError(fmt::format("{}: {} crashed ({}) — the file is probably malformed or of an unsupported kind",
                                 path, reader, signal_name(WTERMSIG(status))));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InputError(fmt::format("{}: {} failed (exit code {}) — the file is probably malformed", path, reader,
                                 WIFEXITED(status) ? WEXITSTATUS(status) : -1));
  return read_record(record.fd, path);
}

}  // namespace mpumesh
