// Reads a whole file into memory; InputError names the file when it is missing,
// unreadable or a directory.
#pragma once

#include <string>

namespace mpumesh {

std::string read_file(const std::string& path);

// The extension of `path` from its last dot, lower-cased (".PLY" -> ".ply"), or "".
std::string lower_extension(const std::string& path);

}  // namespace mpumesh
