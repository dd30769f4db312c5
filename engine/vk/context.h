#pragma once
// The Vulkan instance and device: lavapipe by default, any Vulkan 1.3 device by name. Owns the
// deferred-destruction queue and the validation messenger whose message count tests assert on.
#include <vulkan/vulkan.h>

#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vk/owned.h"

namespace caustica::vk {

class PipelineCache;

struct ContextOptions {
  std::string device_name;        // substring of the device name; empty picks lavapipe, else the first 1.3 device
  bool validation = false;        // Khronos validation with synchronization validation
  bool quiet_validation = false;  // count messages without printing them
  // Fault injection for tests of the error paths, which lavapipe cannot be made to take:
  // VK_ERROR_DEVICE_LOST replaces the result of every frame's fence wait, and
  // VK_ERROR_OUT_OF_DEVICE_MEMORY the result of every vkAllocateMemory. VK_SUCCESS injects nothing.
  VkResult injected_fault = VK_SUCCESS;
  // For a window (caustica view): instance extensions the window system needs (GLFW names them)
  // and VK_KHR_swapchain on the device.
  std::vector<std::string> instance_extensions;
  bool presentation = false;
  // Leaves ray queries off on a device that has them, as on a device without them: for tests of
  // the refusal path, and to compare. CAUSTICA_NO_RAY_QUERY=1 in the environment does the same.
  bool disable_ray_queries = false;
};

// Whether a device can trace exact paths: VK_KHR_acceleration_structure and VK_KHR_ray_query with
// their features and buffer device address. `missing` names what it lacks ("" when it has all).
struct RayQuerySupport {
  bool available = false;
  std::string missing;
};

// The device that Context would pick for `device_name`, probed without creating it: for checking a
// graph that traces without a device (caustica validate: which tracer it takes). Throws as Context does.
RayQuerySupport probe_ray_queries(const std::string& device_name, bool disable = false);

struct DeviceInfo {
  std::string name;
  VkPhysicalDeviceType type;
  uint32_t api_version;
};

// Throws DeviceError when Vulkan cannot start; InputError when --device names no device.
class Context {
 public:
  explicit Context(const ContextOptions& options);
  ~Context();
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  VkInstance instance() const { return instance_; }
  VkPhysicalDevice physical_device() const { return physical_; }
  VkDevice device() const { return device_; }
  VkQueue queue() const { return queue_; }
  // The pipelines made on this device, for reuse (vk/pipeline.h).
  PipelineCache& pipelines() { return *pipelines_; }
  uint32_t queue_family() const { return queue_family_; }
  const VkPhysicalDeviceProperties& properties() const { return properties_; }
  // How many descriptors one pipeline's pushed set may hold (VK_KHR_push_descriptor; 32 on
  // lavapipe and most GPUs).
  uint32_t max_push_descriptors() const { return max_push_descriptors_; }
  const std::string& device_name() const { return device_name_; }
  bool validation_enabled() const { return validation_; }
  uint32_t validation_messages() const { return validation_messages_.load(); }
  uint32_t timestamp_valid_bits() const { return timestamp_valid_bits_; }
  // VK_EXT_shader_atomic_float's buffer and image float32 add (lavapipe and most GPUs have them).
  bool float_atomics() const { return float_atomics_; }
  // Subgroup arithmetic in compute shaders (Vulkan 1.1's optional KHR_shader_subgroup_arithmetic;
  // lavapipe and desktop GPUs have it): the photon kernels add their counters up by subgroup.
  bool subgroup_arithmetic() const { return subgroup_arithmetic_; }
  // shaderSampledImageArrayNonUniformIndexing (lavapipe and desktop GPUs have it): scene textures.
  bool nonuniform_textures() const { return nonuniform_textures_; }
  // VK_KHR_acceleration_structure + VK_KHR_ray_query, enabled (see RayQuerySupport).
  const RayQuerySupport& ray_queries() const { return ray_queries_; }
  // Set when ray_queries().available: the extension entry points the loader does not export.
  struct RayTracingFunctions {
    PFN_vkCreateAccelerationStructureKHR create = nullptr;
    PFN_vkDestroyAccelerationStructureKHR destroy = nullptr;
    PFN_vkGetAccelerationStructureBuildSizesKHR build_sizes = nullptr;
    PFN_vkCmdBuildAccelerationStructuresKHR cmd_build = nullptr;
    PFN_vkGetAccelerationStructureDeviceAddressKHR address = nullptr;
  } rt;
  // Takes ownership of a window surface made on instance(); destroyed after every swapchain.
  void adopt_surface(VkSurfaceKHR surface) { surface_ = surface; }
  // What a frame's fence wait returns instead of `waited` when a fault is injected (ContextOptions).
  VkResult frame_result(VkResult waited) const { return injected_fault_ == VK_ERROR_DEVICE_LOST ? injected_fault_ : waited; }

