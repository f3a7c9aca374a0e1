// lod_zoom: an example renderer. It owns its Vulkan instance, device and queue, has vrpd sample a
// hierarchy on them (vrpd::sample_on), and renders a zoom into the box headless: each frame draws
// the prefix of samples born at a radius of at least the on-screen spacing it wants, as disks, by
// a compute kernel of its own, and writes the frame as a PNG. With --check it then verifies, on
// the frames it rendered, that no point pops (every point a frame drew that is still in view is
// drawn by the next) and that the on-screen density stays within a band.
#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include <vulkan/vulkan.h>

#include "splat.h"  // spirv_splat, from splat.comp
#include "vrpd/hierarchy.h"
#include "vrpd/vulkan_target.h"

namespace {

void check(VkResult r, const char* what) {
    if (r != VK_SUCCESS) throw std::runtime_error(std::string(what) + " failed (VkResult " + std::to_string(r) + ")");
}

std::vector<std::string> messages;
VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT, VkDebugUtilsMessageTypeFlagsEXT,
                                          const VkDebugUtilsMessengerCallbackDataEXT* data, void*) {
    messages.emplace_back(data->pMessage ? data->pMessage : "");
    return VK_FALSE;
}

// The frame's view: a square of side `width` (box units) at `origin`, zooming geometrically from the
// whole unit box towards `focus`, which keeps its place on the screen.
struct View {
    double x0, y0, width;
    bool contains(glm::dvec2 p) const { return p.x >= x0 && p.y >= y0 && p.x < x0 + width && p.y < y0 + width; }
};
View frame_view(int f, int frames, double zoom, glm::dvec2 focus) {
    const double w = std::pow(zoom, -double(f) / double(frames - 1));
    return {focus.x * (1 - w), focus.y * (1 - w), w};
}

struct Options {
    double radius = 0.002;
    unsigned steps = 10, frames = 24, size = 512;
    double zoom = 8, spacing = 8;  // spacing: the on-screen distance wanted between points, pixels
    std::string out = "lod_zoom";
    bool verify = false;
};

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
            return argv[++i];
        };
        if (a == "--radius") o.radius = std::stod(next());
        else if (a == "--steps") o.steps = unsigned(std::stoul(next()));
        else if (a == "--frames") o.frames = unsigned(std::stoul(next()));
        else if (a == "--size") o.size = unsigned(std::stoul(next()));
        else if (a == "--zoom") o.zoom = std::stod(next());
        else if (a == "--spacing") o.spacing = std::stod(next());
        else if (a == "--out") o.out = next();
        else if (a == "--check") o.verify = true;
        else throw std::runtime_error("unknown option " + a +
                                      " (--radius R --steps K --frames F --size PX --zoom Z --spacing PX --out DIR "
                                      "--check)");
    }
    if (o.frames < 2 || o.size < 16 || o.size > 8192 || !(o.zoom >= 1) || !(o.spacing > 0))
        throw std::runtime_error("need --frames >= 2, --size 16..8192, --zoom >= 1, --spacing > 0");
    return o;
}

// The application's Vulkan objects, made as a renderer makes them.
struct App {
    VkInstance instance = VK_NULL_HANDLE;
    VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
    VkPhysicalDevice physical = VK_NULL_HANDLE;
    VkDevice device = VK_NULL_HANDLE;
    std::uint32_t family = 0;
    VkQueue queue = VK_NULL_HANDLE;

