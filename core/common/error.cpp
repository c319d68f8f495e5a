#include "common/error.h"

namespace mpumesh {

void fail_assertion(const char* expr, const char* file, int line, const std::string& msg) {
  throw InternalError(std::string("internal error: ") + msg + " (" + expr + " at " + file + ":" +
                      std::to_string(line) + ")");
}

}  // namespace mpumesh
