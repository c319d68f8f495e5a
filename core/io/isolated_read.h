// Third-party readers (ITK, GDCM and their codecs) run where their crash cannot reach the
// caller: in a child process (fork), which hands the volume back in a shared in-memory
// file (its voxels as int16 where each is one exactly: half the bytes) that the caller
// maps and converts in one copy; a pipe tells the caller when the child has ended. A child
// that dies by a signal, or runs past the time limit, becomes an InputError naming the
// file ("the DICOM reader crashed (abort)"); the caller (the command line, the Python
// interpreter) goes on. An InputError inside the child comes back as the same error.
//
// The time limit is MPUMESH_READER_TIMEOUT seconds (default 600). For the tests,
// MPUMESH_READER_TEST=abort makes the child abort and =hang makes it wait past the limit.
// Built with MPUMESH_READ_IN_PROCESS (the sanitized build, whose allocator is not
// fork-safe), `read` runs in the caller's process instead.
#pragma once

#include <functional>
#include <string>

#include "io/itk_image_io.h"

namespace mpumesh {

// Runs `read` in a child process and returns its volume. `reader` names the reader in the
// error, e.g. "the DICOM reader".
PlainVolume read_isolated(const std::string& path, const std::string& reader, const std::function<PlainVolume()>& read);

}  // namespace mpumesh
