// Vulkan device: see device.h.
#include "device.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <mutex>

#include <fmt/format.h>

#include "buffer.h"
#include "gate.h"
#include "kernel.h"
#include "profiler.h"
#include "shared/kernels.h"

namespace vrpd::detail {
namespace {

const char* kValidationLayer = "VK_LAYER_KHRONOS_validation";

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
    auto* context = static_cast<VulkanContext*>(self);
    const std::lock_guard lock(context->messages_mutex_);
    context->messages_.emplace_back(data->pMessage ? data->pMessage : "(no text)");
    return VK_FALSE;
}

VulkanContext::VulkanContext() {
    const PFN_vkGetInstanceProcAddr get_proc = vulkan_loader();
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
        bool found = std::any_of(props.begin(), props.end(), [](const VkLayerProperties& p) {
            return std::strcmp(p.layerName, kValidationLayer) == 0;
        });
        if (!found)
            throw Error(
                "VRPD_VALIDATION is set but VK_LAYER_KHRONOS_validation is not installed (vulkan-validationlayers)");
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
    VkInstance instance = VK_NULL_HANDLE;
    VkResult r = vk_.vkCreateInstance(&ci, nullptr, &instance);
    if (r == VK_ERROR_INCOMPATIBLE_DRIVER)
        throw Error(
            "no Vulkan 1.2 driver on this machine (install mesa-vulkan-drivers for lavapipe), or use --device cpu");
    detail::check(r, "vkCreateInstance", "this machine");
    load_functions(get_proc, instance);
    instance_ = own<OwnedInstance>(vk_, instance);
    instance_handle_ = instance;
    if (validate) {
        // Warnings and errors, until the instance goes: the messenger outlives the device.
        VkDebugUtilsMessengerCreateInfoEXT mi{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
        mi.messageSeverity =
            VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
        mi.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                         VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
        mi.pfnUserCallback = &VulkanContext::on_message;
        mi.pUserData = this;
        VkDebugUtilsMessengerEXT messenger = VK_NULL_HANDLE;
        detail::check(vk_.vkCreateDebugUtilsMessengerEXT(instance, &mi, nullptr, &messenger),
                      "vkCreateDebugUtilsMessengerEXT", "this machine");
        messenger_ = own<OwnedMessenger>(vk_, instance, messenger);
    }
}

VulkanContext::VulkanContext(const VulkanTarget& target) {
    if (!target.instance || !target.physical_device || !target.device || !target.queue)
        throw Error("VulkanTarget: instance, physical device, device and queue must all be given");
    PFN_vkGetInstanceProcAddr get_proc = target.get_instance_proc_addr;
    if (!get_proc) get_proc = vulkan_loader();
    load_functions(get_proc, target.instance);
    instance_handle_ = target.instance;
    physical_ = target.physical_device;
    VkPhysicalDeviceDriverProperties driver{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_DRIVER_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &driver};
    vk_.vkGetPhysicalDeviceProperties2(physical_, &props);
    device_name_ = fmt::format("{} (the application's device, {} {})", props.properties.deviceName,
                               driver.driverName, driver.driverInfo);
    std::uint32_t families = 0;
    vk_.vkGetPhysicalDeviceQueueFamilyProperties(physical_, &families, nullptr);
    std::vector<VkQueueFamilyProperties> queues(families);
    vk_.vkGetPhysicalDeviceQueueFamilyProperties(physical_, &families, queues.data());
    if (target.queue_family >= families || !(queues[target.queue_family].queueFlags & VK_QUEUE_COMPUTE_BIT))
        throw Error(fmt::format("VulkanTarget: queue family {} of {} has no compute", target.queue_family,
                                device_name_));
    if (props.properties.apiVersion < VK_API_VERSION_1_2)
        throw Error(fmt::format("VulkanTarget: {} does not have Vulkan 1.2", device_name_));
    queue_family_ = target.queue_family;
    vk_.vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    subgroup_scan_ = query_subgroup_scan();
    device_handle_ = target.device;
    queue_ = target.queue;
    make_command_objects();
}

bool VulkanContext::query_subgroup_scan() const {
    VkPhysicalDeviceSubgroupProperties subgroups{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
    VkPhysicalDeviceProperties2 props{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2, &subgroups};
    vk_.vkGetPhysicalDeviceProperties2(physical_, &props);
    return (subgroups.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) != 0 &&
           (subgroups.supportedOperations & VK_SUBGROUP_FEATURE_ARITHMETIC_BIT) != 0 && subgroups.subgroupSize <= 64;
}

void VulkanContext::load_functions(PFN_vkGetInstanceProcAddr get_proc, VkInstance instance) {
#define VRPD_VK_FN(name) \
    if (!vk_.name) vk_.name = reinterpret_cast<PFN_##name>(get_proc(instance, #name));
#include "functions.inc"
#undef VRPD_VK_FN
}

VulkanContext::~VulkanContext() = default;

void VulkanContext::check(VkResult r, const char* what) const { detail::check(r, what, device_name_); }

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
    for (auto& c : enumerate(vk_, instance_handle_)) out.push_back(c.info);
    return out;
}

void VulkanContext::open_device(const std::string& requested) {
    std::string selector = requested;
    if (selector.empty())
        if (const char* env = std::getenv("VRPD_DEVICE")) selector = env;
    auto all = enumerate(vk_, instance_handle_);
    if (all.empty())
        throw Error("no Vulkan device found (install mesa-vulkan-drivers for lavapipe), or use --device cpu");
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
            throw Error(
                fmt::format("Vulkan device '{}' lacks Vulkan 1.2, shaderInt64 or bufferDeviceAddress; use --device cpu",
                            pick->info.name));
    } else {
        for (auto& c : all)
            if (c.info.usable && (!pick || preference(c.type) > preference(pick->type))) pick = &c;
        if (!pick)
            throw Error("no Vulkan device has Vulkan 1.2, shaderInt64 and bufferDeviceAddress; use --device cpu");
    }
    physical_ = pick->handle;
    queue_family_ = pick->queue_family;
    device_name_ = fmt::format("{} ({}, {})", pick->info.name, pick->info.type, pick->info.driver);
    vk_.vkGetPhysicalDeviceMemoryProperties(physical_, &memory_);
    subgroup_scan_ = query_subgroup_scan();

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
    VkDevice device = VK_NULL_HANDLE;
    check(vk_.vkCreateDevice(physical_, &di, nullptr, &device), "vkCreateDevice");
    device_ = own<OwnedDevice>(vk_, device);
    device_handle_ = device;
    vk_.vkGetDeviceQueue(device, queue_family_, 0, &queue_);
    make_command_objects();
}

void VulkanContext::make_command_objects() {
    const VkDevice device = device_handle_;
    VkCommandPoolCreateInfo pi{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
    pi.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
    pi.queueFamilyIndex = queue_family_;
    VkCommandPool pool = VK_NULL_HANDLE;
    check(vk_.vkCreateCommandPool(device, &pi, nullptr, &pool), "vkCreateCommandPool");
    pool_ = own<OwnedCommandPool>(vk_, device, pool);
    VkCommandBufferAllocateInfo ai{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
    ai.commandPool = pool;
    ai.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
    ai.commandBufferCount = 1;
    check(vk_.vkAllocateCommandBuffers(device, &ai, &cmd_), "vkAllocateCommandBuffers");
    VkFenceCreateInfo fi{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
    VkFence fence = VK_NULL_HANDLE;
    check(vk_.vkCreateFence(device, &fi, nullptr, &fence), "vkCreateFence");
    fence_ = own<OwnedFence>(vk_, device, fence);
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
        if (memory_.memoryHeaps[i].flags & VK_MEMORY_HEAP_DEVICE_LOCAL_BIT)
            best = std::max(best, memory_.memoryHeaps[i].size);
    return best;
}

VkCommandBuffer VulkanContext::begin() {
    check(vk_.vkResetCommandBuffer(cmd_, 0), "vkResetCommandBuffer");
    VkCommandBufferBeginInfo bi{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
    bi.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
    check(vk_.vkBeginCommandBuffer(cmd_, &bi), "vkBeginCommandBuffer");
    if (profiler_) profiler_->begin(cmd_);
    return cmd_;
}

void VulkanContext::start_profile() {
    if (!profiler_) profiler_ = std::make_unique<Profiler>(*this);
}

std::vector<PhaseTime> VulkanContext::profile() const {
    return profiler_ ? profiler_->phases() : std::vector<PhaseTime>{};
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

void VulkanContext::open_gate(const Buffer& table, std::uint64_t counters, std::uint32_t slot) {
    if (table.mapped() == nullptr || table.size() < kGateDispatches * 12)
        throw Error("internal: a gate's table must be host-visible and hold its commands");
    if (!gate_kernel_)
        gate_kernel_ = std::make_unique<Kernel>(*this, "gate", spirv_words(spirv_gate), sizeof(shared::GateArgs),
                                                shared::WORKGROUP_SIZE);
    const shared::GateArgs g{counters, table.address(), slot, kGateDispatches};
    dispatch(*gate_kernel_, &g, dispatch_groups(kGateDispatches, shared::WORKGROUP_SIZE));
    barrier();  // the gated commands before the dispatches read them
    gate_ = &table;
    gated_ = 0;
}

void VulkanContext::dispatch(const Kernel& k, const void* push, std::uint32_t groups) {
    if (groups == 0) return;
    // As few rows as the limit allows, of equal length: at most rows - 1 workgroups past `groups`.
    const std::uint32_t rows = (groups - 1) / row_groups_ + 1;
    const std::uint32_t per_row = (groups - 1) / rows + 1;
    if (gate_) {
        if (gated_ == kGateDispatches) throw Error("internal: more gated dispatches than a gate's table holds");
        auto* command = static_cast<std::uint32_t*>(gate_->mapped()) + 3 * gated_;
        command[0] = per_row;
        command[1] = rows;
        command[2] = 1;
        dispatch_indirect(k, push, *gate_, VkDeviceSize(12) * gated_++);
        return;
    }
    if (!k.pipeline()) build_pending();
    vk_.vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline());
    vk_.vkCmdPushConstants(cmd_, k.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, k.push_size(), push);
    vk_.vkCmdDispatch(cmd_, per_row, rows, 1);
    if (profiler_) profiler_->after(cmd_, k);
}

void VulkanContext::dispatch_indirect(const Kernel& k, const void* push, const Buffer& args, VkDeviceSize offset) {
    if (!k.pipeline()) build_pending();
    vk_.vkCmdBindPipeline(cmd_, VK_PIPELINE_BIND_POINT_COMPUTE, k.pipeline());
    vk_.vkCmdPushConstants(cmd_, k.layout(), VK_SHADER_STAGE_COMPUTE_BIT, 0, k.push_size(), push);
    vk_.vkCmdDispatchIndirect(cmd_, args.handle(), offset);
    if (profiler_) profiler_->after(cmd_, k);
}

void VulkanContext::submit_and_wait() {
    check(vk_.vkEndCommandBuffer(cmd_), "vkEndCommandBuffer");
    VkSubmitInfo si{VK_STRUCTURE_TYPE_SUBMIT_INFO};
    si.commandBufferCount = 1;
    si.pCommandBuffers = &cmd_;
    check(vk_.vkQueueSubmit(queue_, 1, &si, fence_.get()), "vkQueueSubmit");
    const VkFence fence = fence_.get();
    check(vk_.vkWaitForFences(device(), 1, &fence, VK_TRUE, UINT64_MAX), "vkWaitForFences");
    check(vk_.vkResetFences(device(), 1, &fence), "vkResetFences");
    ++submits_;
    if (profiler_) profiler_->read();
    check_validation();
}

void VulkanContext::check_validation() {
    if (messages_.empty()) return;
    std::string first = messages_.front();
    std::size_t count = messages_.size();
    messages_.clear();
    throw Error(fmt::format("Vulkan validation reported {} message(s); first: {}", count, first));
}

void VulkanContext::start_run() {
    peak_allocated_ = allocated_;
    submits_ = 0;
    profiler_.reset();
    gate_ = nullptr;
}

namespace {
// The idle contexts, one per device key, and the DeviceSamplers' contexts their runs borrow;
// never destroyed, so that no driver is called from the destructors run at exit.
struct IdleContexts {
    std::mutex lock;
    std::map<std::string, std::unique_ptr<VulkanContext>> by_key;
    std::map<const VulkanTarget*, VulkanContext*> lent;  // DeviceSamplers' contexts
};
IdleContexts& idle_contexts() {
    static IdleContexts* const idle = new IdleContexts;
    return *idle;
}
}  // namespace

ContextLease::ContextLease(const std::string& selector, const VulkanTarget* target)
    : exceptions_(std::uncaught_exceptions()) {
    if (target) {
        {
            IdleContexts& idle = idle_contexts();
            const std::lock_guard hold(idle.lock);
            if (const auto found = idle.lent.find(target); found != idle.lent.end()) use_ = found->second;
        }
        if (!use_) {
            ctx_ = std::make_unique<VulkanContext>(*target);
            use_ = ctx_.get();
        }
        use_->start_run();
        return;
    }
    // What picks the device and the layers, besides the selector.
    const char* env = std::getenv("VRPD_DEVICE");
    key_ = fmt::format("{}\n{}\n{}", selector, env ? env : "", validation_requested() ? 1 : 0);
    {
        IdleContexts& idle = idle_contexts();
        const std::lock_guard hold(idle.lock);
        if (const auto found = idle.by_key.find(key_); found != idle.by_key.end()) {
            ctx_ = std::move(found->second);
            idle.by_key.erase(found);
        }
    }
    if (!ctx_) ctx_ = std::make_unique<VulkanContext>(selector);
    use_ = ctx_.get();
    use_->start_run();
}

ContextLease::~ContextLease() {
    if (key_.empty() || std::uncaught_exceptions() != exceptions_ || !ctx_->idle()) return;
    IdleContexts& idle = idle_contexts();
    const std::lock_guard hold(idle.lock);
    // Of two contexts back from runs at once, the one with more pipelines stays.
    const auto [at, fresh] = idle.by_key.try_emplace(key_, std::move(ctx_));
    if (!fresh && at->second->pipelines() < ctx_->pipelines()) std::swap(at->second, ctx_);
}

void lend_context(const VulkanTarget* target, VulkanContext* ctx) {
    IdleContexts& idle = idle_contexts();
    const std::lock_guard hold(idle.lock);
    if (ctx)
        idle.lent[target] = ctx;
    else
        idle.lent.erase(target);
}

}  // namespace vrpd::detail

namespace vrpd {
std::vector<DeviceInfo> list_devices() { return detail::VulkanContext().devices(); }
}  // namespace vrpd
