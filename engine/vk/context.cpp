#include "vk/context.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <tuple>
#include <utility>
#include <vector>

#include "core/error.h"
#include "vk/host_heap.h"
#include "vk/pipeline.h"

namespace caustica::vk {

const char* result_name(VkResult result) {
  switch (result) {
    case VK_SUCCESS: return "VK_SUCCESS";
    case VK_NOT_READY: return "VK_NOT_READY";
    case VK_TIMEOUT: return "VK_TIMEOUT";
    case VK_INCOMPLETE: return "VK_INCOMPLETE";
    case VK_ERROR_OUT_OF_HOST_MEMORY: return "VK_ERROR_OUT_OF_HOST_MEMORY";
    case VK_ERROR_OUT_OF_DEVICE_MEMORY: return "VK_ERROR_OUT_OF_DEVICE_MEMORY";
    case VK_ERROR_INITIALIZATION_FAILED: return "VK_ERROR_INITIALIZATION_FAILED";
    case VK_ERROR_DEVICE_LOST: return "VK_ERROR_DEVICE_LOST";
    case VK_ERROR_MEMORY_MAP_FAILED: return "VK_ERROR_MEMORY_MAP_FAILED";
    case VK_ERROR_LAYER_NOT_PRESENT: return "VK_ERROR_LAYER_NOT_PRESENT";
    case VK_ERROR_EXTENSION_NOT_PRESENT: return "VK_ERROR_EXTENSION_NOT_PRESENT";
    case VK_ERROR_FEATURE_NOT_PRESENT: return "VK_ERROR_FEATURE_NOT_PRESENT";
    case VK_ERROR_INCOMPATIBLE_DRIVER: return "VK_ERROR_INCOMPATIBLE_DRIVER";
    case VK_ERROR_TOO_MANY_OBJECTS: return "VK_ERROR_TOO_MANY_OBJECTS";
    case VK_ERROR_FORMAT_NOT_SUPPORTED: return "VK_ERROR_FORMAT_NOT_SUPPORTED";
    case VK_ERROR_OUT_OF_POOL_MEMORY: return "VK_ERROR_OUT_OF_POOL_MEMORY";
    default: return "VkResult(other)";
  }
}

void check(VkResult result, const char* call) {
  if (result != VK_SUCCESS) throw DeviceError(std::string(call) + " failed: " + result_name(result));
}

void defer_destroy(Context& context, void (*destroy)(VkDevice, uint64_t), uint64_t handle) {
  context.defer([destroy, handle](VkDevice device) { destroy(device, handle); });
}

namespace {

bool has_layer(const char* name) {
  uint32_t count = 0;
  vkEnumerateInstanceLayerProperties(&count, nullptr);
  std::vector<VkLayerProperties> layers(count);
  vkEnumerateInstanceLayerProperties(&count, layers.data());
  return std::any_of(layers.begin(), layers.end(), [&](const auto& l) { return std::strcmp(l.layerName, name) == 0; });
}

bool has_device_extension(VkPhysicalDevice device, const char* name) {
  uint32_t count = 0;
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, nullptr);
  std::vector<VkExtensionProperties> extensions(count);
  vkEnumerateDeviceExtensionProperties(device, nullptr, &count, extensions.data());
  return std::any_of(extensions.begin(), extensions.end(), [&](const auto& e) { return std::strcmp(e.extensionName, name) == 0; });
}

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

VkInstance create_instance(bool validation, bool with_messenger_info, VkDebugUtilsMessengerCreateInfoEXT* messenger_info,
                           const std::vector<std::string>& more_extensions = {}) {
  VkApplicationInfo app{VK_STRUCTURE_TYPE_APPLICATION_INFO};
  app.pApplicationName = "caustica";
  app.pEngineName = "caustica";
  app.apiVersion = VK_API_VERSION_1_3;
  std::vector<const char*> layers;
  std::vector<const char*> extensions;
  VkValidationFeatureEnableEXT enables[] = {VK_VALIDATION_FEATURE_ENABLE_SYNCHRONIZATION_VALIDATION_EXT};
  VkValidationFeaturesEXT features{VK_STRUCTURE_TYPE_VALIDATION_FEATURES_EXT};
  features.enabledValidationFeatureCount = 1;
  features.pEnabledValidationFeatures = enables;
  if (validation) {
    if (!has_layer("VK_LAYER_KHRONOS_validation")) {
      throw DeviceError("--validate: VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)");
    }
    layers.push_back("VK_LAYER_KHRONOS_validation");
    features.pNext = with_messenger_info ? messenger_info : nullptr;
  }
  extensions.push_back(VK_EXT_DEBUG_UTILS_EXTENSION_NAME);
  for (const auto& e : more_extensions) extensions.push_back(e.c_str());
  VkInstanceCreateInfo info{VK_STRUCTURE_TYPE_INSTANCE_CREATE_INFO};
  info.pApplicationInfo = &app;
  info.enabledLayerCount = static_cast<uint32_t>(layers.size());
  info.ppEnabledLayerNames = layers.data();
  info.enabledExtensionCount = static_cast<uint32_t>(extensions.size());
  info.ppEnabledExtensionNames = extensions.data();
  if (validation) info.pNext = &features;
  VkInstance instance = VK_NULL_HANDLE;
  check(vkCreateInstance(&info, nullptr, &instance), "vkCreateInstance");
  return instance;
}

// The device Context uses: the one whose name contains `device_name`, else lavapipe, else the first
// Vulkan 1.3 device with push descriptors.
VkPhysicalDevice pick_physical_device(VkInstance instance, const std::string& device_name) {
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  std::string available;
  VkPhysicalDevice picked = VK_NULL_HANDLE, fallback = VK_NULL_HANDLE;
  for (auto d : devices) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    available += std::string(available.empty() ? "" : ", ") + "'" + p.deviceName + "'";
    if (p.apiVersion < VK_API_VERSION_1_3 || !has_device_extension(d, VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME)) continue;
    if (!device_name.empty()) {
      if (lower(p.deviceName).find(lower(device_name)) != std::string::npos && !picked) picked = d;
    } else if (p.deviceType == VK_PHYSICAL_DEVICE_TYPE_CPU && !picked) {
      picked = d;  // lavapipe: the target device
    } else if (!fallback) {
      fallback = d;
    }
  }
  if (!picked && device_name.empty()) picked = fallback;
  if (picked) return picked;
  const std::string devices_text = available.empty() ? "none" : available;
  if (!device_name.empty()) throw InputError("no Vulkan 1.3 device matches --device '" + device_name + "'; devices: " + devices_text);
  throw DeviceError("no Vulkan 1.3 device with VK_KHR_push_descriptor (devices: " + devices_text + "; Debian: mesa-vulkan-drivers)");
}

