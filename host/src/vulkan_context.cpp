// Vulkan context: see vulkan_context.h.
#include "vulkan_context.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <dlfcn.h>

#include <fmt/format.h>

namespace vrpd::detail {
namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

void check(VkResult r, const char* what) {
    if (r != VK_SUCCESS) throw Error(fmt::format("Vulkan: {} failed (VkResult {})", what, int(r)));
}

const char* type_name(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return "discrete";
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return "integrated";
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return "virtual";
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return "cpu";
    default: return "other";
    }
}

int preference(VkPhysicalDeviceType t) {
    switch (t) {
    case VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU: return 4;
    case VK_PHYSICAL_DEVICE_TYPE_INTEGRATED_GPU: return 3;
    case VK_PHYSICAL_DEVICE_TYPE_VIRTUAL_GPU: return 2;
    case VK_PHYSICAL_DEVICE_TYPE_CPU: return 1;
    default: return 0;
    }
}

bool validation_requested() {
    const char* v = std::getenv("VRPD_VALIDATION");
    return v && std::strcmp(v, "0") != 0 && *v;
}

}  // namespace

VKAPI_ATTR VkBool32 VKAPI_CALL VulkanContext::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT,
                                                         VkDebugUtilsMessageTypeFlagsEXT,
                                                         const VkDebugUtilsMessengerCallbackDataEXT* data, void* self) {
    static_cast<VulkanContext*>(self)->messages_.emplace_back(data->pMessage ? data->pMessage : "(no text)");
    return VK_FALSE;
}

