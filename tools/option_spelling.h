// How the command line and the Python module spell the option names that core's messages
// carry (common/option_names.h): `particles` is --particles on the command line and
// particles= in Python; a few options have a flag of another name, or one per command
// (the particles' spacing is --spacing, their iteration cap --iterations in `sample` and
// --particle-iterations in `run`).
#pragma once

#include <string>
#include <string_view>

#include "common/error.h"
#include "run_json.h"

namespace mpumesh::tools {

// The flag of option `name` in `command` (e.g. "run", "sample", "tetmesh").
std::string cli_flag(std::string_view name, std::string_view command);
OptionSpelling cli_spelling(std::string command);
// `text` with its option names spelled as `command`'s flags.
std::string cli_text(std::string_view text, std::string_view command);

// The keyword of option `name` in the Python module.
std::string python_keyword(std::string_view name);
OptionSpelling python_spelling();

// Runs f; an InputError from it gets "COMMAND: " in front of its message (none when
// `command` is empty).
template <class F>
void as_command(const std::string& command, F&& f) {
  if (command.empty()) return f();
  try {
    f();
  } catch (const InputError& e) {
    throw InputError(command + ": " + e.what());
  }
}

}  // namespace mpumesh::tools
