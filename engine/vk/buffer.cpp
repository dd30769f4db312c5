#include "vk/buffer.h"

#include <cstring>

namespace caustica::vk {

Buffer make_buffer(Context& vk, VkDeviceSize size, VkBufferUsageFlags usage, VkMemoryPropertyFlags required, const std::string& name,
                   VkMemoryPropertyFlags preferred) {
  Buffer out;
  out.size = size;
  VkBufferCreateInfo info{VK_STRUCTURE_TYPE_BUFFER_CREATE_INFO};
  info.size = size;
  info.usage = usage;
  VkBuffer handle = VK_NULL_HANDLE;
  check(vkCreateBuffer(vk.device(), &info, nullptr, &handle), "vkCreateBuffer");
  out.buffer = OwnedBuffer(vk, handle);
  VkMemoryRequirements requirements;
  vkGetBufferMemoryRequirements(vk.device(), handle, &requirements);
  out.memory = vk.allocate(requirements, required, name.c_str(), preferred, (usage & VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT) != 0);
  check(vkBindBufferMemory(vk.device(), handle, out.memory.get(), 0), "vkBindBufferMemory");
  vk.set_name(VK_OBJECT_TYPE_BUFFER, reinterpret_cast<uint64_t>(handle), name);
  if (required & VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT) {
    check(vkMapMemory(vk.device(), out.memory.get(), 0, VK_WHOLE_SIZE, 0, &out.mapped), "vkMapMemory");
  }
  return out;
}

Buffer make_static_buffer(Context& vk, const void* data, VkDeviceSize bytes, VkBufferUsageFlags usage, const std::string& name) {
  Buffer staging = make_buffer(vk, bytes, VK_BUFFER_USAGE_TRANSFER_SRC_BIT,
                               VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, name + " staging", 0);
  std::memcpy(staging.mapped, data, bytes);
  Buffer out = make_buffer(vk, bytes, usage | VK_BUFFER_USAGE_TRANSFER_DST_BIT, 0, name);
  vk.submit_and_wait([&](VkCommandBuffer cmd) {
    VkBufferCopy copy{0, 0, bytes};
    vkCmdCopyBuffer(cmd, staging.get(), out.get(), 1, &copy);
  });
  return out;
}

}  // namespace caustica::vk

namespace caustica::vk {

VkDeviceAddress device_address(const Context& vk, VkBuffer buffer) {
  VkBufferDeviceAddressInfo info{VK_STRUCTURE_TYPE_BUFFER_DEVICE_ADDRESS_INFO};
  info.buffer = buffer;
  return vkGetBufferDeviceAddress(vk.device(), &info);
}

}  // namespace caustica::vk
