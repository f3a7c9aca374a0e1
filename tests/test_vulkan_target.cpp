// Sampling on an application's own Vulkan device (vrpd/vulkan_target.h): the test plays the
// application, with its own instance (validation layers on under the suite's VRPD_VALIDATION, its
// own messenger), device and queue, and checks the buffers vrpd leaves there against the cpu
// backend's samples, and that the validation layers said nothing from the instance's creation to
// its destruction.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "support.h"
#include "vrpd/hierarchy.h"
#include "vrpd/sizing.h"
#include "vrpd/vulkan_target.h"
#include "vulkan/loader.h"

using namespace vrpd;

namespace {

VKAPI_ATTR VkBool32 VKAPI_CALL count_message(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                             const VkDebugUtilsMessengerCallbackDataEXT* data, void* messages) {
    static_cast<std::vector<std::string>*>(messages)->emplace_back(data->pMessage ? data->pMessage : "");
    return VK_FALSE;
}

// The application: an instance (with validation where the suite runs with it, VRPD_VALIDATION),
// the first device vrpd can use, a compute queue.
struct Application {
    detail::VulkanFunctions vk;
    std::vector<std::string> messages;
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    std::uint32_t family = 0;
    VkQueue queue = VK_NULL_HANDLE;

    Application() {
        const PFN_vkGetInstanceProcAddr get = detail::vulkan_loader();
        vk.vkCreateInstance = reinterpret_cast<PFN_vkCreateInstance>(get(nullptr, "vkCreateInstance"));
        VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        app.pApplicationName = "a renderer";
        app.apiVersion = VK_API_VERSION_1_2;
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        const char* validation = std::getenv("VRPD_VALIDATION");
        const bool validate = validation && *validation && std::strcmp(validation, "0") != 0;
        VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ci.pApplicationInfo = &app;
        ci.enabledLayerCount = validate ? 1 : 0;
        ci.ppEnabledLayerNames = &layer;
        ci.enabledExtensionCount = validate ? 1 : 0;
        ci.ppEnabledExtensionNames = &extension;
        REQUIRE(vk.vkCreateInstance(&ci, nullptr, &instance) == VK_SUCCESS);
#define VRPD_VK_FN(name) \
    if (!vk.name) vk.name = reinterpret_cast<PFN_##name>(get(instance, #name));
#include "vulkan/functions.inc"
#undef VRPD_VK_FN
        if (validate) {
            VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            mi.messageSeverity =
                VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
            mi.pfnUserCallback = &count_message;
            mi.pUserData = &messages;
            REQUIRE(vk.vkCreateDebugUtilsMessengerEXT(instance, &mi, nullptr, &messenger) == VK_SUCCESS);
        }
        std::uint32_t n = 0;
        vk.vkEnumeratePhysicalDevices(instance, &n, nullptr);
        std::vector<VkPhysicalDevice> all(n);
        vk.vkEnumeratePhysicalDevices(instance, &n, all.data());
        REQUIRE(n > 0);
        physical = all.front();
        std::uint32_t qn = 0;
        vk.vkGetPhysicalDeviceQueueFamilyProperties(physical, &qn, nullptr);
        std::vector<VkQueueFamilyProperties> queues(qn);
        vk.vkGetPhysicalDeviceQueueFamilyProperties(physical, &qn, queues.data());
        while (family < qn && !(queues[family].queueFlags & VK_QUEUE_COMPUTE_BIT)) ++family;
        REQUIRE(family < qn);
        float priority = 1;
        VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        qi.queueFamilyIndex = family;
        qi.queueCount = 1;
        qi.pQueuePriorities = &priority;
        VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        f12.bufferDeviceAddress = VK_TRUE;
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
        features.features.shaderInt64 = VK_TRUE;
        VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
        di.queueCreateInfoCount = 1;
        di.pQueueCreateInfos = &qi;
        REQUIRE(vk.vkCreateDevice(physical, &di, nullptr, &device) == VK_SUCCESS);
        vk.vkGetDeviceQueue(device, family, 0, &queue);
    }
    Application(const Application&) = delete;
    Application& operator=(const Application&) = delete;
    ~Application() {
        if (device) vk.vkDestroyDevice(device, nullptr);
        if (messenger) vk.vkDestroyDebugUtilsMessengerEXT(instance, messenger, nullptr);
        if (instance) vk.vkDestroyInstance(instance, nullptr);
    }
    VulkanTarget target() const { return {instance, physical, device, family, queue, detail::vulkan_loader()}; }