    explicit App(bool validate) {
        VkApplicationInfo ai{VK_STRUCTURE_TYPE_APPLICATION_INFO};
        ai.pApplicationName = "lod_zoom";
        ai.apiVersion = VK_API_VERSION_1_2;
        const char* layer = "VK_LAYER_KHRONOS_validation";
        const char* extension = VK_EXT_DEBUG_UTILS_EXTENSION_NAME;
        VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
        ci.pApplicationInfo = &ai;
        ci.enabledLayerCount = validate ? 1 : 0;
        ci.ppEnabledLayerNames = &layer;
        ci.enabledExtensionCount = validate ? 1 : 0;
        ci.ppEnabledExtensionNames = &extension;
        check(vkCreateInstance(&ci, nullptr, &instance), "vkCreateInstance");
        if (validate) {
            VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
            mi.messageSeverity =
                VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
            mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                             VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
            mi.pfnUserCallback = &on_message;
            auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkCreateDebugUtilsMessengerEXT"));
            check(create(instance, &mi, nullptr, &messenger), "vkCreateDebugUtilsMessengerEXT");
        }
        std::uint32_t n = 1;
        VkResult r = vkEnumeratePhysicalDevices(instance, &n, &physical);
        if (n == 0 || (r != VK_SUCCESS && r != VK_INCOMPLETE)) throw std::runtime_error("no Vulkan device");
        std::uint32_t qn = 0;
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &qn, nullptr);
        std::vector<VkQueueFamilyProperties> queues(qn);
        vkGetPhysicalDeviceQueueFamilyProperties(physical, &qn, queues.data());
        while (family < qn && !(queues[family].queueFlags & VK_QUEUE_COMPUTE_BIT)) ++family;
        if (family == qn) throw std::runtime_error("no compute queue");
        float priority = 1;
        VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
        qi.queueFamilyIndex = family;
        qi.queueCount = 1;
        qi.pQueuePriorities = &priority;
        VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        f12.bufferDeviceAddress = VK_TRUE;  // what vrpd needs of the device
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
        features.features.shaderInt64 = VK_TRUE;
        VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
        di.queueCreateInfoCount = 1;
        di.pQueueCreateInfos = &qi;
        check(vkCreateDevice(physical, &di, nullptr, &device), "vkCreateDevice");
        vkGetDeviceQueue(device, family, 0, &queue);
    }
    ~App() {
        if (device) vkDestroyDevice(device, nullptr);
        if (messenger)
            reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(
                vkGetInstanceProcAddr(instance, "vkDestroyDebugUtilsMessengerEXT"))(instance, messenger, nullptr);
        if (instance) vkDestroyInstance(instance, nullptr);
    }
    std::uint32_t host_memory(std::uint32_t allowed) const {
        VkPhysicalDeviceMemoryProperties props;
        vkGetPhysicalDeviceMemoryProperties(physical, &props);
        const VkMemoryPropertyFlags want = VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT;
        for (std::uint32_t i = 0; i < props.memoryTypeCount; ++i)
            if ((allowed & (1u << i)) && (props.memoryTypes[i].propertyFlags & want) == want) return i;
        throw std::runtime_error("no host-visible memory");
    }
};

struct Push {
    float origin[2], scale, disk;
    std::uint32_t count, size;
};

