#include "io/read_file.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/text.h"

namespace mpumesh {

std::string read_file(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw InputError(path + ": file not found");
  if (std::filesystem::is_directory(path, ec)) throw InputError(path + ": is a directory, expected a file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open (" + std::strerror(errno) + ")");
  // Read at the size the file system gives, then on to the end (a file that grew, or a
  // special file that reports no size).
  const auto size = std::filesystem::file_size(path, ec);
  std::string bytes(ec ? 0 : size_t(size), '\0');
  in.read(bytes.data(), std::streamsize(bytes.size()));
  bytes.resize(size_t(in.gcount()));
  if (in) {
    std::ostringstream rest;
    rest << in.rdbuf();
    bytes += rest.str();
  }
  if (in.bad()) throw InputError(path + ": read error");
  return bytes;
}

std::string lower_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  return lower_case(dot == std::string::npos ? "" : path.substr(dot));
}

}  // namespace mpumesh