    // A host-visible, coherent memory type among `allowed`, or ~0u.
    std::uint32_t host_visible(std::uint32_t allowed) const {
        VkPhysicalDeviceMemoryProperties props;
        vk.vkGetPhysicalDeviceMemoryProperties(physical, &props);
        const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i)
            if ((allowed & (1u << i)) && (props.memoryTypes[i].propertyFlags & want) == want) return i;
        return ~0u;
    }
    // Is the memory type vrpd picks for its buffer (the first device-local one) host-visible?
    bool device_local_readable(std::uint32_t allowed) const {
        VkPhysicalDeviceMemoryProperties props;
        vk.vkGetPhysicalDeviceMemoryProperties(physical, &props);
        for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i)
            if ((allowed & (1u << i)) && (props.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT))
                return (props.memoryTypes[i].propertyFlags & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) != 0;
        return false;
    }
    // The contents of host-visible `memory`.
    std::vector<DeviceSample> read(VkDeviceMemory memory, std::size_t count) const {
        void* p = nullptr;
        REQUIRE(vk.vkMapMemory(device, memory, 0, VK_WHOLE_SIZE, 0, &p) == VK_SUCCESS);
        std::vector<DeviceSample> out(count);
        std::memcpy(out.data(), p, count * sizeof(DeviceSample));
        vk.vkUnmapMemory(device, memory);
        return out;
    }
};

void check_rows(const std::vector<DeviceSample>& rows, const Sampling& expected) {
    REQUIRE(rows.size() == expected.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
        const glm::dvec2 p = expected.point(i);
        const double t = expected.birth.empty() ? 1.0 : expected.birth[i];
        INFO("sample " << i);
        REQUIRE(rows[i].x == float(p.x));
        REQUIRE(rows[i].y == float(p.y));
        REQUIRE(rows[i].t == float(t));
        REQUIRE(rows[i].radius == float(expected.radius * t * expected.hierarchy_start));
    }
}

}  // namespace

TEST_CASE(
    "a varying sizing field's hierarchy on the application's device: sampled by its kernels there (auto and "
    "gpu), each row with its level's r at it",
    "[vulkan][gpu][field]") {
    Application app;
    const VulkanTarget target = app.target();
    SampleOptions o = test::options(0, 4, Backend::Auto, {1, 1, Boundary::Free});
    o.sizing = Sizing{"0.01 + 0.02*x", "", 0, 0, -1, SizingRule::Bigger, Weighting::Uniform};
    o.hierarchy = {3, 0};
    SampleOptions on_cpu = o;
    on_cpu.backend = Backend::Cpu;
    const Sampling expected = sample(on_cpu);
    REQUIRE(expected.local_radius.size() == expected.size());

    const DeviceSamples made = sample_on(target, o);
    CHECK(made.sampling.lattice == expected.lattice);
    CHECK(made.sampling.backend == Backend::Gpu);
    CHECK(made.sampling.choice == "the options give the application's Vulkan device");
    VkMemoryRequirements req;
    app.vk.vkGetBufferMemoryRequirements(app.device, made.buffer, &req);
    if (app.device_local_readable(req.memoryTypeBits)) {
        const std::vector<DeviceSample> rows = app.read(made.memory, expected.size());
        for (std::size_t i = 0; i < rows.size(); ++i) {
            INFO("sample " << i);
            REQUIRE(rows[i].x == float(expected.point(i).x));
            REQUIRE(rows[i].t == float(expected.birth[i]));
            REQUIRE(rows[i].radius == float(expected.local_radius[i] * expected.birth[i] * 3));
            REQUIRE(rows[i].radius >= 0.0099f);
        }
    }
    app.vk.vkDestroyBuffer(app.device, made.buffer, nullptr);
    app.vk.vkFreeMemory(app.device, made.memory, nullptr);

    SampleOptions gpu = o, cpu = o;
    gpu.backend = Backend::Gpu;
    // On Gpu the field's kernels run there, each level with the cpu backend's points.
    const DeviceSamples on_device = sample_on(target, gpu);
    CHECK(on_device.sampling.lattice == expected.lattice);
    CHECK(on_device.sampling.birth == expected.birth);
    CHECK(on_device.sampling.backend == Backend::Gpu);
    app.vk.vkDestroyBuffer(app.device, on_device.buffer, nullptr);
    app.vk.vkFreeMemory(app.device, on_device.memory, nullptr);
    // From a field tabulated before, the same levels.
    const DeviceSamples reused = sample_on(target, gpu, SizingField(*o.sizing, o.box));
    CHECK(reused.sampling.lattice == expected.lattice);
    CHECK(reused.sampling.birth == expected.birth);
    app.vk.vkDestroyBuffer(app.device, reused.buffer, nullptr);
    app.vk.vkFreeMemory(app.device, reused.memory, nullptr);
    cpu.backend = Backend::Cpu;
    CHECK_THROWS_WITH(sample_on(target, cpu), Catch::Contains("needs the gpu backend"));
    app.vk.vkDestroyDevice(app.device, nullptr);
    app.device = VK_NULL_HANDLE;
    INFO((app.messages.empty() ? std::string() : app.messages.front()));
    CHECK(app.messages.empty());
}

