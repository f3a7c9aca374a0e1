// The Vulkan loader: see loader.h.
#include "loader.h"

#include <dlfcn.h>

#include <fmt/format.h>

#include "vrpd/vrpd.h"

namespace vrpd::detail {

Loader::Loader() {
    library_ = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!library_)
        throw Error("no Vulkan loader (libvulkan.so.1) on this machine: install libvulkan1 and a driver "
                    "(e.g. mesa-vulkan-drivers), or use --device cpu");
    get_proc_ = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(library_, "vkGetInstanceProcAddr"));
    if (!get_proc_) {
        dlclose(library_);
        throw Error("the Vulkan loader has no vkGetInstanceProcAddr; use --device cpu");
    }
}

Loader::~Loader() { dlclose(library_); }

std::string result_name(VkResult r) {
    switch (r) {
#define VRPD_RESULT(name) \
    case name: return #name;
        VRPD_RESULT(VK_SUCCESS)
        VRPD_RESULT(VK_NOT_READY)
        VRPD_RESULT(VK_TIMEOUT)
        VRPD_RESULT(VK_INCOMPLETE)
        VRPD_RESULT(VK_ERROR_OUT_OF_HOST_MEMORY)
        VRPD_RESULT(VK_ERROR_OUT_OF_DEVICE_MEMORY)
        VRPD_RESULT(VK_ERROR_INITIALIZATION_FAILED)
        VRPD_RESULT(VK_ERROR_DEVICE_LOST)
        VRPD_RESULT(VK_ERROR_MEMORY_MAP_FAILED)
        VRPD_RESULT(VK_ERROR_LAYER_NOT_PRESENT)
        VRPD_RESULT(VK_ERROR_EXTENSION_NOT_PRESENT)
        VRPD_RESULT(VK_ERROR_FEATURE_NOT_PRESENT)
        VRPD_RESULT(VK_ERROR_INCOMPATIBLE_DRIVER)
        VRPD_RESULT(VK_ERROR_TOO_MANY_OBJECTS)
        VRPD_RESULT(VK_ERROR_FORMAT_NOT_SUPPORTED)
        VRPD_RESULT(VK_ERROR_FRAGMENTED_POOL)
        VRPD_RESULT(VK_ERROR_UNKNOWN)
        VRPD_RESULT(VK_ERROR_OUT_OF_POOL_MEMORY)
        VRPD_RESULT(VK_ERROR_INVALID_EXTERNAL_HANDLE)
        VRPD_RESULT(VK_ERROR_FRAGMENTATION)
        VRPD_RESULT(VK_ERROR_INVALID_OPAQUE_CAPTURE_ADDRESS)
#undef VRPD_RESULT
    default: return fmt::format("VkResult {}", int(r));
    }
}

void check(VkResult r, const char* what, const std::string& where) {
    if (r != VK_SUCCESS) throw Error(fmt::format("Vulkan: {} failed on {}: {}", what, where, result_name(r)));
}

}  // namespace vrpd::detail
