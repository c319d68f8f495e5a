// Small text helpers shared by the readers: ASCII lower case, for extensions and for
// header keys and values that formats spell in either case.
#pragma once

#include <algorithm>
#include <cctype>
#include <string>

namespace mpumesh {

inline std::string lower_case(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return s;
}

}  // namespace mpumesh