int run(const Options& o) {
    const bool validate = std::getenv("VRPD_VALIDATION") && std::strcmp(std::getenv("VRPD_VALIDATION"), "0") != 0;
    App app(validate);
    {
        vrpd::SampleOptions so;
        so.radius = o.radius;
        so.hierarchy.steps = o.steps;
        const vrpd::VulkanTarget target{app.instance, app.physical, app.device, app.family, app.queue, nullptr};
        vrpd::DeviceSamples samples = vrpd::sample_on(target, so);
        const vrpd::Hierarchy h(samples.sampling);
        std::filesystem::create_directories(o.out);

        // The image: one uint per pixel, host-visible for the PNG.
        const VkDeviceSize image_bytes = VkDeviceSize(o.size) * o.size * 4;
        VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
        bi.size = image_bytes;
        bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT;
        VkBuffer image;
        check(vkCreateBuffer(app.device, &bi, nullptr, &image), "vkCreateBuffer");
        VkMemoryRequirements req;
        vkGetBufferMemoryRequirements(app.device, image, &req);
        VkMemoryAllocateInfo mai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
        mai.allocationSize = req.size;
        mai.memoryTypeIndex = app.host_memory(req.memoryTypeBits);
        VkDeviceMemory image_memory;
        check(vkAllocateMemory(app.device, &mai, nullptr, &image_memory), "vkAllocateMemory");
        check(vkBindBufferMemory(app.device, image, image_memory, 0), "vkBindBufferMemory");
        void* mapped = nullptr;
        check(vkMapMemory(app.device, image_memory, 0, VK_WHOLE_SIZE, 0, &mapped), "vkMapMemory");
        auto* pixels = static_cast<std::uint32_t*>(mapped);

        // The splat kernel: two storage buffers and the view as push constants.
        VkDescriptorSetLayoutBinding bindings[2]{};
        for (std::uint32_t b = 0; b < 2; ++b)
            bindings[b] = {b, VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 1, VK_SHADER_STAGE_COMPUTE_BIT, nullptr};
        VkDescriptorSetLayoutCreateInfo li{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_LAYOUT_CREATE_INFO};
        li.bindingCount = 2;
        li.pBindings = bindings;
        VkDescriptorSetLayout set_layout;
        check(vkCreateDescriptorSetLayout(app.device, &li, nullptr, &set_layout), "vkCreateDescriptorSetLayout");
        const VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof(Push)};
        VkPipelineLayoutCreateInfo pli{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
        pli.setLayoutCount = 1;
        pli.pSetLayouts = &set_layout;
        pli.pushConstantRangeCount = 1;
        pli.pPushConstantRanges = &range;
        VkPipelineLayout layout;
        check(vkCreatePipelineLayout(app.device, &pli, nullptr, &layout), "vkCreatePipelineLayout");
        VkShaderModuleCreateInfo smi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
        smi.codeSize = sizeof(spirv_splat);
        smi.pCode = spirv_splat;
        VkShaderModule module;
        check(vkCreateShaderModule(app.device, &smi, nullptr, &module), "vkCreateShaderModule");
        VkComputePipelineCreateInfo cpi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
        cpi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO, nullptr, 0, VK_SHADER_STAGE_COMPUTE_BIT,
                     module, "main", nullptr};
        cpi.layout = layout;
        VkPipeline pipeline;
        check(vkCreateComputePipelines(app.device, VK_NULL_HANDLE, 1, &cpi, nullptr, &pipeline),
              "vkCreateComputePipelines");
        const VkDescriptorPoolSize pool_size{VK_DESCRIPTOR_TYPE_STORAGE_BUFFER, 2};
        VkDescriptorPoolCreateInfo dpi{VK_STRUCTURE_TYPE_DESCRIPTOR_POOL_CREATE_INFO};
        dpi.maxSets = 1;
        dpi.poolSizeCount = 1;
        dpi.pPoolSizes = &pool_size;
        VkDescriptorPool descriptor_pool;
        check(vkCreateDescriptorPool(app.device, &dpi, nullptr, &descriptor_pool), "vkCreateDescriptorPool");
        VkDescriptorSetAllocateInfo dsa{VK_STRUCTURE_TYPE_DESCRIPTOR_SET_ALLOCATE_INFO};
        dsa.descriptorPool = descriptor_pool;
        dsa.descriptorSetCount = 1;
        dsa.pSetLayouts = &set_layout;
        VkDescriptorSet set;
        check(vkAllocateDescriptorSets(app.device, &dsa, &set), "vkAllocateDescriptorSets");
        const VkDescriptorBufferInfo infos[2]{{samples.buffer, 0, samples.bytes}, {image, 0, image_bytes}};
        VkWriteDescriptorSet writes[2]{};
        for (std::uint32_t b = 0; b < 2; ++b) {
            writes[b] = {VK_STRUCTURE_TYPE_WRITE_DESCRIPTOR_SET};
            writes[b].dstSet = set;
            writes[b].dstBinding = b;
            writes[b].descriptorCount = 1;
            writes[b].descriptorType = VK_DESCRIPTOR_TYPE_STORAGE_BUFFER;
            writes[b].pBufferInfo = &infos[b];
        }
        vkUpdateDescriptorSets(app.device, 2, writes, 0, nullptr);
        VkCommandPoolCreateInfo cpool{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
        cpool.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
        cpool.queueFamilyIndex = app.family;
        VkCommandPool command_pool;
        check(vkCreateCommandPool(app.device, &cpool, nullptr, &command_pool), "vkCreateCommandPool");
        VkCommandBufferAllocateInfo cba{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
        cba.commandPool = command_pool;
        cba.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
        cba.commandBufferCount = 1;
        VkCommandBuffer cmd;
        check(vkAllocateCommandBuffers(app.device, &cba, &cmd), "vkAllocateCommandBuffers");
        VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
        VkFence fence;
        check(vkCreateFence(app.device, &fi, nullptr, &fence), "vkCreateFence");

        const glm::dvec2 focus{0.37, 0.61};
        std::vector<std::uint32_t> previous;  // the last frame
        std::size_t previous_count = 0;
        View previous_view{};
        int failures = 0;
        std::printf("frame  view width  radius drawn  samples  in view  n r^2 / view area\n");
        for (unsigned f = 0; f < o.frames; ++f) {
            const View v = frame_view(int(f), int(o.frames), o.zoom, focus);
            const double scale = o.size / v.width, wanted = o.spacing / scale;
            // Wider spacings than the hierarchy's first level draw that level.
            const std::size_t count = std::max(h.count_at_radius(wanted), h.count_at(1.0));
            const double drawn_radius = count == 0 ? 0 : double(h.birth()[count - 1]) * h.rf0();
            std::memset(pixels, 0, image_bytes);
            check(vkResetCommandBuffer(cmd, 0), "vkResetCommandBuffer");
            VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
            begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
            check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
            vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, pipeline);
            vkCmdBindDescriptorSets(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, layout, 0, 1, &set, 0, nullptr);
            const Push push{{float(v.x0), float(v.y0)}, float(scale), float(0.35 * o.spacing), std::uint32_t(count),
                            o.size};
            vkCmdPushConstants(cmd, layout, VK_SHADER_STAGE_COMPUTE_BIT, 0, sizeof push, &push);
            vkCmdDispatch(cmd, std::uint32_t((count + 63) / 64), 1, 1);
            // The kernel's writes before the host reads the image.
            VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
            mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT;
            mb.dstAccessMask = VK_ACCESS_HOST_READ_BIT;
            vkCmdPipelineBarrier(cmd, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT, VK_PIPELINE_STAGE_HOST_BIT, 0, 1, &mb, 0,
                                 nullptr, 0, nullptr);
            check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
            VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
            si.commandBufferCount = 1;
            si.pCommandBuffers = &cmd;
            check(vkQueueSubmit(app.queue, 1, &si, fence), "vkQueueSubmit");
            check(vkWaitForFences(app.device, 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
            check(vkResetFences(app.device, 1, &fence), "vkResetFences");
            const std::vector<std::uint32_t> frame(pixels, pixels + std::size_t(o.size) * o.size);

            cairo_surface_t* png = cairo_image_surface_create(CAIRO_FORMAT_RGB24, int(o.size), int(o.size));
            unsigned char* data = cairo_image_surface_get_data(png);
            const int stride = cairo_image_surface_get_stride(png);
            for (unsigned y = 0; y < o.size; ++y)
                for (unsigned x = 0; x < o.size; ++x)
                    reinterpret_cast<std::uint32_t*>(data + y * stride)[x] =
                        frame[y * o.size + x] ? 0x202020 : 0xFFFFFF;
            cairo_surface_mark_dirty(png);
            char name[32];
            std::snprintf(name, sizeof name, "/frame%03u.png", f);
            const cairo_status_t written = cairo_surface_write_to_png(png, (o.out + name).c_str());
            cairo_surface_destroy(png);
            if (written != CAIRO_STATUS_SUCCESS) throw std::runtime_error("cannot write " + o.out + name);

            std::size_t in_view = 0;
            for (std::size_t i = 0; i < count; ++i) in_view += v.contains(h.points()[i]) ? 1 : 0;
            const double density = double(in_view) * drawn_radius * drawn_radius / (v.width * v.width);
            std::printf("%5u  %10.5f  %12.6f  %7zu  %7zu  %.3f\n", f, v.width, drawn_radius, count, in_view, density);
            if (o.verify) {
                // No popping: each point the last frame drew, still in view, is drawn here.
                for (std::size_t i = 0; f > 0 && i < previous_count; ++i) {
                    const glm::dvec2 p = h.points()[i];
                    if (!previous_view.contains(p) || !v.contains(p)) continue;
                    const auto x = unsigned((p.x - v.x0) * scale), y = unsigned((p.y - v.y0) * scale);
                    if (x < o.size && y < o.size && !frame[(o.size - 1 - y) * o.size + x]) {
                        std::printf("frame %u: sample %zu, drawn in frame %u, is missing\n", f, i, f - 1);
                        ++failures;
                    }
                }
                // Density at the radius drawn: a maximal sampling has n r^2 / area near 0.7; a view
                // a few hundred points wide moves it by a few percent.
                if (!(density >= 0.5 && density <= 0.8)) {
                    std::printf("frame %u: n r^2 / view area %.3f is outside [0.5, 0.8]\n", f, density);
                    ++failures;
                }
            }
            previous = frame;
            previous_count = count;
            previous_view = v;
        }
        vkDestroyFence(app.device, fence, nullptr);
        vkDestroyCommandPool(app.device, command_pool, nullptr);
        vkDestroyDescriptorPool(app.device, descriptor_pool, nullptr);
        vkDestroyPipeline(app.device, pipeline, nullptr);
        vkDestroyShaderModule(app.device, module, nullptr);
        vkDestroyPipelineLayout(app.device, layout, nullptr);
        vkDestroyDescriptorSetLayout(app.device, set_layout, nullptr);
        vkUnmapMemory(app.device, image_memory);
        vkDestroyBuffer(app.device, image, nullptr);
        vkFreeMemory(app.device, image_memory, nullptr);
        vkDestroyBuffer(app.device, samples.buffer, nullptr);  // handed over by vrpd
        vkFreeMemory(app.device, samples.memory, nullptr);
        if (failures) return 1;
    }
    vkDestroyDevice(app.device, nullptr);
    app.device = VK_NULL_HANDLE;
    if (!messages.empty()) {
        std::printf("validation: %zu message(s); first: %s\n", messages.size(), messages.front().c_str());
        return 1;
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(parse(argc, argv));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "lod_zoom: error: %s\n", e.what());
        return 2;
    }
}
