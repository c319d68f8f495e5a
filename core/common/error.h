// Error types shared by every stage. InputError is what a user caused (a bad file, an
// absurd parameter): the message names the file or the option and the problem. The
// always-on MPUMESH_ASSERT guards internal invariants, which are bugs when they fail.
#pragma once

#include <stdexcept>
#include <string>

namespace mpumesh {

// Bad input: a file that is not what it claims, a parameter out of range.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A computation that left the numbers (NaN or infinity from a kernel, a diverging
// iteration): reported with the stage and iteration, and nothing is written.
class NumericalError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A violated internal invariant (a bug, not bad input).
class InternalError : public std::logic_error {
 public:
  using std::logic_error::logic_error;
};

[[noreturn]] void fail_assertion(const char* expr, const char* file, int line, const std::string& msg);

}  // namespace mpumesh

#define MPUMESH_ASSERT(cond, msg)                                           \
  do {                                                                      \
    if (!(cond)) ::mpumesh::fail_assertion(#cond, __FILE__, __LINE__, msg); \
  } while (0)
