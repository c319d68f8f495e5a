#include "io/atomic_file.h"

#include <fcntl.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/error.h"

namespace mpumesh {
namespace {

// Fixed slots so that a signal handler can walk them without allocating.
constexpr int kSlots = 64;
std::array<std::atomic<const char*>, kSlots> g_pending{};

void track(const char* p) {
  for (auto& s : g_pending) {
    const char* expected = nullptr;
    if (s.compare_exchange_strong(expected, p)) return;
  }
}
void untrack(const char* p) {
  for (auto& s : g_pending) {
    const char* expected = p;
    if (s.compare_exchange_strong(expected, nullptr)) return;
  }
}

}  // namespace

AtomicFile::AtomicFile(std::string target) : target_(std::move(target)) {
  check_writable(target_);
  namespace fs = std::filesystem;
  fs::path t(target_);
  temp_ = (t.parent_path() / (".partial-" + std::to_string(::getpid()) + "-" + t.filename().string()))
              .string();
  track(temp_.c_str());
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    untrack(temp_.c_str());
    std::remove(temp_.c_str());
  }
}

void AtomicFile::commit() {
  int fd = ::open(temp_.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  if (std::rename(temp_.c_str(), target_.c_str()) != 0)
    throw InputError(target_ + ": cannot write (" + std::strerror(errno) + ")");
  untrack(temp_.c_str());
  committed_ = true;
}

void write_file_atomically(const std::string& bytes, const std::string& path) {
  AtomicFile out(path);
  {
    std::ofstream os(out.temp_path(), std::ios::binary);
    if (!os) throw InputError(path + ": cannot open for writing");
    os.write(bytes.data(), std::streamsize(bytes.size()));
    os.flush();
    if (!os) throw InputError(path + ": write failed (disk full?)");
  }
  out.commit();
}

void check_writable(const std::string& path) {
  namespace fs = std::filesystem;
  fs::path p(path);
  if (p.filename().empty()) throw InputError(path + ": output path names no file");
  fs::path dir = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(path + ": output directory '" + dir.string() + "' does not exist");
  // A file is made and removed there: permission bits say nothing for root, and a
  // read-only or special file system (/proc) refuses only the creation itself.
  const fs::path probe = dir / (".mpumesh-probe-" + std::to_string(::getpid()));
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0600);
  if (fd < 0) throw InputError(path + ": output directory '" + dir.string() + "' is not writable (" +
                               std::strerror(errno) + ")");
  ::close(fd);
  ::unlink(probe.c_str());
  if (fs::is_directory(p, ec)) throw InputError(path + ": is a directory, not a file");
}

void remove_pending_temporaries() {
  for (auto& s : g_pending) {
    const char* p = s.load();
    if (p) ::unlink(p);
  }
}

}  // namespace mpumesh
