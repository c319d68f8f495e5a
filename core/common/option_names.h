// How core names a caller's option in its messages: by a stable name in backquotes
// (`particles`, `particle_spacing`, `keep_specks`), which each edge spells in its own
// language when it shows the message: the command line as --particles, --spacing,
// --keep-specks; the Python module as particles=, particle_spacing=, keep_specks=. A
// message that reaches a user unspelled still reads: "ask for fewer `particles`".
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace mpumesh {

// The stable name as core writes it into a message.
inline std::string option_ref(std::string_view name) { return "`" + std::string(name) + "`"; }

// `text` with every `name` replaced by spell(name); text without backquoted names is
// returned as it is.
std::string spell_options(std::string_view text, const std::function<std::string(std::string_view)>& spell);

}  // namespace mpumesh