const char* const kRayQueryExtensions[] = {VK_KHR_ACCELERATION_STRUCTURE_EXTENSION_NAME, VK_KHR_RAY_QUERY_EXTENSION_NAME,
                                           VK_KHR_DEFERRED_HOST_OPERATIONS_EXTENSION_NAME};

RayQuerySupport ray_query_support(VkPhysicalDevice device, bool disable) {
  const char* env = std::getenv("CAUSTICA_NO_RAY_QUERY");
  if (disable || (env && *env && std::strcmp(env, "0") != 0)) return {false, "ray queries (switched off by CAUSTICA_NO_RAY_QUERY)"};
  std::string missing;
  for (const char* name : kRayQueryExtensions) {
    if (!has_device_extension(device, name)) missing += std::string(missing.empty() ? "" : " and ") + name;
  }
  if (!missing.empty()) return {false, missing};
  VkPhysicalDeviceRayQueryFeaturesKHR ray_query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  acceleration.pNext = &ray_query;
  VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  features12.pNext = &acceleration;
  VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  query.pNext = &features12;
  vkGetPhysicalDeviceFeatures2(device, &query);
  if (!ray_query.rayQuery)
    missing = "the rayQuery feature";
  else if (!acceleration.accelerationStructure)
    missing = "the accelerationStructure feature";
  else if (!features12.bufferDeviceAddress)
    missing = "the bufferDeviceAddress feature";
  return {missing.empty(), missing};
}

