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

// vkGetInstanceProcAddr of libvulkan.so.1, which opens on the first call and stays open, with its
// drivers loaded, until the process ends: a driver may not survive being unloaded and loaded again
// (NVIDIA's refuses every instance after its 29th load in a process with
// VK_ERROR_INCOMPATIBLE_DRIVER), and a library's user may create and drop many contexts. Throws
// Error if there is no loader on this machine.
PFN_vkGetInstanceProcAddr vulkan_loader();

// "VK_ERROR_OUT_OF_DEVICE_MEMORY", or the number for a code vrpd does not name.
std::string result_name(VkResult r);

// Throws Error("Vulkan: WHAT failed on WHERE: VK_...") unless r is VK_SUCCESS.
void check(VkResult r, const char* what, const std::string& where);

}  // namespace vrpd::detail
