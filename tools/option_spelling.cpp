#include "option_spelling.h"

#include <algorithm>

#include "common/option_names.h"

namespace mpumesh::tools {

std::string cli_flag(std::string_view name, std::string_view command) {
  if (name == "particle_spacing") return "--spacing";
  if (name == "particle_iterations") return command == "sample" ? "--iterations" : "--particle-iterations";
  if (name == "volume_size" || name == "volume_grading")
    if (command == "tetmesh") return "--" + std::string(name.substr(7));
  std::string flag = "--" + std::string(name);
  std::replace(flag.begin(), flag.end(), '_', '-');
  return flag;
}

OptionSpelling cli_spelling(std::string command) {
  return [command = std::move(command)](std::string_view name) { return cli_flag(name, command); };
}

std::string cli_text(std::string_view text, std::string_view command) {
  return spell_options(text, cli_spelling(std::string(command)));
}

std::string python_keyword(std::string_view name) { return std::string(name) + "="; }

OptionSpelling python_spelling() {
  return [](std::string_view name) { return python_keyword(name); };
}

}  // namespace mpumesh::tools
