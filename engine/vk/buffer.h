#pragma once
// A buffer with its own memory, mapped when host-visible, and a blocking upload for static data.
#include <string>

#include "vk/context.h"

namespace caustica::vk {

struct Buffer {
  OwnedBuffer buffer;
  OwnedMemory memory;
  VkDeviceSize size = 0;
  void* mapped = nullptr;  // when the memory is host-visible
  VkBuffer get() const { return buffer.get(); }
};

Buffer make_buffer(Context& vk, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags required, const std::string& name,
                   VkMemoryPropertyFlags preferred = VK_MEMORY_PROPERTY_DEVICE_LOCAL_BIT);

// A device-local buffer filled with `bytes` through a staging buffer; waits for the copy.
Buffer make_static_buffer(Context& vk, const void* data, VkDeviceSize bytes, VkBufferUsageFlags usage, const std::string& name);

// The buffer's address; it needs VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT (make_buffer then
// allocates its memory with the device-address flag).
VkDeviceAddress device_address(const Context& vk, VkBuffer buffer);

}  // namespace caustica::vk
