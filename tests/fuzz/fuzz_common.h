// The shape of every fuzz target: bytes in, the parser run, InputError accepted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"

#define MPUMESH_FUZZ_TARGET(body)                                                  \
  extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {        \
    const std::string bytes(reinterpret_cast<const char*>(data), size);            \
    try {                                                                          \
      body;                                                                        \
    } catch (const mpumesh::InputError&) {                                         \
    }                                                                              \
    return 0;                                                                      \
  }
