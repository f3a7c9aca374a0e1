// Language bridge: lets the headers in shaders/shared/ compile as GLSL 4.60 and as C++20.
// Those headers use only the subset valid in both languages; this file maps GLSL names onto C++
// (inside namespace vrpd::shared) and gives the few macros that differ.
#ifndef VRPD_BRIDGE_H
#define VRPD_BRIDGE_H

#ifdef __cplusplus
#include <array>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <glm/common.hpp>
#include <glm/vec2.hpp>
#include <glm/vec4.hpp>
namespace vrpd::shared {
using glm::clamp;
using glm::max;
using glm::min;
using uint = std::uint32_t;
using ivec2 = glm::ivec2;
using uvec2 = glm::uvec2;
using uvec4 = glm::uvec4;
// Without a popcnt target (the portable x86-64 baseline) std::popcount is a library call; this
// sum of bit fields is a dozen inline instructions.
inline int bitCount(std::uint32_t v) {
    v -= (v >> 1) & 0x55555555u;
    v = (v & 0x33333333u) + ((v >> 2) & 0x33333333u);
    return int((((v + (v >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24);
}
inline int findLSB(std::uint32_t v) { return v == 0u ? -1 : std::countr_zero(v); }
inline int findMSB(std::uint32_t v) { return int(std::bit_width(v)) - 1; }
using std::int64_t;
using std::uint64_t;
}  // namespace vrpd::shared
// On x86-64 some steps have a host body built for AVX2 beside the shared one, chosen at run time.
#ifdef __x86_64__
#define VRPD_HOST_AVX2 1
#include <immintrin.h>
namespace vrpd::shared {
// Whether the vector bodies may run: inlined, as a call would cost the hot scans more than the test.
[[gnu::always_inline]] inline bool host_has_avx2() {
    static const bool has = (__builtin_cpu_init(), __builtin_cpu_supports("avx2"));
    return has;
}
}  // namespace vrpd::shared
#endif
#define VRPD_BEGIN namespace vrpd::shared {
#define VRPD_END }
// A device address (GL_EXT_buffer_reference) is a 64-bit integer on the host.
#define VRPD_BUFFER(T) std::uint64_t
#define VRPD_FN inline
// A rarely taken path: kept out of line, so compilers do not compute it on every call.
#define VRPD_COLD_FN [[gnu::cold, gnu::noinline]] inline
// A path that one mode of a caller takes and another never does: kept out of line, so the other
// mode's inlined body stays small.
#define VRPD_OUTLINED_FN [[gnu::noinline]] inline
// An input read by reference on the host (a struct too large to copy per call), an output (or
// in-out) parameter, and a variable private to each invocation (each host thread).
#define VRPD_IN(T) const T&
#define VRPD_OUT(T) T&
#define VRPD_INOUT(T) T&
#define VRPD_PRIVATE constinit inline thread_local
#else
// GLSL: the extensions are enabled by shaders/common.glsl, included first by every kernel.
#define VRPD_BEGIN
#define VRPD_END
#define VRPD_BUFFER(T) T
#define VRPD_FN
#define VRPD_COLD_FN
#define VRPD_OUTLINED_FN
#define VRPD_IN(T) T
#define VRPD_OUT(T) out T
#define VRPD_INOUT(T) inout T
#define VRPD_PRIVATE
#endif

#endif