// The first queue family with graphics, compute and timestamps (and its timestamp bits); none: UINT32_MAX.
std::pair<uint32_t, uint32_t> graphics_compute_family(VkPhysicalDevice physical) {
  uint32_t family_count = 0;
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &family_count, nullptr);
  std::vector<VkQueueFamilyProperties> families(family_count);
  vkGetPhysicalDeviceQueueFamilyProperties(physical, &family_count, families.data());
  for (uint32_t i = 0; i < family_count; ++i) {
    const VkQueueFlags need = VK_QUEUE_GRAPHICS_BIT | VK_QUEUE_COMPUTE_BIT;
    if ((families[i].queueFlags & need) == need && families[i].timestampValidBits > 0) return {i, families[i].timestampValidBits};
  }
  return {UINT32_MAX, 0};
}

// The features and extensions the device is created with, chained from `features` as
// vkCreateDevice reads them; the chain points into the object, so it is neither copied nor moved.
struct DeviceFeatures {
  VkPhysicalDeviceFeatures2 features{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
  VkPhysicalDeviceVulkan13Features features13{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_3_FEATURES};
  VkPhysicalDeviceVulkan12Features features12{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
  VkPhysicalDeviceShaderAtomicFloatFeaturesEXT atomic_float{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
  VkPhysicalDeviceAccelerationStructureFeaturesKHR acceleration{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_FEATURES_KHR};
  VkPhysicalDeviceRayQueryFeaturesKHR ray_query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_RAY_QUERY_FEATURES_KHR};
  std::vector<const char*> extensions{VK_KHR_PUSH_DESCRIPTOR_EXTENSION_NAME};
  bool float_atomics = false, nonuniform_textures = false;

  DeviceFeatures(VkPhysicalDevice physical, bool presentation, bool ray_queries) {
    features13.synchronization2 = VK_TRUE;
    features13.dynamicRendering = VK_TRUE;
    features13.maintenance4 = VK_TRUE;  // required in 1.3; glslang emits LocalSizeId for SPIR-V 1.6
    // Required in 1.3 (with descriptorIndexing): lighting loops over every light's shadow map in an array.
    features.features.shaderSampledImageArrayDynamicIndexing = VK_TRUE;
    features.pNext = &features13;
    if (presentation) extensions.push_back(VK_KHR_SWAPCHAIN_EXTENSION_NAME);
    enable_float_atomics(physical);
    // Scene textures are indexed by object within one draw: a non-uniform index into their array.
    VkPhysicalDeviceVulkan12Features supported{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_VULKAN_1_2_FEATURES};
    VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    query.pNext = &supported;
    vkGetPhysicalDeviceFeatures2(physical, &query);
    nonuniform_textures = supported.shaderSampledImageArrayNonUniformIndexing == VK_TRUE;
    features12.shaderSampledImageArrayNonUniformIndexing = supported.shaderSampledImageArrayNonUniformIndexing;
    features12.pNext = features.pNext;
    features.pNext = &features12;
    // Ray queries: chained in front of whatever else is enabled.
    if (ray_queries) {
      features12.bufferDeviceAddress = VK_TRUE;
      acceleration.accelerationStructure = VK_TRUE;
      ray_query.rayQuery = VK_TRUE;
      acceleration.pNext = &ray_query;
      ray_query.pNext = features12.pNext;
      features12.pNext = &acceleration;
      for (const char* name : kRayQueryExtensions) extensions.push_back(name);
    }
  }
  DeviceFeatures(const DeviceFeatures&) = delete;
  DeviceFeatures& operator=(const DeviceFeatures&) = delete;

  // Float atomic adds splat photon power; passes that need them check float_atomics().
  void enable_float_atomics(VkPhysicalDevice physical) {
    if (!has_device_extension(physical, VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME)) return;
    VkPhysicalDeviceFeatures2 query{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_FEATURES_2};
    query.pNext = &atomic_float;
    vkGetPhysicalDeviceFeatures2(physical, &query);
    float_atomics = atomic_float.shaderBufferFloat32AtomicAdd && atomic_float.shaderImageFloat32AtomicAdd;
    if (!float_atomics) return;
    VkPhysicalDeviceShaderAtomicFloatFeaturesEXT enable{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SHADER_ATOMIC_FLOAT_FEATURES_EXT};
    enable.shaderBufferFloat32AtomicAdd = VK_TRUE;
    enable.shaderImageFloat32AtomicAdd = VK_TRUE;
    atomic_float = enable;
    features13.pNext = &atomic_float;
    extensions.push_back(VK_EXT_SHADER_ATOMIC_FLOAT_EXTENSION_NAME);
  }
};

bool has_subgroup_arithmetic(VkPhysicalDevice physical) {
  VkPhysicalDeviceSubgroupProperties subgroup{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_SUBGROUP_PROPERTIES};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties.pNext = &subgroup;
  vkGetPhysicalDeviceProperties2(physical, &properties);
  const VkSubgroupFeatureFlags needed = VK_SUBGROUP_FEATURE_BASIC_BIT | VK_SUBGROUP_FEATURE_ARITHMETIC_BIT;
  return (subgroup.supportedStages & VK_SHADER_STAGE_COMPUTE_BIT) && (subgroup.supportedOperations & needed) == needed;
}

Context::RayTracingFunctions load_ray_tracing_functions(VkDevice device) {
  const auto load = [&](const char* name) { return vkGetDeviceProcAddr(device, name); };
  Context::RayTracingFunctions rt;
  rt.create = reinterpret_cast<PFN_vkCreateAccelerationStructureKHR>(load("vkCreateAccelerationStructureKHR"));
  rt.destroy = reinterpret_cast<PFN_vkDestroyAccelerationStructureKHR>(load("vkDestroyAccelerationStructureKHR"));
  rt.build_sizes = reinterpret_cast<PFN_vkGetAccelerationStructureBuildSizesKHR>(load("vkGetAccelerationStructureBuildSizesKHR"));
  rt.cmd_build = reinterpret_cast<PFN_vkCmdBuildAccelerationStructuresKHR>(load("vkCmdBuildAccelerationStructuresKHR"));
  rt.address = reinterpret_cast<PFN_vkGetAccelerationStructureDeviceAddressKHR>(load("vkGetAccelerationStructureDeviceAddressKHR"));
  return rt;
}

}  // namespace

RayQuerySupport probe_ray_queries(const std::string& device_name, bool disable) {
  VkInstance instance = create_instance(false, false, nullptr);
  try {
    const RayQuerySupport support = ray_query_support(pick_physical_device(instance, device_name), disable);
    vkDestroyInstance(instance, nullptr);
    return support;
  } catch (...) {
    vkDestroyInstance(instance, nullptr);
    throw;
  }
}

VKAPI_ATTR VkBool32 VKAPI_CALL Context::on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user) {
  auto* self = static_cast<Context*>(user);
  if (severity < VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT) return VK_FALSE;
  self->validation_messages_.fetch_add(1);
  if (!self->quiet_validation_) {
    std::fprintf(stderr, "validation %s: %s\n", severity >= VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT ? "error" : "warning",
                 data->pMessage ? data->pMessage : "");
  }
  return VK_FALSE;
}

