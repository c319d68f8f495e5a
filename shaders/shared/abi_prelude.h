// Lets a shaders/shared/*_abi.h header compile both as GLSL and as C++: in C++ the GLSL
// scalar and vector names map to fixed-size types with the same std430 layout.
#ifndef MPUMESH_ABI_PRELUDE_H
#define MPUMESH_ABI_PRELUDE_H
#ifdef __cplusplus
#include <cstdint>
namespace mpumesh::abi {
using uint = uint32_t;
struct alignas(16) uvec4 { uint32_t x, y, z, w; };
struct alignas(16) ivec4 { int32_t x, y, z, w; };
struct alignas(16) vec4 { float x, y, z, w; };
}  // namespace mpumesh::abi
#define ABI_BEGIN namespace mpumesh::abi {
#define ABI_END }
#else
#define ABI_BEGIN
#define ABI_END
#endif
#endif
