#pragma once
// RAII for Vulkan objects. Destruction is deferred: an Owned handle going out of scope hands its
// destroy call to the Context, which runs it once the GPU has finished every frame submitted so far.
// No code outside this header and Context calls vkDestroy*/vkFree* directly.
#include <vulkan/vulkan.h>

#include <memory>
#include <utility>

namespace caustica::vk {

class Context;
void defer_destroy(Context& context, void (*destroy)(VkDevice, uint64_t), uint64_t handle);

template <typename T, void (*Destroy)(VkDevice, T, const VkAllocationCallbacks*)>
class Owned {
 public:
  Owned() = default;
  Owned(Context& context, T handle) : context_(&context), handle_(handle) {}
  ~Owned() { reset(); }
  Owned(const Owned&) = delete;
  Owned& operator=(const Owned&) = delete;
  Owned(Owned&& other) noexcept : context_(other.context_), handle_(std::exchange(other.handle_, T{})) {}
  Owned& operator=(Owned&& other) noexcept {
    if (this != &other) {
      reset();
      context_ = other.context_;
      handle_ = std::exchange(other.handle_, T{});
    }
    return *this;
  }

  T get() const { return handle_; }
  explicit operator bool() const { return handle_ != T{}; }

  void reset() {
    if (handle_ != T{}) {
      defer_destroy(*context_, &destroy_erased, reinterpret_cast<uint64_t>(handle_));
      handle_ = T{};
    }
  }

 private:
  static void destroy_erased(VkDevice device, uint64_t handle) { Destroy(device, reinterpret_cast<T>(handle), nullptr); }
  Context* context_ = nullptr;
  T handle_{};
};

using OwnedImage = Owned<VkImage, vkDestroyImage>;
using OwnedImageView = Owned<VkImageView, vkDestroyImageView>;
using OwnedBuffer = Owned<VkBuffer, vkDestroyBuffer>;
using OwnedMemory = Owned<VkDeviceMemory, vkFreeMemory>;
using OwnedSampler = Owned<VkSampler, vkDestroySampler>;
using OwnedShaderModule = Owned<VkShaderModule, vkDestroyShaderModule>;
using OwnedPipeline = Owned<VkPipeline, vkDestroyPipeline>;
using OwnedPipelineLayout = Owned<VkPipelineLayout, vkDestroyPipelineLayout>;
using OwnedSetLayout = Owned<VkDescriptorSetLayout, vkDestroyDescriptorSetLayout>;
using OwnedDescriptorPool = Owned<VkDescriptorPool, vkDestroyDescriptorPool>;
using OwnedQueryPool = Owned<VkQueryPool, vkDestroyQueryPool>;
using OwnedFence = Owned<VkFence, vkDestroyFence>;
using OwnedCommandPool = Owned<VkCommandPool, vkDestroyCommandPool>;
using OwnedSemaphore = Owned<VkSemaphore, vkDestroySemaphore>;
using OwnedRenderPass = Owned<VkRenderPass, vkDestroyRenderPass>;
using OwnedFramebuffer = Owned<VkFramebuffer, vkDestroyFramebuffer>;
using OwnedDescriptorPool = Owned<VkDescriptorPool, vkDestroyDescriptorPool>;
using OwnedSwapchain = Owned<VkSwapchainKHR, vkDestroySwapchainKHR>;

// An owned object that several holders share (a pipeline the process reuses): destroyed, deferred
// as an Owned one is, when the last holder lets it go.
template <typename O>
class Shared {
 public:
  Shared() = default;
  explicit Shared(O owned) : owned_(std::make_shared<O>(std::move(owned))) {}
  auto get() const { return owned_ ? owned_->get() : decltype(std::declval<const O&>().get()){}; }
  explicit operator bool() const { return owned_ && static_cast<bool>(*owned_); }
  bool shared_elsewhere() const { return owned_.use_count() > 1; }

 private:
  std::shared_ptr<O> owned_;
};

}  // namespace caustica::vk