std::vector<DeviceInfo> Context::list_devices() {
  VkInstance instance = create_instance(false, false, nullptr);
  uint32_t count = 0;
  vkEnumeratePhysicalDevices(instance, &count, nullptr);
  std::vector<VkPhysicalDevice> devices(count);
  vkEnumeratePhysicalDevices(instance, &count, devices.data());
  std::vector<DeviceInfo> out;
  for (auto d : devices) {
    VkPhysicalDeviceProperties p;
    vkGetPhysicalDeviceProperties(d, &p);
    out.push_back({p.deviceName, p.deviceType, p.apiVersion});
  }
  vkDestroyInstance(instance, nullptr);
  return out;
}

Context::Context(const ContextOptions& options)
    : validation_(options.validation), quiet_validation_(options.quiet_validation), injected_fault_(options.injected_fault) {
  VkDebugUtilsMessengerCreateInfoEXT messenger_info{VK_STRUCTURE_TYPE_DEBUG_UTILS_MESSENGER_CREATE_INFO_EXT};
  messenger_info.messageSeverity = VK_DEBUG_UTILS_MESSAGE_SEVERITY_WARNING_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_SEVERITY_ERROR_BIT_EXT;
  messenger_info.messageType = VK_DEBUG_UTILS_MESSAGE_TYPE_GENERAL_BIT_EXT | VK_DEBUG_UTILS_MESSAGE_TYPE_VALIDATION_BIT_EXT |
                               VK_DEBUG_UTILS_MESSAGE_TYPE_PERFORMANCE_BIT_EXT;
  messenger_info.pfnUserCallback = &Context::on_message;
  messenger_info.pUserData = this;
  instance_ = create_instance(validation_, true, &messenger_info, options.instance_extensions);
  if (validation_) {
    auto create = reinterpret_cast<PFN_vkCreateDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance_, "vkCreateDebugUtilsMessengerEXT"));
    check(create(instance_, &messenger_info, nullptr, &messenger_), "vkCreateDebugUtilsMessengerEXT");
  }

  try {
    physical_ = pick_physical_device(instance_, options.device_name);
  } catch (...) {
    vkDestroyInstance(instance_, nullptr);  // the destructor does not run for a failed constructor
    throw;
  }
  vkGetPhysicalDeviceProperties(physical_, &properties_);
  VkPhysicalDevicePushDescriptorPropertiesKHR push{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PUSH_DESCRIPTOR_PROPERTIES_KHR};
  VkPhysicalDeviceProperties2 with_push{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  with_push.pNext = &push;
  vkGetPhysicalDeviceProperties2(physical_, &with_push);
  max_push_descriptors_ = push.maxPushDescriptors;
  vkGetPhysicalDeviceMemoryProperties(physical_, &memory_properties_);
  keep_freed_memory(properties_.deviceType);  // before lavapipe allocates per frame (vk/host_heap.h)
  subgroup_arithmetic_ = has_subgroup_arithmetic(physical_);
  device_name_ = properties_.deviceName;

  std::tie(queue_family_, timestamp_valid_bits_) = graphics_compute_family(physical_);
  if (queue_family_ == UINT32_MAX) {
    vkDestroyInstance(instance_, nullptr);
    throw DeviceError(device_name_ + " has no graphics+compute queue with timestamps");
  }

  float priority = 1.0f;
  VkDeviceQueueCreateInfo queue_info{VK_STRUCTURE_TYPE_DEVICE_QUEUE_CREATE_INFO};
  queue_info.queueFamilyIndex = queue_family_;
  queue_info.queueCount = 1;
  queue_info.pQueuePriorities = &priority;
  if (options.presentation && !has_device_extension(physical_, VK_KHR_SWAPCHAIN_EXTENSION_NAME))
    throw DeviceError(device_name_ + " cannot present to a window (no VK_KHR_swapchain)");
  ray_queries_ = ray_query_support(physical_, options.disable_ray_queries);
  const DeviceFeatures enabled(physical_, options.presentation, ray_queries_.available);
  float_atomics_ = enabled.float_atomics;
  nonuniform_textures_ = enabled.nonuniform_textures;
  VkDeviceCreateInfo info{VK_STRUCTURE_TYPE_DEVICE_CREATE_INFO};
  info.pNext = &enabled.features;
  info.queueCreateInfoCount = 1;
  info.pQueueCreateInfos = &queue_info;
  info.enabledExtensionCount = static_cast<uint32_t>(enabled.extensions.size());
  info.ppEnabledExtensionNames = enabled.extensions.data();
  VkResult created = vkCreateDevice(physical_, &info, nullptr, &device_);
  if (created != VK_SUCCESS) {
    vkDestroyInstance(instance_, nullptr);
    check(created, "vkCreateDevice");
  }
  vkGetDeviceQueue(device_, queue_family_, 0, &queue_);
  pipelines_ = std::make_unique<PipelineCache>();
  push_descriptor_set = reinterpret_cast<PFN_vkCmdPushDescriptorSetKHR>(vkGetDeviceProcAddr(device_, "vkCmdPushDescriptorSetKHR"));
  begin_label_ = reinterpret_cast<PFN_vkCmdBeginDebugUtilsLabelEXT>(vkGetInstanceProcAddr(instance_, "vkCmdBeginDebugUtilsLabelEXT"));
  end_label_ = reinterpret_cast<PFN_vkCmdEndDebugUtilsLabelEXT>(vkGetInstanceProcAddr(instance_, "vkCmdEndDebugUtilsLabelEXT"));
  set_name_ = reinterpret_cast<PFN_vkSetDebugUtilsObjectNameEXT>(vkGetInstanceProcAddr(instance_, "vkSetDebugUtilsObjectNameEXT"));
  if (ray_queries_.available) rt = load_ray_tracing_functions(device_);
}

