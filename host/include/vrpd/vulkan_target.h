// Sampling on the application's own Vulkan device: a renderer's instance, device and queue, with
// the samples left in a buffer it can bind as a vertex or storage buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>

#include <vulkan/vulkan_core.h>

#include "vrpd/vrpd.h"

namespace vrpd {

// The application's Vulkan objects. vrpd creates no instance or device on them: it makes its own
// command pool, fence, pipelines and buffers on `device` and frees them before it returns (the
// buffer it hands over excepted), or, through a DeviceSampler, when that goes. The device must
// have been created with Vulkan 1.2, the features bufferDeviceAddress (Vulkan 1.2) and
// shaderInt64, and a queue of `queue_family` that has compute. vrpd submits to `queue` from the
// calling thread and waits for its own work each time; the queue is externally synchronised
// (Vulkan's rule): no other thread may use it during a call.
struct VulkanTarget {
    VkInstance instance = VK_NULL_HANDLE;
    VkPhysicalDevice physical_device = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    std::uint32_t queue_family = 0;
    VkQueue queue = VK_NULL_HANDLE;
    // The application's loader entry point; null: vrpd opens libvulkan.so.1 for its own.
    PFN_vkGetInstanceProcAddr get_instance_proc_addr = nullptr;
};

// One sample in the buffer: 16 bytes, usable as a vertex attribute (R32G32B32A32_SFLOAT) or a
// std430 vec4. x, y in box units; t its birth (1 for a direct run); radius = Rf at its birth
// (t S Rf: the spacing of the level it belongs to, for point sizes), or with a sizing field its
// level's r at the sample (t S r, r from Sampling::local_radius).
struct DeviceSample {
    float x, y, t, radius;
};

struct DeviceSamples {
    Sampling sampling;           // the same samples on the host (lattice, birth), for Hierarchy
    VkBuffer buffer = VK_NULL_HANDLE;
    VkDeviceMemory memory = VK_NULL_HANDLE;  // VK_NULL_HANDLE when the caller passed the buffer
    VkDeviceSize bytes = 0;      // sampling.size() * sizeof(DeviceSample)
};

// Samples `options` (its backend must be Auto or Gpu) on the target's device, a varying sizing
// field too, and writes the samples, in birth order, to a buffer on it. The buffer:
// - `into` = VK_NULL_HANDLE: vrpd allocates a device-local buffer (usage vertex, storage, transfer
//   source and destination; exclusive to `queue_family`) and hands it over with its memory: the
//   caller frees both (vkDestroyBuffer, vkFreeMemory) once its own use of them is complete.
// - otherwise: `into` must have transfer-destination usage and at least `bytes` bytes; else Error,
//   naming the size needed, and nothing is written.
// Synchronisation: when this returns, vrpd's work on the queue is complete (it waited on its own
// fence), and its last command is a barrier that makes the buffer's contents visible to any later
// vertex-input, shader or transfer read on the same queue. On another queue family the caller
// transfers ownership of the buffer first. Throws Error with the reason.
DeviceSamples sample_on(const VulkanTarget& target, const SampleOptions& options, VkBuffer into = VK_NULL_HANDLE,
                        VkDeviceSize into_bytes = 0);
// The same from a sizing field tabulated before (vrpd/sizing.h, sample(options, field)).
class SizingField;
DeviceSamples sample_on(const VulkanTarget& target, const SampleOptions& options, const SizingField& field,
                        VkBuffer into = VK_NULL_HANDLE, VkDeviceSize into_bytes = 0);

namespace detail {
class VulkanContext;
}

// sample_on for an application that samples more than once: vrpd's command pool, fence and
// kernels' pipelines on the target's device (tens of milliseconds to make) are made once and kept
// until the DeviceSampler goes, which must be before the device. One thread at a time.
class DeviceSampler {
public:
    // Throws Error as sample_on does for a target it cannot use.
    explicit DeviceSampler(const VulkanTarget& target);
    ~DeviceSampler();
    DeviceSampler(const DeviceSampler&) = delete;
    DeviceSampler& operator=(const DeviceSampler&) = delete;
    // sample_on(target, options, into, into_bytes), on the objects kept.
    DeviceSamples sample(const SampleOptions& options, VkBuffer into = VK_NULL_HANDLE, VkDeviceSize into_bytes = 0);
    // The same from a sizing field tabulated before (vrpd/sizing.h, sample(options, field)): a
    // renderer sampling one field again, with another seed or from other given samples, skips
    // its tabulation.
    DeviceSamples sample(const SampleOptions& options, const SizingField& field, VkBuffer into = VK_NULL_HANDLE,
                         VkDeviceSize into_bytes = 0);
    // The pipelines made on the device so far: a call makes none of those its kernels have.
    std::size_t pipelines() const;

private:
    // The samples of a run on the target to a buffer there (`into`, or one vrpd makes).
    DeviceSamples deliver(Sampling sampling, VkBuffer into, VkDeviceSize into_bytes);
    VulkanTarget target_;
    std::unique_ptr<detail::VulkanContext> ctx_;
};

}  // namespace vrpd
