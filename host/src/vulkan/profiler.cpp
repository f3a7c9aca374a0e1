// Device-side profiling: see profiler.h.
#include "profiler.h"

#include <fmt/format.h>

#include "device.h"
#include "kernel.h"

namespace vrpd::detail {

Profiler::Profiler(const VulkanContext& ctx) : ctx_(ctx) {
    const VulkanFunctions& vk = ctx.vk();
    VkPhysicalDeviceProperties props;
    vk.vkGetPhysicalDeviceProperties(ctx.physical(), &props);
    std::uint32_t n = 0;
    vk.vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical(), &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vk.vkGetPhysicalDeviceQueueFamilyProperties(ctx.physical(), &n, families.data());
    timestamp_bits_ = families[ctx.queue_family()].timestampValidBits;
    timestamp_ns_ = props.limits.timestampPeriod;
    if (timestamp_bits_ == 0 || timestamp_ns_ <= 0.0)
        throw Error(fmt::format("{} has no timestamps on its compute queue, which profiling needs; try --device cpu",
                                ctx.device_name()));
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = kQueries;
    VkQueryPool pool = VK_NULL_HANDLE;
    ctx.check(vk.vkCreateQueryPool(ctx.device(), &qi, nullptr, &pool), "vkCreateQueryPool");
    queries_ = own<OwnedQueryPool>(vk, ctx.device(), pool);
}

void Profiler::begin(VkCommandBuffer cmd) {
    timed_.clear();
    ctx_.vk().vkCmdResetQueryPool(cmd, queries_.get(), 0, kQueries);
    ctx_.vk().vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(), 0);
}

void Profiler::after(VkCommandBuffer cmd, const Kernel& k) {
    if (timed_.size() + 1 >= kQueries)
        throw Error("internal: more dispatches in one submit than profiling has timestamps");
    timed_.push_back(&k);
    ctx_.vk().vkCmdWriteTimestamp(cmd, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_.get(),
                                  std::uint32_t(timed_.size()));
}

void Profiler::read() {
    if (timed_.empty()) return;
    std::vector<std::uint64_t> ticks(timed_.size() + 1);
    ctx_.check(ctx_.vk().vkGetQueryPoolResults(
                   ctx_.device(), queries_.get(), 0, std::uint32_t(ticks.size()), ticks.size() * sizeof(std::uint64_t),
                   ticks.data(), sizeof(std::uint64_t), VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
               "vkGetQueryPoolResults");
    const std::uint64_t mask = timestamp_bits_ >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << timestamp_bits_) - 1;
    for (std::size_t i = 0; i < timed_.size(); ++i)
        times_.add(timed_[i]->name(), double((ticks[i + 1] - ticks[i]) & mask) * timestamp_ns_ * 1e-9);
    timed_.clear();
}

}  // namespace vrpd::detail