Context::~Context() {
  if (abandoned_) return;
  pipelines_.reset();  // queues their destruction, which wait_idle() runs
  wait_idle();
  if (messenger_) {
    auto destroy =
        reinterpret_cast<PFN_vkDestroyDebugUtilsMessengerEXT>(vkGetInstanceProcAddr(instance_, "vkDestroyDebugUtilsMessengerEXT"));
    destroy(instance_, messenger_, nullptr);
  }
  if (surface_) vkDestroySurfaceKHR(instance_, surface_, nullptr);
  vkDestroyDevice(device_, nullptr);
  vkDestroyInstance(instance_, nullptr);
}

void Context::defer(std::function<void(VkDevice)> destroy) {
  if (abandoned_) return;
  pending_.push_back({submission_, std::move(destroy)});
}

void Context::retire(uint64_t completed_submission) {
  // Destroy in reverse order of release so views die before their images and memory last.
  std::vector<Pending> keep;
  for (auto it = pending_.rbegin(); it != pending_.rend(); ++it) {
    if (it->submission <= completed_submission) it->destroy(device_);
  }
  for (auto& p : pending_) {
    if (p.submission > completed_submission) keep.push_back(std::move(p));
  }
  pending_ = std::move(keep);
}

void Context::wait_idle() {
  if (!device_ || abandoned_) return;
  vkDeviceWaitIdle(device_);
  retire(submission_);
}

