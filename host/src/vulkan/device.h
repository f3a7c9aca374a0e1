// A Vulkan device for vrpd: the instance (with the validation layers and their messages when
// VRPD_VALIDATION is set), device selection, the compute queue, and one command buffer with one
// fence per submit. Buffers (buffer.h) and kernels (kernel.h) are made on it.
#pragma once

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "handles.h"
#include "kernel.h"
#include "loader.h"
#include "phase_times.h"
#include "vrpd/vrpd.h"
#include "vrpd/vulkan_target.h"

namespace vrpd::detail {

class Buffer;
class Profiler;

class VulkanContext {
public:
    // Opens the loader and the instance; throws Error if there is no loader or no driver.
    VulkanContext();
    // The same, then open_device(selector).
    explicit VulkanContext(const std::string& selector) : VulkanContext() { open_device(selector); }
    // On the application's instance and device (vrpd/vulkan_target.h), which it neither creates
    // nor destroys; throws Error if the physical device lacks what vrpd needs.
    explicit VulkanContext(const VulkanTarget& target);
    ~VulkanContext();
    VulkanContext(const VulkanContext&) = delete;
    VulkanContext& operator=(const VulkanContext&) = delete;

    std::vector<DeviceInfo> devices() const;
    // Opens the device chosen by `selector` (index or name substring; empty: $VRPD_DEVICE, else the
    // best usable device: discrete, integrated, virtual, then CPU).
    void open_device(const std::string& selector);

    const VulkanFunctions& vk() const { return vk_; }
    VkDevice device() const { return device_handle_; }
    VkPhysicalDevice physical() const { return physical_; }
    std::uint32_t queue_family() const { return queue_family_; }
    const std::string& device_name() const { return device_name_; }
    // Whether compute shaders have subgroup arithmetic with subgroups of at most 64 invocations,
    // which the scans' first pass then uses (primitives.h). Tests turn it off, so that both of
    // its bodies run.
    bool subgroup_scan() const { return subgroup_scan_; }
    void disable_subgroup_scan() { subgroup_scan_ = false; }
    // Throws Error("Vulkan: WHAT failed on DEVICE: VK_...") unless r is VK_SUCCESS.
    void check(VkResult r, const char* what) const;
    std::uint32_t memory_type(std::uint32_t allowed, bool host_visible) const;
    std::uint64_t device_heap_bytes() const;
    // Device memory held by vrpd's buffers now, and at most so far (Buffer reports its allocations).
    void note_allocation(std::int64_t bytes);
    std::uint64_t allocated_bytes() const { return allocated_; }
    std::uint64_t peak_allocated_bytes() const { return peak_allocated_; }

    // Recording into the one command buffer, and submitting it (waits on a fence).
    VkCommandBuffer begin();
    VkCommandBuffer recording() const { return cmd_; }  // the command buffer begin() returned
    void submit_and_wait();
    std::uint64_t submits() const { return submits_; }  // submit_and_wait calls so far
    // Makes every shader write before it visible to every shader read and indirect read after it.
    void barrier();
    // Records `groups` workgroups of k in rows of at most row_groups_ (kMaxWorkgroups: a dispatch's
    // count along x is limited, to 65 535 on many devices); the kernels number their items across
    // the rows (work_item(), shared/kernels.h), and a row may hold a few workgroups past `groups`.
    void dispatch(const Kernel& k, const void* push, std::uint32_t groups);
    // Tests set fewer workgroups a row, so that every dispatch of more takes several rows.
    void set_row_groups(std::uint32_t groups) { row_groups_ = std::max<std::uint32_t>(groups, 1); }
    void dispatch_indirect(const Kernel& k, const void* push, const Buffer& args, VkDeviceSize offset);
    // Between open_gate and close_gate, dispatch() records indirect dispatches whose commands it
    // writes to `table` (host-visible, kGateDispatches commands of 3 words). open_gate first
    // records gate.comp, which zeroes their group counts, and with them the gated work, while
    // counter word `slot` of the array at device address `counters` is not 0.
    static constexpr std::uint32_t kGateDispatches = 64;
    void open_gate(const Buffer& table, std::uint64_t counters, std::uint32_t slot);
    void close_gate() { gate_ = nullptr; }

    // Validation messages (VRPD_VALIDATION=1); throws Error with the first if there were any.
    void check_validation();

