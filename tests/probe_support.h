// Test kernels that run shared/ code on the device (tests/shaders): host arrays copied into
// buffers of their own, and one dispatch waited on.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "vulkan/buffer.h"
#include "vulkan/device.h"
#include "vulkan/kernel.h"

namespace vrpd::test {

// Copies of host arrays in host-visible buffers of their own for a probe kernel (at least one
// word each: an empty array too), by device address.
struct DeviceCopies {
    detail::VulkanContext& ctx;
    std::vector<detail::Buffer> buffers;
    std::uint64_t operator()(const void* data, std::size_t bytes) {
        detail::Buffer& b = buffers.emplace_back(ctx, std::max<std::size_t>(bytes, 8), true);
        if (bytes > 0) std::memcpy(b.mapped(), data, bytes);
        return b.address();
    }
};

// Runs a probe kernel (workgroups of 64) over `count` items and waits for its results.
inline void run_probe(detail::VulkanContext& ctx, const detail::Kernel& probe, const void* push, std::size_t count) {
    ctx.begin();
    ctx.dispatch(probe, push, std::uint32_t((count + 63) / 64));
    ctx.barrier();  // results before the host reads them
    ctx.submit_and_wait();
    ctx.check_validation();
}

}  // namespace vrpd::test