FrameCommands make_frame_commands(Context& vk) {
  FrameCommands commands;
  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.flags = VK_COMMAND_POOL_CREATE_RESET_COMMAND_BUFFER_BIT;
  pool_info.queueFamilyIndex = vk.queue_family();
  VkCommandPool pool = VK_NULL_HANDLE;
  check(vkCreateCommandPool(vk.device(), &pool_info, nullptr, &pool), "vkCreateCommandPool");
  commands.pool = OwnedCommandPool(vk, pool);
  VkCommandBufferAllocateInfo cmd_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cmd_info.commandPool = pool;
  cmd_info.level = VK_COMMAND_BUFFER_LEVEL_PRIMARY;
  cmd_info.commandBufferCount = 1;
  check(vkAllocateCommandBuffers(vk.device(), &cmd_info, &commands.cmd), "vkAllocateCommandBuffers");
  VkFenceCreateInfo fence_info{VK_STRUCTURE_TYPE_FENCE_CREATE_INFO};
  VkFence fence = VK_NULL_HANDLE;
  check(vkCreateFence(vk.device(), &fence_info, nullptr, &fence), "vkCreateFence");
  commands.fence = OwnedFence(vk, fence);
  return commands;
}

OwnedSemaphore make_semaphore(Context& vk) {
  VkSemaphoreCreateInfo info{VK_STRUCTURE_TYPE_SEMAPHORE_CREATE_INFO};
  VkSemaphore semaphore = VK_NULL_HANDLE;
  check(vkCreateSemaphore(vk.device(), &info, nullptr, &semaphore), "vkCreateSemaphore");
  return OwnedSemaphore(vk, semaphore);
}