    // From now on, times every dispatch with device timestamps (profiler.h). Throws Error if the
    // queue has no timestamps.
    void start_profile();
    std::vector<PhaseTime> profile() const;

    // The pipeline of a kernel's SPIR-V (by its address), push-constant size, workgroup size and
    // variant (kernel.h), kept until the context goes: its layout made at once, the pipeline
    // itself (the driver's compilation: tens of milliseconds, a second for a field run's kernels
    // on lavapipe) by build_pending, which the first dispatch of a kernel not yet built calls.
    const KernelPipeline& pipeline(std::span<const std::uint32_t> spirv, std::uint32_t push_size,
                                   std::uint32_t workgroup, std::uint32_t variant);
    // Builds every pipeline asked for and not yet built, several at once on the host's threads:
    // a run's kernels are asked for together, as its engine is made.
    void build_pending();
    std::size_t pipelines() const { return pipelines_.size(); }
    std::size_t pending_pipelines() const { return pending_.size(); }

    // A run starts on a context a run before may have used (ContextLease): its memory peak,
    // submits and profile start afresh, and no gate is open.
    void start_run();
    // No buffer, gate or validation message left over: fit for another run.
    bool idle() const { return allocated_ == 0 && gate_ == nullptr && messages_.empty(); }

private:
    static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT*, void*);

    // In creation order, so that destruction runs in reverse: the messenger outlives the device
    // and hears about its destruction.
    // Helpers of the constructors: the instance-level entry points from get_proc, the command
    // pool, command buffer and fence on the device, and subgroup_scan's answer.
    void load_functions(PFN_vkGetInstanceProcAddr get_proc, VkInstance instance);
    void make_command_objects();
    bool query_subgroup_scan() const;

    VulkanFunctions vk_;
    std::mutex messages_mutex_;  // the validation layers may call on_message from build_pending's threads
    std::vector<std::string> messages_;
    OwnedInstance instance_;
    OwnedMessenger messenger_;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties memory_{};
    std::uint32_t queue_family_ = 0;
    bool subgroup_scan_ = false;
    std::string device_name_;
    OwnedDevice device_;             // empty on an application's device
    VkInstance instance_handle_ = VK_NULL_HANDLE;
    VkDevice device_handle_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    OwnedCommandPool pool_;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;  // freed with its pool
    OwnedFence fence_;
    std::unique_ptr<Profiler> profiler_;
    std::uint64_t allocated_ = 0;
    std::uint64_t peak_allocated_ = 0;
    std::uint64_t submits_ = 0;
    std::uint32_t row_groups_ = kMaxWorkgroups;
    const Buffer* gate_ = nullptr;  // the open gate's table, if any
    std::uint32_t gated_ = 0;       // dispatches recorded through it
    // After the device: destroyed before it.
    std::map<std::tuple<const std::uint32_t*, std::uint32_t, std::uint32_t, std::uint32_t>, KernelPipeline> pipelines_;
    std::vector<KernelPipeline*> pending_;  // entries of pipelines_ not yet built
    std::unique_ptr<Kernel> gate_kernel_;  // gate.comp, made by the first open_gate
};

// The context of one run: on the application's device (its DeviceSampler's, else one made for
// the run), or one of the process's, taken from those earlier runs left idle on the same device
// and given back when the lease ends, so that a run finds its device and pipelines made. Contexts
// go back only from a run that ended normally, with nothing left over; the process keeps one idle
// context per device until it exits.
class ContextLease {
public:
    ContextLease(const std::string& selector, const VulkanTarget* target);
    ~ContextLease();
    ContextLease(const ContextLease&) = delete;
    ContextLease& operator=(const ContextLease&) = delete;
    VulkanContext& get() { return *use_; }

private:
    std::unique_ptr<VulkanContext> ctx_;  // none when borrowed from a DeviceSampler
    VulkanContext* use_ = nullptr;
    std::string key_;  // empty: the application's device, never kept
    int exceptions_;   // std::uncaught_exceptions() when the lease began
};

// A DeviceSampler's context for its target (the sampler's own copy, by address), which the runs
// on that target borrow; null withdraws it.
void lend_context(const VulkanTarget* target, VulkanContext* ctx);

}  // namespace vrpd::detail
