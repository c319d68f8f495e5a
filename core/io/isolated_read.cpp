#include "io/isolated_read.h"

#include <fmt/format.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

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
    while (n > 0) {
      const ssize_t w = ::write(fd_, c, n);
      if (w < 0 && errno == EINTR) continue;
      if (w <= 0) ::_exit(3);  // the parent sees no complete record
      c += w, n -= size_t(w);
    }
  }

 private:
  int fd_;
};

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
  w.put(uint64_t(v.voxels.size()));
  w.raw(v.voxels.data(), v.voxels.size() * sizeof(float));
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

 private:
  int fd_;
  const std::string& path_;
  size_t at_ = 0;
};

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
  const uint64_t n = r.get<uint64_t>();
  v.voxels.resize(size_t(n));
  r.raw(v.voxels.data(), size_t(n) * sizeof(float));
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