void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages,
                    VkAccessFlags2 dst_access) {
  VkMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_MEMORY_BARRIER_2, nullptr, src_stages, src_access, dst_stages, dst_access};
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.memoryBarrierCount = 1;
  dependency.pMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd, &dependency);
}

VkImageMemoryBarrier2 image_transition(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                                       VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages,
                                       VkAccessFlags2 dst_access, uint32_t levels, uint32_t layers) {
  VkImageMemoryBarrier2 barrier{VK_STRUCTURE_TYPE_IMAGE_MEMORY_BARRIER_2};
  barrier.srcStageMask = src_stages;
  barrier.srcAccessMask = src_access;
  barrier.dstStageMask = dst_stages;
  barrier.dstAccessMask = dst_access;
  barrier.oldLayout = from;
  barrier.newLayout = to;
  barrier.srcQueueFamilyIndex = barrier.dstQueueFamilyIndex = VK_QUEUE_FAMILY_IGNORED;
  barrier.image = image;
  barrier.subresourceRange = {aspect, 0, levels, 0, layers};
  return barrier;
}

void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                   VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages, VkAccessFlags2 dst_access,
                   uint32_t levels) {
  const VkImageMemoryBarrier2 barrier =
      image_transition(image, aspect, from, to, src_stages, src_access, dst_stages, dst_access, levels, 1);
  VkDependencyInfo dependency{VK_STRUCTURE_TYPE_DEPENDENCY_INFO};
  dependency.imageMemoryBarrierCount = 1;
  dependency.pImageMemoryBarriers = &barrier;
  vkCmdPipelineBarrier2(cmd, &dependency);
}

