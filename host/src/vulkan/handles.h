// Ownership of Vulkan handles: each one has exactly one owner, which destroys it. A constructor
// that fails part-way frees what it made, since the members made so far are destroyed.
#pragma once

#include <utility>

#include "loader.h"

namespace vrpd::detail {

// A move-only owner of handle T; Destroyer(handle) frees it. VK_NULL_HANDLE owns nothing.
template <class T, class Destroyer>
class Owned {
public:
    Owned() = default;
    Owned(Destroyer destroy, T handle) : destroy_(destroy), handle_(handle) {}
    Owned(Owned&& o) noexcept { *this = std::move(o); }
    Owned& operator=(Owned&& o) noexcept {
        if (this != &o) {
            reset();
            destroy_ = o.destroy_;
            handle_ = std::exchange(o.handle_, VK_NULL_HANDLE);
        }
        return *this;
    }
    ~Owned() { reset(); }
    T get() const { return handle_; }
    // Hands the handle over: it is no longer freed here.
    T release() { return std::exchange(handle_, VK_NULL_HANDLE); }
    explicit operator bool() const { return handle_ != VK_NULL_HANDLE; }

private:
    void reset() {
        if (handle_ != VK_NULL_HANDLE) destroy_(handle_);
        handle_ = VK_NULL_HANDLE;
    }
    Destroyer destroy_{};
    T handle_ = VK_NULL_HANDLE;
};

// Destroyers: vkDestroyX(handle, allocator) for the instance and the device,
// vkDestroyX(parent, handle, allocator) for what is made on them.
template <class T, auto VulkanFunctions::*Destroy>
struct DestroyRoot {
    const VulkanFunctions* vk = nullptr;
    void operator()(T h) const { (vk->*Destroy)(h, nullptr); }
};
template <class Parent, class T, auto VulkanFunctions::*Destroy>
struct DestroyChild {
    const VulkanFunctions* vk = nullptr;
    Parent parent = VK_NULL_HANDLE;
    void operator()(T h) const { (vk->*Destroy)(parent, h, nullptr); }
};

template <class T, auto VulkanFunctions::*Destroy>
using RootHandle = Owned<T, DestroyRoot<T, Destroy>>;
template <class T, auto VulkanFunctions::*Destroy>
using DeviceHandle = Owned<T, DestroyChild<VkDevice, T, Destroy>>;

using OwnedInstance = RootHandle<VkInstance, &VulkanFunctions::vkDestroyInstance>;
using OwnedDevice = RootHandle<VkDevice, &VulkanFunctions::vkDestroyDevice>;
using OwnedMessenger = Owned<VkDebugUtilsMessengerEXT, DestroyChild<VkInstance, VkDebugUtilsMessengerEXT,
                                                                   &VulkanFunctions::vkDestroyDebugUtilsMessengerEXT>>;
using OwnedBuffer = DeviceHandle<VkBuffer, &VulkanFunctions::vkDestroyBuffer>;
using OwnedMemory = DeviceHandle<VkDeviceMemory, &VulkanFunctions::vkFreeMemory>;
using OwnedShaderModule = DeviceHandle<VkShaderModule, &VulkanFunctions::vkDestroyShaderModule>;
using OwnedPipelineLayout = DeviceHandle<VkPipelineLayout, &VulkanFunctions::vkDestroyPipelineLayout>;
using OwnedPipeline = DeviceHandle<VkPipeline, &VulkanFunctions::vkDestroyPipeline>;
using OwnedCommandPool = DeviceHandle<VkCommandPool, &VulkanFunctions::vkDestroyCommandPool>;
using OwnedFence = DeviceHandle<VkFence, &VulkanFunctions::vkDestroyFence>;
using OwnedQueryPool = DeviceHandle<VkQueryPool, &VulkanFunctions::vkDestroyQueryPool>;

// Makes an owner of `handle` created on `parent` (or a root handle, without a parent).
template <class O, class T>
O own(const VulkanFunctions& vk, T handle) { return O({&vk}, handle); }
template <class O, class Parent, class T>
O own(const VulkanFunctions& vk, Parent parent, T handle) { return O({&vk, parent}, handle); }

}  // namespace vrpd::detail
