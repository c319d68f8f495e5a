#include "common/eval_precision.h"

#include <atomic>
#include <cstdlib>

namespace mpumesh {

const char* eval_precision_name(EvalPrecision p) { return p == EvalPrecision::kFloat ? "float32" : "float64"; }

std::optional<EvalPrecision> parse_eval_precision(const std::string& name) {
  for (EvalPrecision p : {EvalPrecision::kDouble, EvalPrecision::kFloat})
    if (name == eval_precision_name(p)) return p;
  return std::nullopt;
}

namespace {

std::atomic<EvalPrecision>& current() {
  static std::atomic<EvalPrecision> precision{[] {
    const char* env = std::getenv("MPUMESH_EVAL");
    return env ? parse_eval_precision(env).value_or(EvalPrecision::kDouble) : EvalPrecision::kDouble;
  }()};
  return precision;
}

}  // namespace

EvalPrecision eval_precision() { return current().load(std::memory_order_relaxed); }

void set_eval_precision(EvalPrecision p) { current().store(p, std::memory_order_relaxed); }

}  // namespace mpumesh
