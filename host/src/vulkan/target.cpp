// Sampling on the application's Vulkan device (vrpd/vulkan_target.h): the run's engine works on
// the target's device, on the DeviceSampler's context; the samples then go to a buffer there,
// through one staging copy.
#include <cstring>

#include <fmt/format.h>

#include "buffer.h"
#include "device.h"
#include "vrpd/sizing.h"
#include "vrpd/vulkan_target.h"

namespace vrpd {

DeviceSamples sample_on(const VulkanTarget& target, const SampleOptions& options, VkBuffer into,
                        VkDeviceSize into_bytes) {
    return DeviceSampler(target).sample(options, into, into_bytes);
}

DeviceSamples sample_on(const VulkanTarget& target, const SampleOptions& options, const SizingField& field,
                        VkBuffer into, VkDeviceSize into_bytes) {
    return DeviceSampler(target).sample(options, field, into, into_bytes);
}

DeviceSampler::DeviceSampler(const VulkanTarget& target)
    : target_(target), ctx_(std::make_unique<detail::VulkanContext>(target)) {
    detail::lend_context(&target_, ctx_.get());
}

DeviceSampler::~DeviceSampler() { detail::lend_context(&target_, nullptr); }

std::size_t DeviceSampler::pipelines() const { return ctx_->pipelines(); }

DeviceSamples DeviceSampler::sample(const SampleOptions& options, VkBuffer into, VkDeviceSize into_bytes) {
    SampleOptions on_target = options;
    on_target.vulkan = &target_;  // the runs borrow ctx_ (ContextLease)
    return deliver(vrpd::sample(on_target), into, into_bytes);
}

DeviceSamples DeviceSampler::sample(const SampleOptions& options, const SizingField& field, VkBuffer into,
                                    VkDeviceSize into_bytes) {
    SampleOptions on_target = options;
    on_target.vulkan = &target_;
    return deliver(vrpd::sample(on_target, field), into, into_bytes);
}

DeviceSamples DeviceSampler::deliver(Sampling sampling, VkBuffer into, VkDeviceSize into_bytes) {
    using namespace detail;
    DeviceSamples out;
    out.sampling = std::move(sampling);
    const Sampling& s = out.sampling;
    out.bytes = s.size() * sizeof(DeviceSample);
    if (into && into_bytes < out.bytes)
        throw Error(fmt::format("the buffer given has {} bytes; the {} samples need {}", into_bytes, s.size(),
                                out.bytes));

    std::vector<DeviceSample> rows(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) {
        const glm::dvec2 p = s.point(i);
        const double t = s.birth.empty() ? 1.0 : s.birth[i];
        const double r = (s.local_radius.empty() ? s.radius : s.local_radius[i]) * t * s.hierarchy_start;
        rows[i] = {float(p.x), float(p.y), float(t), float(r)};
    }

    VulkanContext& ctx = *ctx_;
    ctx.start_run();
    const VulkanFunctions& vk = ctx.vk();
    OwnedBuffer buffer;
    OwnedMemory memory;
    if (!into) {
        VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        bi.size = out.bytes;
        bi.usage = VK_BUFFER_USAGE_VERTEX_BUFFER_BIT | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT |
                   VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
        bi.sharingMode = VK_SHARING_MODE_EXCLUSIVE;
        VkBuffer b = VK_NULL_HANDLE;
        ctx.check(vk.vkCreateBuffer(ctx.device(), &bi, nullptr, &b), "vkCreateBuffer");
        buffer = own<OwnedBuffer>(vk, ctx.device(), b);
        VkMemoryRequirements req;
        vk.vkGetBufferMemoryRequirements(ctx.device(), b, &req);
        VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        ai.allocationSize = req.size;
        ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, false);
        VkDeviceMemory m = VK_NULL_HANDLE;
        ctx.check(vk.vkAllocateMemory(ctx.device(), &ai, nullptr, &m), "vkAllocateMemory");
        memory = own<OwnedMemory>(vk, ctx.device(), m);
        ctx.check(vk.vkBindBufferMemory(ctx.device(), b, m, 0), "vkBindBufferMemory");
        into = b;
    }
    {
        Buffer staging(ctx, out.bytes, true);
        std::memcpy(staging.mapped(), rows.data(), out.bytes);
        VkCommandBuffer cmd = ctx.begin();
        const VkBufferCopy all{0, 0, out.bytes};
        vk.vkCmdCopyBuffer(cmd, staging.handle(), into, 1, &all);
        // The copy before any later read of the buffer on this queue: vertex input, shaders,
        // transfers (a barrier orders the commands submitted after it too).
        VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
        mb.srcAccessMask = VK_ACCESS_TRANSFER_WRITE_BIT;
        mb.dstAccessMask = VK_ACCESS_MEMORY_READ_BIT;
        vk.vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_TRANSFER_BIT, VK_PIPELINE_STAGE_ALL_COMMANDS_BIT, 0, 1, &mb, 0,
                                nullptr, 0, nullptr);
        ctx.submit_and_wait();
    }
    out.buffer = buffer ? buffer.release() : into;
    out.memory = memory.release();
    return out;
}

}  // namespace vrpd
