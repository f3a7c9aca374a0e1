// A device buffer with its own memory, addressable from shaders (GL_EXT_buffer_reference).
#pragma once

#include <cstdint>

#include "handles.h"

namespace vrpd::detail {

class VulkanContext;

// Move-only; frees itself. Running out of memory is reported as such, naming the device.
class Buffer {
public:
    Buffer() = default;
    Buffer(VulkanContext& ctx, VkDeviceSize size, bool host_visible);
    Buffer(Buffer&& o) noexcept;
    Buffer& operator=(Buffer&& o) noexcept;
    ~Buffer();

    VkBuffer handle() const { return buffer_.get(); }
    VkDeviceSize size() const { return size_; }
    std::uint64_t address() const { return address_; }
    void* mapped() const { return mapped_; }  // null unless host-visible

private:
    void forget_allocation();
    // The memory before the buffer: the buffer is destroyed first.
    VulkanContext* ctx_ = nullptr;
    OwnedMemory memory_;
    OwnedBuffer buffer_;
    VkDeviceSize size_ = 0;
    VkDeviceSize allocated_ = 0;  // bytes of its memory allocation (size, aligned by the driver)
    std::uint64_t address_ = 0;
    void* mapped_ = nullptr;
};

// Grows b to exactly `bytes` (keeping its contents if `preserve`), unless it holds that much
// already. Never called while recording: a replaced buffer may not be referenced by a pending
// command buffer.
void grow(VulkanContext& ctx, Buffer& b, std::uint64_t bytes, bool preserve = false);

}  // namespace vrpd::detail
