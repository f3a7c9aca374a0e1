// Included first by every kernel: the GLSL version's extensions the shared headers rely on.
#extension GL_EXT_shader_explicit_arithmetic_types_int64 : require
#extension GL_EXT_buffer_reference : require
#extension GL_KHR_memory_scope_semantics : require
#extension GL_GOOGLE_include_directive : require
// The scope and order of the atomic loads and stores of words that invocations of one dispatch
// write while others read them: relaxed (each word's value alone matters), across the device.
#define VRPD_RELAXED gl_ScopeDevice, gl_StorageSemanticsBuffer, gl_SemanticsRelaxed
