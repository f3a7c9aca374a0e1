// Compute kernels: see kernel.h.
#include "kernel.h"

#include <algorithm>
#include <atomic>
#include <system_error>
#include <thread>

#include "device.h"

namespace vrpd::detail {

Kernel::Kernel(VulkanContext& ctx, std::string name, std::span<const std::uint32_t> spirv, std::uint32_t push_size,
               std::uint32_t workgroup, std::uint32_t variant)
    : name_(std::move(name)), push_size_(push_size), entry_(&ctx.pipeline(spirv, push_size, workgroup, variant)) {}

const KernelPipeline& VulkanContext::pipeline(std::span<const std::uint32_t> spirv, std::uint32_t push_size,
                                              std::uint32_t workgroup, std::uint32_t variant) {
    const auto key = std::make_tuple(spirv.data(), push_size, workgroup, variant);
    if (const auto found = pipelines_.find(key); found != pipelines_.end()) return found->second;
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    check(vk_.vkCreatePipelineLayout(device(), &li, nullptr, &layout), "vkCreatePipelineLayout");
    KernelPipeline made{own<OwnedPipelineLayout>(vk_, device(), layout), {}, spirv, workgroup, variant};
    KernelPipeline& entry = pipelines_.emplace(key, std::move(made)).first->second;
    pending_.push_back(&entry);
    return entry;
}

void VulkanContext::build_pending() {
    std::vector<KernelPipeline*> todo;
    todo.swap(pending_);
    // One pipeline: its shader module (needed only to build it), its constants (a shader without
    // constant 1 ignores its entry) and the driver's compilation.
    auto build = [&](const KernelPipeline& p) {
        VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        mi.codeSize = p.spirv.size_bytes();
        mi.pCode = p.spirv.data();
        VkShaderModule module = VK_NULL_HANDLE;
        check(vk_.vkCreateShaderModule(device(), &mi, nullptr, &module), "vkCreateShaderModule");
        const auto owned_module = own<OwnedShaderModule>(vk_, device(), module);
        const std::uint32_t constants[2] = {p.workgroup, p.variant};
        const VkSpecializationMapEntry entries[2] = {{0, 0, sizeof(std::uint32_t)}, {1, 4, sizeof(std::uint32_t)}};
        VkSpecializationInfo spec{2, entries, sizeof(constants), constants};
        VkComputePipelineCreateInfo pi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        pi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
        pi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
        pi.stage.module = module;
        pi.stage.pName = "main";
        pi.stage.pSpecializationInfo = &spec;
        pi.layout = p.layout.get();
        VkPipeline pipeline = VK_NULL_HANDLE;
        check(vk_.vkCreateComputePipelines(device(), VK_NULL_HANDLE, 1, &pi, nullptr, &pipeline),
              "vkCreateComputePipelines");
        return pipeline;
    };
    // Each thread takes the next pipeline to build: vkCreateComputePipelines synchronises nothing
    // but a pipeline cache (none is given), so the driver compiles on them all at once. A failure
    // is reported as the first pipeline's in the list, whatever the timing.
    std::vector<VkPipeline> made(todo.size(), VK_NULL_HANDLE);
    std::vector<std::exception_ptr> failed(todo.size());
    std::atomic<std::size_t> next = 0;
    auto work = [&] {
        for (std::size_t i; (i = next.fetch_add(1, std::memory_order_relaxed)) < todo.size();) {
            try {
                made[i] = build(*todo[i]);
            } catch (...) {
                failed[i] = std::current_exception();
            }
        }
    };
    const std::size_t cores = std::max(1u, std::thread::hardware_concurrency());
    const std::size_t helpers = std::min(cores, std::max<std::size_t>(todo.size(), 1)) - 1;
    std::vector<std::thread> threads;
    for (std::size_t t = 0; t < helpers; ++t) {
        try {
            threads.emplace_back(work);
        } catch (const std::system_error&) {
            break;  // no more threads to be had: the ones running, this one among them, build the rest
        }
    }
    work();
    for (std::thread& t : threads) t.join();
    for (std::size_t i = 0; i < todo.size(); ++i)
        if (made[i] != VK_NULL_HANDLE) todo[i]->pipeline = own<OwnedPipeline>(vk_, device(), made[i]);
    for (std::size_t i = 0; i < todo.size(); ++i) {
        if (!failed[i]) continue;
        for (std::size_t j = i; j < todo.size(); ++j)
            if (made[j] == VK_NULL_HANDLE) pending_.push_back(todo[j]);
        std::rethrow_exception(failed[i]);
    }
}

}  // namespace vrpd::detail
