#ifndef FOVLAB_GPU_TYPES_H
#define FOVLAB_GPU_TYPES_H
// The vocabulary of the structs that C++ fills and the shaders read (renderer/shaders/shared/*_params.h,
// each included by both): in GLSL the built-in types; in C++ types of the same size and std430
// alignment in namespace fovlab::gpu. Every struct here is read with the std430 layout (push
// constants and storage buffers). A vec3 is 12 bytes on a 4-byte alignment in C++ (glm::vec3) but on
// 16 in GLSL, so every vec3 here starts a 16-byte slot and a 4-byte scalar completes it; the layout
// test (tests/renderer/gpu_layout_test.cpp) compares every struct's offsets and size in both.
#ifdef __cplusplus
#include <cstddef>
#include <cstdint>

#include <glm/vec3.hpp>

namespace fovlab::gpu {

using uint = uint32_t;

// A GLSL vector of N components T, aligned as std430 aligns it; indexed like the arrays it replaces.
template <typename T, int N, size_t Alignment>
struct alignas(Alignment) Vector {
  T components[N];
  constexpr T& operator[](int i) { return components[i]; }
  constexpr const T& operator[](int i) const { return components[i]; }
  constexpr T* begin() { return components; }
  constexpr T* end() { return components + N; }
  constexpr const T* begin() const { return components; }
  constexpr const T* end() const { return components + N; }
};
using vec2 = Vector<float, 2, 8>;
using uvec2 = Vector<uint32_t, 2, 8>;
using ivec2 = Vector<int32_t, 2, 8>;
using vec3 = glm::vec3;
using vec4 = Vector<float, 4, 16>;
using uvec4 = Vector<uint32_t, 4, 16>;
using ivec4 = Vector<int32_t, 4, 16>;

}  // namespace fovlab::gpu

#define FOVLAB_GPU_BEGIN namespace fovlab::gpu {
#define FOVLAB_GPU_END }
#else
#define FOVLAB_GPU_BEGIN
#define FOVLAB_GPU_END
#endif

FOVLAB_GPU_BEGIN
// The workgroup width (local_size_x) of the passes that run over a frame in rows of invocations (the
// zone blend, its display and band passes, the sRGB8 encoder, the copy baseline, the upsampler).
const uint ROW_GROUP_WIDTH = 64u;
#ifdef __cplusplus
// The workgroups of ROW_GROUP_WIDTH that cover a row of `width` pixels.
constexpr uint32_t row_groups(uint32_t width) { return (width + ROW_GROUP_WIDTH - 1) / ROW_GROUP_WIDTH; }
#endif
FOVLAB_GPU_END

#endif
