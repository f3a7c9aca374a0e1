// The Vulkan layer itself: the validation capture that every other test relies on must be able
// to fail, and device selection must refuse what it cannot use.
#include <catch2/catch.hpp>

#include <link.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <set>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "vulkan/buffer.h"
#include "vulkan/device.h"
#include "vulkan/kernel.h"
#include "vulkan/primitives.h"
#include "coverage_probe.h"
#include "support.h"

using namespace vrpd;

TEST_CASE("a validation message becomes an error", "[gpu][vulkan]") {
    REQUIRE(std::getenv("VRPD_VALIDATION") != nullptr);  // ctest sets it for every test
    detail::VulkanContext ctx("");
    VkBufferCreateInfo bad{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bad.size = 0;  // VUID-VkBufferCreateInfo-size-00912: size must be greater than 0
    bad.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
    VkBuffer buffer = VK_NULL_HANDLE;
    ctx.vk().vkCreateBuffer(ctx.device(), &bad, nullptr, &buffer);
    if (buffer) ctx.vk().vkDestroyBuffer(ctx.device(), buffer, nullptr);
    CHECK_THROWS_WITH(ctx.check_validation(), Catch::Contains("00912"));
    CHECK_NOTHROW(ctx.check_validation());  // reported once
}

TEST_CASE("device selection refuses an unknown device", "[gpu][vulkan]") {
    CHECK_THROWS_WITH(detail::VulkanContext("no-such-device-name"), Catch::Contains("no Vulkan device matches"));
    CHECK_THROWS_WITH(detail::VulkanContext("99"), Catch::Contains("no Vulkan device matches"));
    const auto devices = list_devices();
    REQUIRE_FALSE(devices.empty());
    CHECK(detail::VulkanContext("0").device_name().find(devices[0].name) == 0);
}

// The shared objects this process has loaded, by path.
std::set<std::string> loaded_objects() {
    std::set<std::string> names;
    dl_iterate_phdr(
        [](dl_phdr_info* info, std::size_t, void* out) {
            static_cast<std::set<std::string>*>(out)->insert(info->dlpi_name ? info->dlpi_name : "");
            return 0;
        },
        &names);
    return names;
}

// NVIDIA's driver refuses every instance after it has been loaded 29 times in one process
// (VK_ERROR_INCOMPATIBLE_DRIVER), and the loader unloads the drivers with the last instance: a
// renderer or a test that makes and drops contexts must find the drivers already loaded.
TEST_CASE("contexts come and go without the drivers being unloaded and loaded again", "[gpu][vulkan]") {
    detail::VulkanContext("").device_name();
    const std::set<std::string> after_first = loaded_objects();
    for (int i = 0; i < 40; ++i) {
        detail::VulkanContext ctx("");
        std::set<std::string> now = loaded_objects();
        for (const std::string& name : now) {
            INFO("context " << i << " loaded " << name);
            // Layers (validation) come and go with each instance.
            if (name.find("VkLayer") == std::string::npos) CHECK(after_first.count(name) == 1);
        }
    }
}

// Making a run's device and pipelines takes tens of milliseconds: a run's context goes back for
// the next run on the same device, and a run that fails drops its context.
TEST_CASE("a run's context serves the next run on its device, pipelines and all, its counts afresh", "[gpu][vulkan]") {
    const auto make_kernel = [](detail::VulkanContext& ctx) {
        return detail::Kernel(ctx, "coverage_probe", {spirv_coverage_probe, std::size(spirv_coverage_probe)}, 64, 64);
    };
    const detail::VulkanContext* kept = nullptr;
    {
        detail::ContextLease lease("", nullptr);
        make_kernel(lease.get());
        const detail::Buffer b(lease.get(), 4096, true);
        lease.get().begin();
        lease.get().submit_and_wait();
        CHECK(lease.get().submits() == 1);
        kept = &lease.get();
    }
    {
        detail::ContextLease lease("", nullptr);
        REQUIRE(&lease.get() == kept);
        CHECK(lease.get().submits() == 0);
        CHECK(lease.get().peak_allocated_bytes() == 0);
        const std::size_t pipelines = lease.get().pipelines();
        CHECK(pipelines >= 1);
        make_kernel(lease.get());
        CHECK(lease.get().pipelines() == pipelines);  // none made anew
        // While it is held, another run makes a context of its own; of the two back at once, the
        // one with the pipelines stays.
        detail::ContextLease other("", nullptr);
        CHECK(other.get().pipelines() == 0);
    }
    try {
        detail::ContextLease lease("", nullptr);
        REQUIRE(&lease.get() == kept);
        throw Error("a run that fails");
    } catch (const Error&) {
    }
    detail::ContextLease after("", nullptr);
    CHECK(after.get().pipelines() == 0);
}

// A run's kernels ask for their pipelines as its engine is made; the driver compiles them all at
// the first dispatch, on several threads.
TEST_CASE("a context builds the pipelines its kernels ask for together, at the first dispatch", "[gpu][vulkan]") {
    detail::VulkanContext ctx("");
    const std::span<const std::uint32_t> probe{spirv_coverage_probe, std::size(spirv_coverage_probe)};
    std::vector<detail::Kernel> kernels;
    for (std::uint32_t variant = 0; variant < 6; ++variant) kernels.emplace_back(ctx, "probe", probe, 64, 64, variant);
    CHECK(ctx.pipelines() == 6);
    CHECK(ctx.pending_pipelines() == 6);
    for (const detail::Kernel& k : kernels) CHECK(k.pipeline() == VK_NULL_HANDLE);
    const detail::Buffer args(ctx, 12, true);  // an indirect dispatch of no workgroups: nothing runs
    std::memset(args.mapped(), 0, 12);
    const std::array<std::uint8_t, 64> push{};
    ctx.begin();
    ctx.dispatch_indirect(kernels[3], push.data(), args, 0);
    ctx.submit_and_wait();
    CHECK(ctx.pending_pipelines() == 0);
    for (const detail::Kernel& k : kernels) CHECK(k.pipeline() != VK_NULL_HANDLE);
    kernels.emplace_back(ctx, "probe", probe, 64, 64, 2);  // made already
    CHECK(kernels.back().pipeline() == kernels[2].pipeline());
    CHECK(ctx.pending_pipelines() == 0);
    ctx.check_validation();
}

// The prefix sum every list of the engines is built with: one block (SCAN_BLOCK elements) is
// scanned and totalled by its first pass alone, more take all three (the block sums' scan in
// one chunk of 64 and in several). Its first pass by subgroup arithmetic where the device has it
// (lavapipe does), and by shared memory alone.
TEST_CASE("the device's exclusive prefix sum and its total, in one block and in several", "[gpu][vulkan]") {
    detail::VulkanContext ctx("");
    const bool subgroups = GENERATE(true, false);
    INFO("subgroup arithmetic " << subgroups);
    if (!subgroups) ctx.disable_subgroup_scan();
    if (subgroups && ctx.device_name().find("llvmpipe") != std::string::npos) CHECK(ctx.subgroup_scan());
    if (!subgroups) CHECK_FALSE(ctx.subgroup_scan());
    const detail::Buffer counters(ctx, 64, true);
    detail::Primitives primitives(ctx, counters);
    auto* total = static_cast<std::uint32_t*>(counters.mapped());
    for (const std::uint32_t count : {0u, 1u, 511u, 512u, 513u, 5000u, 40000u}) {
        INFO("count " << count);
        const detail::Buffer data(ctx, 4 * std::max(count, 1u), true);
        auto* v = static_cast<std::uint32_t*>(data.mapped());
        std::vector<std::uint32_t> expected(count);
        std::uint32_t sum = 0;
        for (std::uint32_t i = 0; i < count; ++i) {
            v[i] = (i * 2654435761u) >> 28;  // 0 to 15
            expected[i] = sum;
            sum += v[i];
        }
        total[3] = 12345;
        primitives.reserve_scan(count);
        ctx.begin();
        primitives.scan(data.address(), count, 3);
        ctx.submit_and_wait();
        CHECK(std::vector<std::uint32_t>(v, v + count) == expected);
        CHECK(total[3] == sum);
    }
    ctx.check_validation();
}

// The sort that puts a round's samples in arrival order: up to SORT_SMALL points ranked in one
// dispatch, more by the radix passes; both stable. 70 000 points take 137 tiles of SCAN_BLOCK,
// more than one workgroup of the scatter.
TEST_CASE("the device's sort by key, stable, of a few points and of many", "[gpu][vulkan]") {
    detail::VulkanContext ctx("");
    const detail::Buffer counters(ctx, 64, true);
    detail::Primitives primitives(ctx, counters);
    for (const std::uint32_t count : {1u, 2u, 100u, 511u, 512u, 513u, 3000u, 70000u}) {
        INFO("count " << count);
        const detail::Buffer points(ctx, 8 * std::uint64_t(count), true), keys(ctx, 4 * std::uint64_t(count), true),
            tmp(ctx, 12 * std::uint64_t(count), false);
        auto* p = static_cast<std::uint32_t*>(points.mapped());
        auto* k = static_cast<std::uint32_t*>(keys.mapped());
        std::vector<std::pair<std::uint32_t, std::uint32_t>> expected(count);  // (key, point's index)
        for (std::uint32_t i = 0; i < count; ++i) {
            // Keys from few values (ties, whose order the sort keeps) and across every byte.
            k[i] = ((i * 2654435761u) >> 29) * 0x01010101u;
            p[2 * i] = i;
            p[2 * i + 1] = ~i;
            expected[i] = {k[i], i};
        }
        std::stable_sort(expected.begin(), expected.end(),
                         [](const auto& a, const auto& b) { return a.first < b.first; });
        primitives.reserve_sort(count);
        ctx.begin();
        primitives.sort(points.address(), keys.address(), tmp.address(), count, 3);
        ctx.submit_and_wait();
        std::size_t wrong = 0;
        for (std::uint32_t i = 0; i < count; ++i)
            wrong += k[i] != expected[i].first || p[2 * i] != expected[i].second || p[2 * i + 1] != ~expected[i].second;
        CHECK(wrong == 0);
    }
    ctx.check_validation();
}

// Runs on several threads at once each take a context of their own from the process's.
TEST_CASE("runs on four threads at once sample on the device as one run does", "[gpu][vulkan]") {
    const Sampling expected = sample(test::options(0.01, 3, Backend::Cpu));
    std::vector<Sampling> got(4);
    std::vector<std::thread> threads;
    for (std::size_t k = 0; k < got.size(); ++k)
        threads.emplace_back([&, k] { got[k] = sample(test::options(0.01, 3, Backend::Gpu)); });
    for (std::thread& t : threads) t.join();
    for (const Sampling& s : got) CHECK(s.lattice == expected.lattice);
}

TEST_CASE("a buffer larger than the device holds is refused as out of memory", "[gpu][vulkan]") {
    detail::VulkanContext ctx("");
    CHECK_THROWS_WITH(detail::Buffer(ctx, VkDeviceSize(1) << 46, false), Catch::Contains("out of memory on"));
    CHECK(ctx.peak_allocated_bytes() == 0);
    CHECK_NOTHROW(ctx.check_validation());
}

TEST_CASE("errors name the VkResult and the device", "[gpu][vulkan]") {
    CHECK(detail::result_name(VK_ERROR_OUT_OF_DEVICE_MEMORY) == "VK_ERROR_OUT_OF_DEVICE_MEMORY");
    CHECK(detail::result_name(VkResult(-12345)) == "VkResult -12345");
    detail::VulkanContext ctx("");
    CHECK_THROWS_WITH(ctx.check(VK_ERROR_DEVICE_LOST, "vkQueueSubmit"),
                      "Vulkan: vkQueueSubmit failed on " + ctx.device_name() + ": VK_ERROR_DEVICE_LOST");
    CHECK_THROWS_WITH(detail::Buffer(ctx, VkDeviceSize(1) << 46, false), Catch::Contains("VK_ERROR_OUT_OF_"));
}

TEST_CASE("buffers account for their memory through moves, and free it", "[gpu][vulkan]") {
    detail::VulkanContext ctx("");
    {
        detail::Buffer a(ctx, 1 << 20, false);
        const std::uint64_t one = ctx.allocated_bytes();
        CHECK(one >= (1u << 20));
        detail::Buffer b(std::move(a));
        CHECK(ctx.allocated_bytes() == one);
        CHECK(a.handle() == VK_NULL_HANDLE);
        detail::Buffer c(ctx, 1 << 20, true);
        c = std::move(b);  // c's own memory is freed first
        CHECK(ctx.allocated_bytes() == one);
        CHECK(c.mapped() == nullptr);
        detail::grow(ctx, c, 3 << 20, true);
        CHECK(c.size() == (3u << 20));
    }
    CHECK(ctx.allocated_bytes() == 0);
    CHECK(ctx.peak_allocated_bytes() >= (2u << 20));
    CHECK_NOTHROW(ctx.check_validation());
}