  // Memory type index with all of `required` among `type_bits`, preferring `preferred` too.
  uint32_t memory_type(uint32_t type_bits, VkMemoryPropertyFlags required, VkMemoryPropertyFlags preferred = 0) const;
  // `device_address` allocates with VK_MEMORY_ALLOCATE_DEVICE_ADDRESS_BIT (acceleration structure inputs).
  OwnedMemory allocate(VkMemoryRequirements requirements, VkMemoryPropertyFlags required, const char* what,
                       VkMemoryPropertyFlags preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT, bool device_address = false);

  // Names an object for validation messages and capture tools.
  void set_name(VkObjectType type, uint64_t handle, const std::string& name) const;
  void begin_label(VkCommandBuffer cmd, const std::string& name) const;
  void end_label(VkCommandBuffer cmd) const;

  // Push descriptors (VK_KHR_push_descriptor) keep passes free of descriptor pools.
  PFN_vkCmdPushDescriptorSetKHR push_descriptor_set = nullptr;

  // Deferred destruction: queued destroys run after the GPU finished everything submitted so far.
  void defer(std::function<void(VkDevice)> destroy);
  uint64_t begin_submission() { return ++submission_; }  // the serial of the submission being built
  void retire(uint64_t completed_submission);            // call once that submission's fence signalled
  void wait_idle();
  // The device runs work that will not finish (a frame past its timeout, a signal during a wait):
  // from now on nothing waits for it and nothing is destroyed (the objects may still be in use), so
  // that the process can unwind and exit. The objects are the process's to free at exit.
  void abandon() { abandoned_ = true; }
  // Records commands into a one-time command buffer, submits it and waits (uploads at load time).
  void submit_and_wait(const std::function<void(VkCommandBuffer)>& record);

  static std::vector<DeviceInfo> list_devices();

 private:
  VkInstance instance_ = VK_NULL_HANDLE;
  VkDebugUtilsMessengerEXT messenger_ = VK_NULL_HANDLE;
  VkPhysicalDevice physical_ = VK_NULL_HANDLE;
  VkDevice device_ = VK_NULL_HANDLE;
  VkQueue queue_ = VK_NULL_HANDLE;
  std::unique_ptr<PipelineCache> pipelines_;
  uint32_t queue_family_ = 0;
  uint32_t timestamp_valid_bits_ = 0;
  bool float_atomics_ = false;
  bool nonuniform_textures_ = false;
  bool subgroup_arithmetic_ = false;
  RayQuerySupport ray_queries_;
  VkPhysicalDeviceProperties properties_{};
  uint32_t max_push_descriptors_ = 32;
  VkPhysicalDeviceMemoryProperties memory_properties_{};
  std::string device_name_;
  bool validation_ = false;
  bool quiet_validation_ = false;
  std::atomic<uint32_t> validation_messages_{0};
  PFN_vkCmdBeginDebugUtilsLabelEXT begin_label_ = nullptr;
  PFN_vkCmdEndDebugUtilsLabelEXT end_label_ = nullptr;
  PFN_vkSetDebugUtilsObjectNameEXT set_name_ = nullptr;
  struct Pending {
    uint64_t submission;
    std::function<void(VkDevice)> destroy;
  };
  std::vector<Pending> pending_;
  uint64_t submission_ = 0;
  bool abandoned_ = false;
  VkResult injected_fault_ = VK_SUCCESS;
  VkSurfaceKHR surface_ = VK_NULL_HANDLE;

  static VKAPI_ATTR VkBool32 VKAPI_CALL on_message(VkDebugUtilsMessageSeverityFlagBitsEXT severity, VkDebugUtilsMessageTypeFlagsEXT types,
                                                   const VkDebugUtilsMessengerCallbackDataEXT* data, void* user);
};

// A resettable primary command buffer with its pool and an unsignalled fence: what one frame in
// flight records into and waits on.
struct FrameCommands {
  OwnedCommandPool pool;
  VkCommandBuffer cmd = VK_NULL_HANDLE;  // freed with the pool
  OwnedFence fence;
};
FrameCommands make_frame_commands(Context& vk);
OwnedSemaphore make_semaphore(Context& vk);

// A global memory barrier (synchronization2).
void memory_barrier(VkCommandBuffer cmd, VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages,
                    VkAccessFlags2 dst_access);

// A barrier on the first `levels` mip levels and `layers` layers of an image (synchronization2), to
// record with others.
VkImageMemoryBarrier2 image_transition(VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                                       VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages,
                                       VkAccessFlags2 dst_access, uint32_t levels, uint32_t layers);
// A layout transition of the first `levels` mip levels of a single-layer image (synchronization2).
void image_barrier(VkCommandBuffer cmd, VkImage image, VkImageAspectFlags aspect, VkImageLayout from, VkImageLayout to,
                   VkPipelineStageFlags2 src_stages, VkAccessFlags2 src_access, VkPipelineStageFlags2 dst_stages, VkAccessFlags2 dst_access,
                   uint32_t levels = 1);

// Throws DeviceError naming the call and the VkResult.
void check(VkResult result, const char* call);
const char* result_name(VkResult result);

}  // namespace caustica::vk
