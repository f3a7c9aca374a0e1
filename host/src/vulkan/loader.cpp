// The Vulkan loader: see loader.h.
#include "loader.h"

#include <dlfcn.h>

#include <fmt/format.h>

#include "vrpd/vrpd.h"

namespace vrpd::detail {

PFN_vkGetInstanceProcAddr vulkan_loader() {
    static void* const library = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!library)
        throw Error("no Vulkan loader (libvulkan.so.1) on this machine: install libvulkan1 and a driver "
                    "(e.g. mesa-vulkan-drivers), or use --device cpu");
    static const auto get_proc = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(library, "vkGetInstanceProcAddr"));
    if (!get_proc) throw Error("the Vulkan loader has no vkGetInstanceProcAddr; use --device cpu");
    // The loader unloads the drivers when the last instance goes. One instance that lives until
    // the process ends keeps them loaded; where it cannot be made, the context's own instance
    // reports why.
    static const VkInstance anchor = [] {
        auto create = reinterpret_cast<PFN_vkCreateInstance>(get_proc(nullptr, "vkCreateInstance"));
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.apiVersion = VK_API_VERSION_1_2;
        VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ci.pApplicationInfo = &app;
        VkInstance instance = VK_NULL_HANDLE;
        return create && create(&ci, nullptr, &instance) == VK_SUCCESS ? instance : VK_NULL_HANDLE;
    }();
    (void)anchor;
    return get_proc;
}

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