// A renderer that samples again (another seed, radius or field) finds its pipelines made.
TEST_CASE("a DeviceSampler keeps its pipelines on the application's device from call to call, and frees them",
          "[vulkan][gpu]") {
    Application app;
    SampleOptions o = test::options(0.02, 5, Backend::Gpu);
    SampleOptions field = test::options(0, 6, Backend::Gpu, {1, 1, Boundary::Free});
    field.sizing = Sizing{"0.02 + 0.02*x", "", 0, 0, -1, SizingRule::Smaller, Weighting::Uniform};
    {
        DeviceSampler sampler(app.target());
        CHECK(sampler.pipelines() == 0);
        std::size_t made = 0;
        for (std::uint32_t seed : {5u, 6u}) {
            o.seed = seed;
            SampleOptions on_cpu = o;
            on_cpu.backend = Backend::Cpu;
            const DeviceSamples out = sampler.sample(o);
            CHECK(out.sampling.lattice == sample(on_cpu).lattice);
            if (seed == 5) made = sampler.pipelines();
            CHECK(made > 10);
            CHECK(sampler.pipelines() == made);  // the second call makes none
            app.vk.vkDestroyBuffer(app.device, out.buffer, nullptr);
            app.vk.vkFreeMemory(app.device, out.memory, nullptr);
        }
        // A field's kernels are made once too.
        SampleOptions field_cpu = field;
        field_cpu.backend = Backend::Cpu;
        const Sampling expected = sample(field_cpu);
        for (int call = 0; call < 2; ++call) {
            const DeviceSamples out = sampler.sample(field);
            CHECK(out.sampling.lattice == expected.lattice);
            if (call == 0) {
                CHECK(sampler.pipelines() > made);
                made = sampler.pipelines();
            }
            CHECK(sampler.pipelines() == made);
            app.vk.vkDestroyBuffer(app.device, out.buffer, nullptr);
            app.vk.vkFreeMemory(app.device, out.memory, nullptr);
        }
        // A field tabulated once, sampled again with another seed: the cpu's points, no new pipeline.
        const SizingField tabulated(*field.sizing, field.box);
        field.seed = field_cpu.seed = 7;
        const DeviceSamples out = sampler.sample(field, tabulated);
        CHECK(out.sampling.lattice == sample(field_cpu).lattice);
        CHECK(out.sampling.lattice != expected.lattice);
        CHECK(out.bytes == out.sampling.size() * sizeof(DeviceSample));
        CHECK(sampler.pipelines() == made);
        app.vk.vkDestroyBuffer(app.device, out.buffer, nullptr);
        app.vk.vkFreeMemory(app.device, out.memory, nullptr);
    }
    // The sampler gone, nothing of vrpd's is left on the device.
    app.vk.vkDestroyDevice(app.device, nullptr);
    app.device = VK_NULL_HANDLE;
    INFO((app.messages.empty() ? std::string() : app.messages.front()));
    CHECK(app.messages.empty());
}

