// What ITK, GDCM and the libraries under them (MetaIO, niftilib, teem) say while a volume
// is read: warnings through ITK's output window, GDCM's trace streams, and plain writes
// to stderr. While a LibraryMessages lives, all three are collected instead of printed;
// `take` then sorts them: a message that reports damage (data not read completely, a
// truncated or corrupt stream, a failed read) becomes an InputError naming the file, the
// rest come back as notes for the JSON report. Reads are serialised by it, since the
// streams it redirects are the process's own.
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace mpumesh {

class LibraryMessages {
 public:
  LibraryMessages();
  ~LibraryMessages();
  LibraryMessages(const LibraryMessages&) = delete;
  LibraryMessages& operator=(const LibraryMessages&) = delete;

  // Stops collecting; throws InputError("<name>: <the library's message>") when one of
  // the messages reports damage, else returns them as one note each ("ITK: ...").
  std::vector<std::string> take(const std::string& name);

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Whether a library's message reports damage to the data (public for the tests).
bool reports_damage(const std::string& message);

}  // namespace mpumesh
