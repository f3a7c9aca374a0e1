// The periodogram on a Vulkan device: one submit per point set (upload, kernel, read-back).
#include "spectrum_kernel.h"

#include <algorithm>
#include <cstring>

#include "buffer.h"
#include "device.h"
#include "kernel.h"
#include "shared/spectrum.h"
#include "spectrum.h"

namespace vrpd::detail {

std::string device_periodogram(const std::vector<std::vector<shared::uvec2>>& sets, std::uint32_t half_width,
                               const std::string& selector, std::vector<double>& sum) {
    constexpr std::uint32_t kWorkgroup = 64;  // the kernel's local_size_x
    ContextLease lease(selector, nullptr);
    VulkanContext& ctx = lease.get();
    const Kernel spectrum(ctx, "spectrum", spirv_words(spirv_spectrum), sizeof(shared::SpectrumArgs), kWorkgroup);
    const auto frequencies = std::uint32_t(sum.size());
    std::size_t largest = 0;
    for (const auto& s : sets) largest = std::max(largest, s.size());
    const VkDeviceSize point_bytes = largest * sizeof(shared::uvec2);
    Buffer staging(ctx, point_bytes, true), points(ctx, point_bytes, false);
    Buffer power(ctx, VkDeviceSize(frequencies) * sizeof(float), true);
    for (const auto& set : sets) {
        const VkDeviceSize bytes = set.size() * sizeof(shared::uvec2);
        std::memcpy(staging.mapped(), set.data(), bytes);
        VkCommandBuffer cmd = ctx.begin();
        const VkBufferCopy all{0, 0, bytes};
        ctx.vk().vkCmdCopyBuffer(cmd, staging.handle(), points.handle(), 1, &all);
        ctx.barrier();
        const shared::SpectrumArgs args{points.address(), power.address(), std::uint32_t(set.size()), half_width,
                                        frequencies, 0};
        ctx.dispatch(spectrum, &args, dispatch_groups(frequencies, kWorkgroup * shared::SPECTRUM_RUN));
        ctx.barrier();  // the kernel's writes before the host reads them
        ctx.submit_and_wait();
        const auto* p = static_cast<const float*>(power.mapped());
        for (std::uint32_t f = 0; f < frequencies; ++f) sum[f] += double(p[f]);
    }
    ctx.check_validation();
    return ctx.device_name();
}

}  // namespace vrpd::detail