TEST_CASE("sampling on the application's device: its buffer, the cpu backend's points, no validation message",
          "[vulkan][gpu][hierarchy]") {
    Application app;
    const VulkanTarget target = app.target();
    SampleOptions o = test::options(0.02, 5, Backend::Auto);
    o.hierarchy = {5, 0};
    SampleOptions on_cpu = o;
    on_cpu.backend = Backend::Cpu;
    const Sampling expected = sample(on_cpu);

    // vrpd allocates the buffer and hands it over.
    DeviceSamples made = sample_on(target, o);
    CHECK(made.sampling.lattice == expected.lattice);
    CHECK(made.sampling.device.find("the application's device") != std::string::npos);
    REQUIRE(made.buffer != VK_NULL_HANDLE);
    REQUIRE(made.memory != VK_NULL_HANDLE);
    CHECK(made.bytes == expected.size() * 16);
    VkMemoryRequirements req;
    app.vk.vkGetBufferMemoryRequirements(app.device, made.buffer, &req);
    CHECK(req.size >= made.bytes);
    // lavapipe's device-local memory is host-visible: the buffer can be read here directly.
    if (app.device_local_readable(req.memoryTypeBits)) check_rows(app.read(made.memory, expected.size()), expected);
    const Hierarchy levels(made.sampling);
    CHECK(levels.count_at(1.0) < levels.size());
    app.vk.vkDestroyBuffer(app.device, made.buffer, nullptr);  // the caller frees what it was handed
    app.vk.vkFreeMemory(app.device, made.memory, nullptr);

    // The application's own buffer: too small is refused, large enough is filled.
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = expected.size() * 16;
    bi.usage = VK_BUFFER_USAGE_TRANSFER_DST_BIT | VK_BUFFER_USAGE_VERTEX_BUFFER_BIT;
    VkBuffer own = VK_NULL_HANDLE;
    REQUIRE(app.vk.vkCreateBuffer(app.device, &bi, nullptr, &own) == VK_SUCCESS);
    app.vk.vkGetBufferMemoryRequirements(app.device, own, &req);
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = app.host_visible(req.memoryTypeBits);
    REQUIRE(ai.memoryTypeIndex != ~0u);
    VkDeviceMemory own_memory = VK_NULL_HANDLE;
    REQUIRE(app.vk.vkAllocateMemory(app.device, &ai, nullptr, &own_memory) == VK_SUCCESS);
    REQUIRE(app.vk.vkBindBufferMemory(app.device, own, own_memory, 0) == VK_SUCCESS);
    CHECK_THROWS_WITH(sample_on(target, o, own, bi.size - 16), Catch::Contains("samples need"));
    const DeviceSamples filled = sample_on(target, o, own, bi.size);
    CHECK(filled.buffer == own);
    CHECK(filled.memory == VK_NULL_HANDLE);
    check_rows(app.read(own_memory, expected.size()), expected);
    app.vk.vkDestroyBuffer(app.device, own, nullptr);
    app.vk.vkFreeMemory(app.device, own_memory, nullptr);

    SampleOptions wrong = o;
    wrong.backend = Backend::Cpu;
    CHECK_THROWS_WITH(sample_on(target, wrong), Catch::Contains("needs the gpu backend"));
    VulkanTarget missing = target;
    missing.queue = VK_NULL_HANDLE;
    CHECK_THROWS_WITH(sample_on(missing, o), Catch::Contains("must all be given"));

    // Everything vrpd made on the device is gone before the application destroys it: the
    // validation layers, which report objects left on a destroyed device, say nothing.
    app.vk.vkDestroyDevice(app.device, nullptr);
    app.device = VK_NULL_HANDLE;
    INFO((app.messages.empty() ? std::string() : app.messages.front()));
    CHECK(app.messages.empty());
}
