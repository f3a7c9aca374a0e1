// The Vulkan loader, opened at run time (so hosts without Vulkan still run the host backends),
// the entry points vrpd uses, and errors that name their VkResult.
#pragma once

#define VK_NO_PROTOTYPES
#include <vulkan/vulkan.h>

#include <string>

namespace vrpd::detail {

// The Vulkan entry points vrpd uses, loaded from libvulkan.so.1.
struct VulkanFunctions {
#define VRPD_VK_FN(name) PFN_##name name = nullptr;
#include "functions.inc"
#undef VRPD_VK_FN
};

// libvulkan.so.1, open while this lives. Move-only.
class Loader {
public:
    // Throws Error if there is no loader on this machine.
    Loader();
    Loader(const Loader&) = delete;
    Loader& operator=(const Loader&) = delete;
    ~Loader();
    PFN_vkGetInstanceProcAddr get_instance_proc_addr() const { return get_proc_; }

private:
    void* library_ = nullptr;
    PFN_vkGetInstanceProcAddr get_proc_ = nullptr;
};

// "VK_ERROR_OUT_OF_DEVICE_MEMORY", or the number for a code vrpd does not name.
std::string result_name(VkResult r);

// Throws Error("Vulkan: WHAT failed on WHERE: VK_...") unless r is VK_SUCCESS.
void check(VkResult r, const char* what, const std::string& where);

}  // namespace vrpd::detail
