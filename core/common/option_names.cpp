#include "common/option_names.h"

#include <cctype>

namespace mpumesh {
namespace {

bool name_char(char c) { return std::islower(static_cast<unsigned char>(c)) || std::isdigit(static_cast<unsigned char>(c)) || c == '_'; }

}  // namespace

std::string spell_options(std::string_view text, const std::function<std::string(std::string_view)>& spell) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    const size_t open = text.find('`', i);
    if (open == std::string_view::npos) break;
    size_t close = open + 1;
    while (close < text.size() && name_char(text[close])) ++close;
    if (close == open + 1 || close >= text.size() || text[close] != '`') {  // not a name: kept
      out.append(text.substr(i, open + 1 - i));
      i = open + 1;
      continue;
    }
    out.append(text.substr(i, open - i));
    out += spell(text.substr(open + 1, close - open - 1));
    i = close + 1;
  }
  out.append(text.substr(i));
  return out;
}

}  // namespace mpumesh