void Context::submit_and_wait(const std::function<void(VkCommandBuffer)>& record) {
  VkCommandPoolCreateInfo pool_info{VK_STRUCTURE_TYPE_COMMAND_POOL_CREATE_INFO};
  pool_info.flags = VK_COMMAND_POOL_CREATE_TRANSIENT_BIT;
  pool_info.queueFamilyIndex = queue_family_;
  VkCommandPool pool_handle = VK_NULL_HANDLE;
  check(vkCreateCommandPool(device_, &pool_info, nullptr, &pool_handle), "vkCreateCommandPool");
  OwnedCommandPool pool(*this, pool_handle);
  VkCommandBufferAllocateInfo cmd_info{VK_STRUCTURE_TYPE_COMMAND_BUFFER_ALLOCATE_INFO};
  cmd_info.commandPool = pool_handle;
  cmd_info.commandBufferCount = 1;
  VkCommandBuffer cmd = VK_NULL_HANDLE;
  check(vkAllocateCommandBuffers(device_, &cmd_info, &cmd), "vkAllocateCommandBuffers");
  VkCommandBufferBeginInfo begin{VK_STRUCTURE_TYPE_COMMAND_BUFFER_BEGIN_INFO};
  begin.flags = VK_COMMAND_BUFFER_USAGE_ONE_TIME_SUBMIT_BIT;
  check(vkBeginCommandBuffer(cmd, &begin), "vkBeginCommandBuffer");
  record(cmd);
  check(vkEndCommandBuffer(cmd), "vkEndCommandBuffer");
  const uint64_t submission = begin_submission();
  VkCommandBufferSubmitInfo cmd_submit{VK_STRUCTURE_TYPE_COMMAND_BUFFER_SUBMIT_INFO};
  cmd_submit.commandBuffer = cmd;
  VkSubmitInfo2 submit{VK_STRUCTURE_TYPE_SUBMIT_INFO_2};
  submit.commandBufferInfoCount = 1;
  submit.pCommandBufferInfos = &cmd_submit;
  check(vkQueueSubmit2(queue_, 1, &submit, VK_NULL_HANDLE), "vkQueueSubmit2");
  check(vkQueueWaitIdle(queue_), "vkQueueWaitIdle");
  retire(submission);
}

uint32_t Context::memory_type(uint32_t type_bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred) const {
  for (int pass = 0; pass < 2; ++pass) {
    VkMemoryPropertyFlags want = pass == 0 ? required | preferred : required;
    for (uint32_t i = 0; i < memory_properties_.memoryTypeCount; ++i) {
      if ((type_bits & (1u << i)) && (memory_properties_.memoryTypes[i].propertyFlags & want) == want) return i;
    }
  }
  throw DeviceError("no memory type with the required properties on " + device_name_);
}

OwnedMemory Context::allocate(VkMemoryRequirements requirements, VkMemoryPropertyFlags required, const char* what,
                              VkMemoryPropertyFlags preferred, bool device_address) {
  VkMemoryAllocateFlagsInfo flags{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_FLAGS_INFO};
  flags.flags = VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT;
  VkMemoryAllocateInfo info{VK_STRUCTURE_TYPE_MEMORY_ALLOCATE_INFO};
  if (device_address) info.pNext = &flags;
  info.allocationSize = requirements.size;
  info.memoryTypeIndex = memory_type(requirements.memoryTypeBits, required, preferred);
  VkDeviceMemory memory = VK_NULL_HANDLE;
  VkResult result = injected_fault_ == VK_ERROR_OUT_OF_DEVICE_MEMORY ? injected_fault_ : vkAllocateMemory(device_, &info, nullptr, &memory);
  if (result != VK_SUCCESS) {
    throw DeviceError(std::string("vkAllocateMemory for ") + what + " (" + std::to_string(requirements.size) +
                      " bytes) failed: " + result_name(result));
  }
  set_name(VK_OBJECT_TYPE_DEVICE_MEMORY, reinterpret_cast<uint64_t>(memory), what);
  return OwnedMemory(*this, memory);
}

void Context::set_name(VkObjectType type, uint64_t handle, const std::string& name) const {
  if (!set_name_) return;
  VkDebugUtilsObjectNameInfoEXT info{VK_STRUCTURE_TYPE_DEBUG_UTILS_OBJECT_NAME_INFO_EXT};
  info.objectType = type;
  info.objectHandle = handle;
  info.pObjectName = name.c_str();
  set_name_(device_, &info);
}

void Context::begin_label(VkCommandBuffer cmd, const std::string& name) const {
  if (!begin_label_) return;
  VkDebugUtilsLabelEXT label{VK_STRUCTURE_TYPE_DEBUG_UTILS_LABEL_EXT};
  label.pLabelName = name.c_str();
  begin_label_(cmd, &label);
}

void Context::end_label(VkCommandBuffer cmd) const {
  if (end_label_) end_label_(cmd);
}

}  // namespace caustica::vk
