// Reads the regular files of a gzip-compressed tar archive (ustar/GNU headers) into
// memory. Used for InVesalius .inv3 projects. Sizes are checked against the data, and the
// total unpacked size is capped, so a hostile archive fails with InputError.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>

namespace mpumesh {

// gunzip of a whole buffer (concatenated members allowed); InputError on corrupt data.
std::string gunzip(const std::string& gz, const std::string& name, uint64_t max_bytes);

// gzip of a whole buffer (fast level): for tests and the .inv3 fuzz target, which build
// archives in memory.
std::string gzip(const std::string& bytes);

// File name (without leading directories) to contents: views into `tar`, which must
// outlive them (an .inv3 volume is tens of MB, not copied again).
std::map<std::string, std::string_view> untar(const std::string& tar, const std::string& name);

}  // namespace mpumesh
