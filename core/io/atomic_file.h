// Output files that appear whole or not at all: data goes to a temporary name beside the
// target (".partial-PID-NAME", keeping the extension so that format-by-extension writers
// such as ITK's still work) and is renamed over the target only on commit(). A writer that throws, or a run that is
// interrupted, leaves the previous file (if any) untouched; the destructor and
// remove_pending_temporaries() (for signal handlers) delete the temporary.
#pragma once

#include <string>

namespace mpumesh {

class AtomicFile {
 public:
  explicit AtomicFile(std::string target);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& temp_path() const { return temp_; }
  // fsyncs and renames the temporary over the target.
  void commit();

 private:
  std::string target_, temp_;
  bool committed_ = false;
};

// Writes `bytes` to `path` through an AtomicFile; InputError naming `path` on failure.
void write_file_atomically(const std::string& bytes, const std::string& path);

// Fails with InputError naming `path` when its directory does not exist or is not
// writable: call before long work starts.
void check_writable(const std::string& path);

// Deletes every temporary not yet committed (async-signal-safe: unlink only).
void remove_pending_temporaries();

}  // namespace mpumesh