VulkanContext::VulkanContext() {
    library_ = dlopen("libvulkan.so.1", RTLD_NOW | RTLD_LOCAL);
    if (!library_)
        throw Error("no Vulkan loader (libvulkan.so.1) on this machine: install libvulkan1 and a driver "
                    "(e.g. mesa-vulkan-drivers), or use --device cpu");
    auto get_proc = reinterpret_cast<PFN_vkGetInstanceProcAddr>(dlsym(library_, "vkGetInstanceProcAddr"));
    if (!get_proc) throw Error("the Vulkan loader has no vkGetInstanceProcAddr; use --device cpu");
    vk_.vkCreateInstance = reinterpret_cast<PFN_vkCreateInstance>(get_proc(nullptr, "vkCreateInstance"));
    vk_.vkEnumerateInstanceLayerProperties = reinterpret_cast<PFN_vkEnumerateInstanceLayerProperties>(
        get_proc(nullptr, "vkEnumerateInstanceLayerProperties"));

    const bool validate = validation_requested();
    std::vector<const char*> layers, extensions;
    if (validate) {
        std::uint32_t n = 0;
        vk_.vkEnumerateInstanceLayerProperties(&n, nullptr);
        std::vector<VkLayerProperties> props(n);
        vk_.vkEnumerateInstanceLayerProperties(&n, props.data());
        bool found = std::any_of(props.begin(), props.end(),
                                 [](const VkLayerProperties& p) { return std::strcmp(p.layerName, kValidationLayer) == 0; });
        if (!found) throw Error("VRPD_VALIDATION is set but VK_LAYER_KHRONOS_validation is not installed (vulkan-validationlayers)");
        layers.push_back(kValidationLayer);
        extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
    }
    VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
    app.pApplicationName = "vrpd";
    app.apiVersion = VK_API_VERSION_1_2;
    VkInstanceCreateInfo ci{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
    ci.pApplicationInfo = &app;
    ci.enabledLayerCount = std::uint32_t(layers.size());
    ci.ppEnabledLayerNames = layers.data();
    ci.enabledExtensionCount = std::uint32_t(extensions.size());
    ci.ppEnabledExtensionNames = extensions.data();
    VkResult r = vk_.vkCreateInstance(&ci, nullptr, &instance_);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw Error("no Vulkan 1.2 driver on this machine (install mesa-vulkan-drivers for lavapipe), or use --device cpu");
    check(r, "vkCreateInstance");
#define VRPD_VK_FN(name) \
    if (!vk_.name) vk_.name = reinterpret_cast<PFN_##name>(get_proc(instance_, #name));
#include "vulkan_functions.inc"
#undef VRPD_VK_FN
    if (validate) {
        VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        mi.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        mi.pfnUserCallback = &VulkanContext::on_message;
        mi.pUserData = this;
        check(vk_.vkCreateDebugUtilsMessengerEXT(instance_, &mi, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
    }
}

VulkanContext::~VulkanContext() {
    if (device_) {
        if (queries_) vk_.vkDestroyQueryPool(device_, queries_, nullptr);
        if (fence_) vk_.vkDestroyFence(device_, fence_, nullptr);
        if (pool_) vk_.vkDestroyCommandPool(device_, pool_, nullptr);
        vk_.vkDestroyDevice(device_, nullptr);
    }
    if (messenger_) vk_.vkDestroyDebugUtilsMessengerEXT(instance_, messenger_, nullptr);
    if (instance_) vk_.vkDestroyInstance(instance_, nullptr);
    if (library_) dlclose(library_);
}

namespace {
struct Candidate {
    VkPhysicalDevice handle;
    DeviceInfo info;
    VkPhysicalDeviceType type;
    std::uint32_t queue_family;
};

std::vector<Candidate> enumerate(const VulkanFunctions& vk, VkInstance instance) {
    std::uint32_t n = 0;
    vk.vkEnumeratePhysicalDevices(instance, &n, nullptr);
    std::vector<VkPhysicalDevice> handles(n);
    vk.vkEnumeratePhysicalDevices(instance, &n, handles.data());
    std::vector<Candidate> out;
    for (std::uint32_t i = 0; i < n; ++i) {
        VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
        VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
        vk.vkGetPhysicalDeviceProperties2(handles[i], &props);
        VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
        VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
        vk.vkGetPhysicalDeviceFeatures2(handles[i], &features);
        std::uint32_t qn = 0;
        vk.vkGetPhysicalDeviceQueueFamilyProperties(handles[i], &qn, nullptr);
        std::vector<VkQueueFamilyProperties> queues(qn);
        vk.vkGetPhysicalDeviceQueueFamilyProperties(handles[i], &qn, queues.data());
        std::uint32_t family = UINT32_MAX;
        for (std::uint32_t q = 0; q < qn && family == UINT32_MAX; ++q)
            if (queues[q].queueFlags & VK_QUEUE_COMPUTE_BIT) family = q;
        const bool usable = props.properties.apiVersion >= VK_API_VERSION_1_2 && features.features.shaderInt64 &&
                            f12.bufferDeviceAddress && family != UINT32_MAX;
        out.push_back({handles[i],
                       {i, props.properties.deviceName, type_name(props.properties.deviceType),
                        fmt::format("{} {}", driver.driverName, driver.driverInfo), usable},
                       props.properties.deviceType, family});
    }
    return out;
}
}  // namespace

std::vector<DeviceInfo> VulkanContext::devices() const {
    std::vector<DeviceInfo> out;
    for (auto& c : enumerate(vk_, instance_)) out.push_back(c.info);
    return out;
}

void VulkanContext::open_device(const std::string& requested) {
    std::string selector = requested;
    if (selector.empty())
        if (const char* env = std::getenv("VRPD_DEVICE")) selector = env;
    auto all = enumerate(vk_, instance_);
    if (all.empty()) throw Error("no Vulkan device found (install mesa-vulkan-drivers for lavapipe), or use --device cpu");
    const Candidate* pick = nullptr;
    if (!selector.empty()) {
        bool numeric = std::all_of(selector.begin(), selector.end(), [](unsigned char ch) { return std::isdigit(ch); });
        for (auto& c : all) {
            if (numeric ? std::to_string(c.info.index) == selector : c.info.name.find(selector) != std::string::npos) {
                pick = &c;
                break;
            }
        }
        if (!pick) throw Error(fmt::format("no Vulkan device matches '{}' (see `vrpd devices`)", selector));
        if (!pick->info.usable)
            throw Error(fmt::format("Vulkan device '{}' lacks Vulkan 1.2, shaderInt64 or bufferDeviceAddress; use --device cpu",
                                    pick->info.name));
    } else {
        for (auto& c : all)
            if (c.info.usable && (!pick || preference(c.type) > preference(pick->type))) pick = &c;
        if (!pick) throw Error("no Vulkan device has Vulkan 1.2, shaderInt64 and bufferDeviceAddress; use --device cpu");
    }
    physical_ = pick->handle;
    queue_family_ = pick->queue_family;
    device_name_ = fmt::format("{} ({}, {})", pick->info.name, pick->info.type, pick->info.driver);
    vk_.vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);

    float priority = 1.0f;
    VkDeviceQueueCreateInfo qi{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
    qi.queueFamilyIndex = queue_family_;
    qi.queueCount = 1;
    qi.pQueuePriorities = &priority;
    VkPhysicalDeviceVulkan12Features f12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    f12.bufferDeviceAddress = VK_TRUE;
    VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2, &f12};
    features.features.shaderInt64 = VK_TRUE;
    VkDeviceCreateInfo di{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO, &features};
    di.queueCreateInfoCount = 1;
    di.pQueueCreateInfos = &qi;
    check(vk_.vkCreateDevice(physical_, &di, nullptr, &device_), "vkCreateDevice");
    vk_.vkGetDeviceQueue(device_, queue_family_, 0, &queue_);

    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = queue_family_;
    check(vk_.vkCreateCommandPool(device_, &pi, nullptr, &pool_), "vkCreateCommandPool");
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool_;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    check(vk_.vkAllocateCommandBuffers(device_, &ai, &cmd_), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    check(vk_.vkCreateFence(device_, &fi, nullptr, &fence_), "vkCreateFence");
    check_validation();
}

std::uint32_t VulkanContext::memory_type(std::uint32_t allowed, bool host_visible) const {
    const VkMemoryPropertyFlags want = host_visible
                                           ? VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT
                                           : VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT;
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
        if ((allowed & (1u << i)) && (memory_.memoryTypes[i].propertyFlags & want) == want) return i;
    for (std::uint32_t i = 0; i < memory_.memoryTypeCount; ++i)
        if (allowed & (1u << i)) return i;
    throw Error("Vulkan: no memory type for a buffer");
}

std::uint64_t VulkanContext::device_heap_bytes() const {
    std::uint64_t best = 0;
    for (std::uint32_t i = 0; i < memory_.memoryHeapCount; ++i)
        if (memory_.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT) best = std::max(best, memory_.memoryHeaps[i].size);
    return best;
}

VkCommandBuffer VulkanContext::begin() {
    check(vk_.vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vk_.vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
    if (queries_) {
        timed_.clear();
        vk_.vkCmdResetQueryPool(cmd_, queries_, 0, kQueries);
        vk_.vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, 0);
    }
    return cmd_;
}

void VulkanContext::start_profile() {
    if (queries_) return;
    VkPhysicalDeviceProperties props;
    vk_.vkGetPhysicalDeviceProperties(physical_, &props);
    std::uint32_t n = 0;
    vk_.vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, nullptr);
    std::vector<VkQueueFamilyProperties> families(n);
    vk_.vkGetPhysicalDeviceQueueFamilyProperties(physical_, &n, families.data());
    timestamp_bits_ = families[queue_family_].timestampValidBits;
    timestamp_ns_ = props.limits.timestampPeriod;
    if (timestamp_bits_ == 0 || timestamp_ns_ <= 0.0)
        throw Error(fmt::format("{} has no timestamps on its compute queue, which profiling needs; try --device cpu",
                                device_name_));
    VkQueryPoolCreateInfo qi{VK_STRUCTURE_TYPE_QUERY_POOL_CREATE_INFO};
    qi.queryType = VK_QUERY_TYPE_TIMESTAMP;
    qi.queryCount = kQueries;
    check(vk_.vkCreateQueryPool(device_, &qi, nullptr, &queries_), "vkCreateQueryPool");
}

// Adds the timestamps of the submit just finished to the kernels' times.
void VulkanContext::read_timestamps() {
    if (!queries_ || timed_.empty()) return;
    std::vector<std::uint64_t> ticks(timed_.size() + 1);
    check(vk_.vkGetQueryPoolResults(device_, queries_, 0, std::uint32_t(ticks.size()),
                                    ticks.size() * sizeof(std::uint64_t), ticks.data(), sizeof(std::uint64_t),
                                    VK_QUERY_RESULT_64_BIT | VK_QUERY_RESULT_WAIT_BIT),
          "vkGetQueryPoolResults");
    const std::uint64_t mask = timestamp_bits_ >= 64 ? ~std::uint64_t(0) : (std::uint64_t(1) << timestamp_bits_) - 1;
    for (std::size_t i = 0; i < timed_.size(); ++i)
        times_.add(timed_[i]->name(), double((ticks[i + 1] - ticks[i]) & mask) * timestamp_ns_ * 1e-9);
    timed_.clear();
}

void VulkanContext::write_timestamp(const Kernel& k) {
    if (!queries_) return;
    if (timed_.size() + 1 >= kQueries)
        throw Error("internal: more dispatches in one submit than profiling has timestamps");
    timed_.push_back(&k);
    vk_.vkCmdWriteTimestamp(cmd_, VK_PIPELINE_STAGE_BOTTOM_OF_PIPE_BIT, queries_, std::uint32_t(timed_.size()));
}

void VulkanContext::barrier() {
    VkMemoryBarrier mb{VK_STRUCTURE_TYPE_MEMORY_BARRIER};
    mb.srcAccessMask = VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_TRANSFER_WRITE_BIT;
    mb.dstAccessMask = VK_ACCESS_SHADER_READ_BIT | VK_ACCESS_SHADER_WRITE_BIT | VK_ACCESS_INDIRECT_COMMAND_READ_BIT |
                       VK_ACCESS_TRANSFER_READ_BIT | VK_ACCESS_TRANSFER_WRITE_BIT | VK_ACCESS_HOST_READ_BIT;
    vk_.vkCmdPipelineBarrier(cmd_, VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_TRANSFER_BIT,
                             VK_PIPELINE_STAGE_COMPUTE_SHADER_BIT | VK_PIPELINE_STAGE_DRAW_INDIRECT_BIT |
                                 VK_PIPELINE_STAGE_TRANSFER_BIT | VK_PIPELINE_STAGE_HOST_BIT,
                             0, 1, &mb, 0, nullptr, 0, nullptr);
}

void VulkanContext::note_allocation(std::int64_t bytes) {
    allocated_ += std::uint64_t(bytes);
    peak_allocated_ = std::max(peak_allocated_, allocated_);
}

void VulkanContext::dispatch(const Kernel& k, const void* push, std::uint32_t groups) {
    if (groups == 0) return;
    vk_.vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline());
    vk_.vkCmdPushConstants(cmd_, k.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, k.push_size(), push);
    vk_.vkCmdDispatch(cmd_, groups, 1, 1);
    write_timestamp(k);
}

void VulkanContext::dispatch_indirect(const Kernel& k, const void* push, const Buffer& args, VkDeviceSize offset) {
    vk_.vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline());
    vk_.vkCmdPushConstants(cmd_, k.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, k.push_size(), push);
    vk_.vkCmdDispatchIndirect(cmd_, args.handle(), offset);
    write_timestamp(k);
}

