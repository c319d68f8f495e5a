// The benchmarks' shared parts: the memory set-up every benchmark that times peers makes,
// a product command timed as a user runs it, and the truth benchmarks' table of figures
// against the analytic truth (core/phantom/truth_figures.h), one row per mesh.
#pragma once

#include <string>

#include "phantom/truth_figures.h"

namespace mpumesh::bench {

// Memory for a benchmark that times our runs against its peers, called first in main:
// malloc tuned as mpumesh tunes it (tune_memory), and the huge-page choice
// (common/memory.h) made once here whatever the input's size, so that the peers in this
// process and our runs, which inherit it through GLIBC_TUNABLES, all run alike. Prints it.
void same_memory_for_all(char** argv);

// Runs `cmd` through the shell; exits the benchmark when it fails. Seconds.
double timed_system(const std::string& cmd);

// Whether a benchmark's argument names a backend (cpu, gpu, auto).
bool is_backend(const std::string& arg);
// The options the environment variable `name` adds to our runs, with a space in front
// (empty when unset).
std::string extra_args(const char* name);

// The header and a row. `slices`: with the volume and slice-phase columns.
void print_truth_header(bool slices);
void print_truth_row(const std::string& name, const phantom::TruthFigures& f, double seconds, bool slices);

}  // namespace mpumesh::bench
