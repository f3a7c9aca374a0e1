// Device buffers: see buffer.h.
#include "buffer.h"

#include <algorithm>
#include <utility>

#include <fmt/format.h>

#include "device.h"

namespace vrpd::detail {

Buffer::Buffer(VulkanContext& ctx, VkDeviceSize size, bool host_visible) : ctx_(&ctx), size_(size) {
    const auto& vk = ctx.vk();
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = std::max<VkDeviceSize>(size, 16);
    bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
               VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT |
               VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    // A driver may refuse an allocation when the buffer is created (lavapipe does) or when its
    // memory is allocated: either way the user hears what ran out.
    auto refuse_if_out_of_memory = [&](VkResult r, VkDeviceSize bytes) {
        if (r == VK_ERROR_OUT_OF_DEVICE_MEMORY || r == VK_ERROR_OUT_OF_HOST_MEMORY)
            throw Error(fmt::format("out of memory on {} allocating {} MiB ({}); try a larger radius or --device cpu",
                                    ctx.device_name(), bytes >> 20, result_name(r)));
    };
    VkBuffer buffer = VK_NULL_HANDLE;
    const VkResult created = vk.vkCreateBuffer(ctx.device(), &bi, nullptr, &buffer);
    refuse_if_out_of_memory(created, bi.size);
    ctx.check(created, "vkCreateBuffer");
    buffer_ = own<OwnedBuffer>(vk, ctx.device(), buffer);
    VkMemoryRequirements req;
    vk.vkGetBufferMemoryRequirements(ctx.device(), buffer, &req);
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, &flags};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, host_visible);
    VkDeviceMemory memory = VK_NULL_HANDLE;
    const VkResult allocated = vk.vkAllocateMemory(ctx.device(), &ai, nullptr, &memory);
    refuse_if_out_of_memory(allocated, req.size);
    ctx.check(allocated, "vkAllocateMemory");
    memory_ = own<OwnedMemory>(vk, ctx.device(), memory);
    allocated_ = req.size;
    ctx.note_allocation(std::int64_t(allocated_));
    ctx.check(vk.vkBindBufferMemory(ctx.device(), buffer, memory, 0), "vkBindBufferMemory");
    VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    info.buffer = buffer;
    address_ = vk.vkGetBufferDeviceAddress(ctx.device(), &info);
    if (host_visible) ctx.check(vk.vkMapMemory(ctx.device(), memory, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
}

Buffer::Buffer(Buffer&& o) noexcept { *this = std::move(o); }

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        forget_allocation();
        buffer_ = std::move(o.buffer_);  // the old buffer goes before the old memory
        memory_ = std::move(o.memory_);
        ctx_ = o.ctx_;
        size_ = std::exchange(o.size_, 0);
        allocated_ = std::exchange(o.allocated_, 0);
        address_ = std::exchange(o.address_, 0);
        mapped_ = std::exchange(o.mapped_, nullptr);
    }
    return *this;
}

Buffer::~Buffer() { forget_allocation(); }

// The context counts the bytes of live allocations; the owned handles free the rest.
void Buffer::forget_allocation() {
    if (memory_) ctx_->note_allocation(-std::int64_t(allocated_));
}

void grow(VulkanContext& ctx, Buffer& b, std::uint64_t bytes, bool preserve) {
    if (b.size() >= bytes && b.handle()) return;
    if (!preserve) b = Buffer();  // free first: the peak is then the new size, not both
    Buffer bigger(ctx, bytes, false);
    if (preserve && b.size() > 0) {
        VkCommandBuffer cmd = ctx.begin();
        VkBufferCopy all{0, 0, b.size()};
        ctx.vk().vkCmdCopyBuffer(cmd, b.handle(), bigger.handle(), 1, &all);
        ctx.barrier();  // the copy before later shader use
        ctx.submit_and_wait();
    }
    b = std::move(bigger);
}

}  // namespace vrpd::detail