void VulkanContext::submit_and_wait() {
    check(vk_.vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd_;
    check(vk_.vkQueueSubmit(queue_, 1, &si, fence_), "vkQueueSubmit");
    check(vk_.vkWaitForFences(device_, 1, &fence_, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    check(vk_.vkResetFences(device_, 1, &fence_), "vkResetFences");
    read_timestamps();
    check_validation();
}

void VulkanContext::check_validation() {
    if (messages_.empty()) return;
    std::string first = messages_.front();
    std::size_t count = messages_.size();
    messages_.clear();
    throw Error(fmt::format("Vulkan validation reported {} message(s); first: {}", count, first));
}

Buffer::Buffer(VulkanContext& ctx, VkDeviceSize size, bool host_visible) : ctx_(&ctx), size_(size) {
    const auto& vk = ctx.vk();
    VkBufferCreateInfo bi{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
    bi.size = std::max<VkDeviceSize>(size, 16);
    bi.usage = VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT |
               VK_BUFFER_USAGE_INDIRECT_BUFFER_BIT | VK_BUFFER_USAGE_TRANSFER_SRC_BIT | VK_BUFFER_USAGE_TRANSFER_DST_BIT;
    // A driver may refuse an allocation when the buffer is created (lavapipe does) or when its
    // memory is allocated: either way the user hears what ran out.
    auto refuse_if_out_of_memory = [&](VkResult r, VkDeviceSize bytes) {
        if (r != VK_ERROR_OUT_OF_DEVICE_MEMORY && r != VK_ERROR_OUT_OF_HOST_MEMORY) return;
        release();
        throw Error(fmt::format("out of memory on {} allocating {} MiB; try a larger radius or --device cpu",
                                ctx.device_name(), bytes >> 20));
    };
    VkResult created = vk.vkCreateBuffer(ctx.device(), &bi, nullptr, &buffer_);
    if (created != VK_SUCCESS) buffer_ = VK_NULL_HANDLE;  // undefined after a failure
    refuse_if_out_of_memory(created, bi.size);
    check(created, "vkCreateBuffer");
    VkMemoryRequirements req;
    vk.vkGetBufferMemoryRequirements(ctx.device(), buffer_, &req);
    VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
    flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
    VkMemoryAllocateInfo ai{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO, &flags};
    ai.allocationSize = req.size;
    ai.memoryTypeIndex = ctx.memory_type(req.memoryTypeBits, host_visible);
    VkResult r = vk.vkAllocateMemory(ctx.device(), &ai, nullptr, &memory_);
    if (r != VK_SUCCESS) memory_ = VK_NULL_HANDLE;
    refuse_if_out_of_memory(r, req.size);
    check(r, "vkAllocateMemory");
    allocated_ = req.size;
    ctx.note_allocation(std::int64_t(allocated_));
    check(vk.vkBindBufferMemory(ctx.device(), buffer_, memory_, 0), "vkBindBufferMemory");
    VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
    info.buffer = buffer_;
    address_ = vk.vkGetBufferDeviceAddress(ctx.device(), &info);
    if (host_visible) check(vk.vkMapMemory(ctx.device(), memory_, 0, VK_WHOLE_SIZE, 0, &mapped_), "vkMapMemory");
}

Buffer& Buffer::operator=(Buffer&& o) noexcept {
    if (this != &o) {
        release();
        std::swap(ctx_, o.ctx_);
        std::swap(buffer_, o.buffer_);
        std::swap(memory_, o.memory_);
        std::swap(size_, o.size_);
        std::swap(allocated_, o.allocated_);
        std::swap(address_, o.address_);
        std::swap(mapped_, o.mapped_);
    }
    return *this;
}

Buffer::~Buffer() { release(); }

void Buffer::release() {
    if (!ctx_) return;
    if (buffer_) ctx_->vk().vkDestroyBuffer(ctx_->device(), buffer_, nullptr);
    if (memory_) {
        ctx_->vk().vkFreeMemory(ctx_->device(), memory_, nullptr);
        ctx_->note_allocation(-std::int64_t(allocated_));
    }
    buffer_ = VK_NULL_HANDLE;
    memory_ = VK_NULL_HANDLE;
    mapped_ = nullptr;
    size_ = 0;
    allocated_ = 0;
    address_ = 0;
}

Kernel::Kernel(VulkanContext& ctx, std::string name, std::span<const std::uint32_t> spirv, std::uint32_t push_size,
               std::uint32_t workgroup)
    : ctx_(ctx), name_(std::move(name)), push_size_(push_size) {
    const auto& vk = ctx.vk();
    VkShaderModuleCreateInfo mi{VK_STRUCTURE_TYPE_SHADER_MODULE_CREATE_INFO};
    mi.codeSize = spirv.size_bytes();
    mi.pCode = spirv.data();
    VkShaderModule module;
    check(vk.vkCreateShaderModule(ctx.device(), &mi, nullptr, &module), "vkCreateShaderModule");
    VkPushConstantRange range{VK_SHADER_STAGE_COMPUTE_BIT, 0, push_size};
    VkPipelineLayoutCreateInfo li{VK_STRUCTURE_TYPE_PIPELINE_LAYOUT_CREATE_INFO};
    li.pushConstantRangeCount = 1;
    li.pPushConstantRanges = &range;
    check(vk.vkCreatePipelineLayout(ctx.device(), &li, nullptr, &layout_), "vkCreatePipelineLayout");
    VkSpecializationMapEntry entry{0, 0, sizeof(std::uint32_t)};
    VkSpecializationInfo spec{1, &entry, sizeof(std::uint32_t), &workgroup};
    VkComputePipelineCreateInfo pi{VK_STRUCTURE_TYPE_COMPUTE_PIPELINE_CREATE_INFO};
    pi.stage = {VK_STRUCTURE_TYPE_PIPELINE_SHADER_STAGE_CREATE_INFO};
    pi.stage.stage = VK_SHADER_STAGE_COMPUTE_BIT;
    pi.stage.module = module;
    pi.stage.pName = "main";
    pi.stage.pSpecializationInfo = &spec;
    pi.layout = layout_;
    VkResult r = vk.vkCreateComputePipelines(ctx.device(), VK_NULL_HANDLE, 1, &pi, nullptr, &pipeline_);
    vk.vkDestroyShaderModule(ctx.device(), module, nullptr);
    check(r, "vkCreateComputePipelines");
}

Kernel::~Kernel() {
    ctx_.vk().vkDestroyPipeline(ctx_.device(), pipeline_, nullptr);
    ctx_.vk().vkDestroyPipelineLayout(ctx_.device(), layout_, nullptr);
}

}  // namespace vrpd::detail

namespace vrpd {
std::vector<DeviceInfo> list_devices() { return detail::VulkanContext().devices(); }
}  // namespace vrpd
