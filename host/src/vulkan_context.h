// Vulkan for vrpd: the loader opened at run time (so hosts without Vulkan still run the CPU
// backends), device selection, validation-message capture, buffers with device addresses,
// compute pipelines, and one command buffer with one fence per submit.
#pragma once

#define VK_NO_PROTOTYPES
#include <vulkan/vulkan.h>

#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "phase_times.h"
#include "vrpd/vrpd.h"

namespace vrpd::detail {

// The Vulkan entry points vrpd uses, loaded from libvulkan.so.1.
struct VulkanFunctions {
#define VRPD_VK_FN(name) PFN_##name name = nullptr;
#include "vulkan_functions.inc"
#undef VRPD_VK_FN
};

class VulkanContext;

// A buffer with its own memory, addressable from shaders. Move-only; frees itself.
class Buffer {
public:
    Buffer() = default;
    Buffer(VulkanContext& ctx, VkDeviceSize size, bool host_visible);
    Buffer(Buffer&& o) noexcept { *this = std::move(o); }
    Buffer& operator=(Buffer&& o) noexcept;
    ~Buffer();

    VkBuffer handle() const { return buffer_; }
    VkDeviceSize size() const { return size_; }
    std::uint64_t address() const { return address_; }
    void* mapped() const { return mapped_; }  // null unless host-visible

private:
    void release();
    VulkanContext* ctx_ = nullptr;
    VkBuffer buffer_ = VK_NULL_HANDLE;
    VkDeviceMemory memory_ = VK_NULL_HANDLE;
    VkDeviceSize size_ = 0;
    VkDeviceSize allocated_ = 0;  // bytes of its memory allocation (size, aligned by the driver)
    std::uint64_t address_ = 0;
    void* mapped_ = nullptr;
};

// A compute pipeline with a push-constant block of push_size bytes and no descriptor sets.
class Kernel {
public:
    Kernel(VulkanContext& ctx, std::string name, std::span<const std::uint32_t> spirv, std::uint32_t push_size,
           std::uint32_t workgroup);
    Kernel(const Kernel&) = delete;
    Kernel& operator=(const Kernel&) = delete;
    ~Kernel();
    VkPipeline pipeline() const { return pipeline_; }
    VkPipelineLayout layout() const { return layout_; }
    std::uint32_t push_size() const { return push_size_; }
    const std::string& name() const { return name_; }

private:
    VulkanContext& ctx_;
    std::string name_;
    VkPipelineLayout layout_ = VK_NULL_HANDLE;
    VkPipeline pipeline_ = VK_NULL_HANDLE;
    std::uint32_t push_size_;
};

class VulkanContext {
public:
    // Opens the loader and the instance; throws Error if there is no loader or no driver.
    VulkanContext();
    // The same, then open_device(selector).
    explicit VulkanContext(const std::string& selector) : VulkanContext() { open_device(selector); }
    ~VulkanContext();
    VulkanContext(const VulkanContext&) = delete;
    VulkanContext& operator=(const VulkanContext&) = delete;

    std::vector<DeviceInfo> devices() const;
    // Opens the device chosen by `selector` (index or name substring; empty: $VRPD_DEVICE, else the
    // best usable device: discrete, integrated, virtual, then CPU).
    void open_device(const std::string& selector);

    const VulkanFunctions& vk() const { return vk_; }
    VkDevice device() const { return device_; }
    const std::string& device_name() const { return device_name_; }
    std::uint32_t memory_type(std::uint32_t allowed, bool host_visible) const;
    std::uint64_t device_heap_bytes() const;
    // Device memory held by vrpd's buffers now, and at most so far (Buffer reports its allocations).
    void note_allocation(std::int64_t bytes);
    std::uint64_t allocated_bytes() const { return allocated_; }
    std::uint64_t peak_allocated_bytes() const { return peak_allocated_; }

    // Recording into the one command buffer, and submitting it (waits on a fence).
    VkCommandBuffer begin();
    void submit_and_wait();
    // Makes every shader write before it visible to every shader read and indirect read after it.
    void barrier();
    void dispatch(const Kernel& k, const void* push, std::uint32_t groups);
    void dispatch_indirect(const Kernel& k, const void* push, const Buffer& args, VkDeviceSize offset);

    // Validation messages (VRPD_VALIDATION=1); throws Error with the first if there were any.
    void check_validation();

    // From now on, times every dispatch with device timestamps: from the end of the work recorded
    // before it to its own end. Throws Error if the queue has no timestamps.
    void start_profile();
    const std::vector<PhaseTime>& profile() const { return times_.phases(); }

private:
    static constexpr std::uint32_t kQueries = 256;  // timestamps per submit: far more than its dispatches
    void write_timestamp(const Kernel& k);
    void read_timestamps();

    void* library_ = nullptr;
    VulkanFunctions vk_;
    VkInstance instance_ = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
    VkPhysicalDevice physical_ = VK_NULL_HANDLE;
    VkPhysicalDeviceMemoryProperties memory_{};
    VkDevice device_ = VK_NULL_HANDLE;
    VkQueue queue_ = VK_NULL_HANDLE;
    std::uint32_t queue_family_ = 0;
    VkCommandPool pool_ = VK_NULL_HANDLE;
    VkCommandBuffer cmd_ = VK_NULL_HANDLE;
    VkFence fence_ = VK_NULL_HANDLE;
    std::string device_name_;
    std::vector<std::string> messages_;
    std::uint64_t allocated_ = 0;
    std::uint64_t peak_allocated_ = 0;
    // Profiling: timestamp 0 at begin(), then one after each dispatch, named in timed_.
    VkQueryPool queries_ = VK_NULL_HANDLE;
    std::uint32_t timestamp_bits_ = 0;
    double timestamp_ns_ = 0.0;  // nanoseconds per timestamp tick
    std::vector<const Kernel*> timed_;
    PhaseTimes times_;

    static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                     VkDebugUtilsMessageTypeFlagsEXT,
                                                     const VkDebugUtilsMessengerCallbackDataEXT*, void*);
};

}  // namespace vrpd::detail
