// A compute kernel: a pipeline with a push-constant block and no descriptor sets (buffers are
// passed by device address), its workgroup size given as specialization constant 0 and a variant
// word as specialization constant 1 (kernels that declare it fold the branches it decides away:
// llvmpipe runs both sides of every branch its lanes reach, shared/radii.h).
#pragma once

#include <cstdint>
#include <span>
#include <string>

#include "handles.h"

namespace vrpd::detail {

class VulkanContext;

// A pipeline of a context's cache (VulkanContext::pipeline): its layout, the pipeline once built
// (null until then), and what it is built from.
struct KernelPipeline {
    OwnedPipelineLayout layout;
    OwnedPipeline pipeline;
    std::span<const std::uint32_t> spirv;
    std::uint32_t workgroup = 0, variant = 0;
};

// A kernel's pipeline, from its context's cache: handles that own nothing, valid while the
// context lives; the pipeline null until the context has built it.
class Kernel {
public:
    Kernel(VulkanContext& ctx, std::string name, std::span<const std::uint32_t> spirv, std::uint32_t push_size,
           std::uint32_t workgroup, std::uint32_t variant = 0);
    VkPipeline pipeline() const { return entry_->pipeline.get(); }
    VkPipelineLayout layout() const { return entry_->layout.get(); }
    std::uint32_t push_size() const { return push_size_; }
    const std::string& name() const { return name_; }

private:
    std::string name_;
    std::uint32_t push_size_;
    const KernelPipeline* entry_;
};

}  // namespace vrpd::detail

namespace vrpd::detail {
// The least maxComputeWorkGroupCount Vulkan allows in each dimension: a dispatch's row of
// workgroups holds at most this many.
inline constexpr std::uint32_t kMaxWorkgroups = 65535;
// Workgroups of `per_group` invocations that cover n items.
inline std::uint32_t dispatch_groups(std::uint64_t n, std::uint32_t per_group) {
    return std::uint32_t((n + per_group - 1) / per_group);
}
// A SPIR-V array (spirv_<name>, generated at build time) as a span of words.
template <std::size_t N>
std::span<const std::uint32_t> spirv_words(const std::uint32_t (&code)[N]) {
    return {code, N};
}
}  // namespace vrpd::detail

// The initializer of kernel member name_ (in a constructor's list, where the generated header
// spirv_<name> is included), on the member `ctx_` declared before it; its name, in profiles, is
// its shader's. The arguments after `push`: the workgroup size, and optionally the variant.
#define VRPD_KERNEL(name, push, ...) name##_(ctx_, #name, spirv_words(spirv_##name), sizeof(push), __VA_ARGS__)
