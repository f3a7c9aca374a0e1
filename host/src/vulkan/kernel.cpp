// Compute kernels: see kernel.h.
#include "kernel.h"

#include "device.h"

namespace vrpd::detail {

Kernel::Kernel(VulkanContext& ctx, std::string name, std::span<const std::uint32_t> spirv, std::uint32_t push_size,
               std::uint32_t workgroup, std::uint32_t variant)
    : name_(std::move(name)), push_size_(push_size) {
    const VulkanContext::Pipeline& p = ctx.pipeline(spirv, push_size, workgroup, variant);
    layout_ = p.layout.get();
    pipeline_ = p.pipeline.get();
}

const VulkanContext::Pipeline& VulkanContext::pipeline(std::span<const std::uint32_t> spirv, std::uint32_t push_size,
                                                       std::uint32_t workgroup, std::uint32_t variant) {
    const auto key = std::make_tuple(spirv.data(), push_size, workgroup, variant);
    if (const auto found = pipelines_.find(key); found != pipelines_.end()) return found->second;
    VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    mi.codeSize = spirv.size_bytes();
    mi.pCode = spirv.data();
    VkShaderModule module = VK_NULL_HANDLE;
    check(vk_.vkCreateShaderModule(device(), &mi, nullptr, &module), "vkCreateShaderModule");
    const auto owned_module = own<OwnedShaderModule>(vk_, device(), module);  // needed only to build the pipeline
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
    VkPipelineLayout layout = VK_NULL_HANDLE;
    check(vk_.vkCreatePipelineLayout(device(), &li, nullptr, &layout), "vkCreatePipelineLayout");
    Pipeline made{own<OwnedPipelineLayout>(vk_, device(), layout), {}};
    // A shader without constant 1 ignores its entry.
    const std::uint32_t constants[2] = {workgroup, variant};
    const VkSpecializationMapEntry entries[2] = {{0, 0, sizeof(std::uint32_t)}, {1, 4, sizeof(std::uint32_t)}};
    VkSpecializationInfo spec{2, entries, sizeof(constants), constants};
    VkComputePipelineCreateInfo pi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    pi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pi.stage.module = module;
    pi.stage.pName = "main";
    pi.stage.pSpecializationInfo = &spec;
    pi.layout = layout;
    VkPipeline pipeline = VK_NULL_HANDLE;
    check(vk_.vkCreateComputePipelines(device(), VK_NULL_HANDLE, 1, &pi, nullptr, &pipeline),
          "vkCreateComputePipelines");
    made.pipeline = own<OwnedPipeline>(vk_, device(), pipeline);
    return pipelines_.emplace(key, std::move(made)).first->second;
}

}  // namespace vrpd::detail
