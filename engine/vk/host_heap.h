#pragma once
// The host heap's policy for a CPU Vulkan device, whose "device memory" and per-frame work are the
// process's own allocations (docs/lavapipe.md, "The heap between frames").
#include <vulkan/vulkan.h>

#include <string>

// Whether this build's malloc is a sanitizer's, which glibc's heap settings do not reach.
#if defined(__SANITIZE_ADDRESS__)
#define CAUSTICA_SANITIZER_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define CAUSTICA_SANITIZER_ALLOCATOR 1
#endif
#endif

namespace caustica::vk {

struct HostHeapPolicy {
  bool kept = false;   // freed memory stays with the process (up to kHeapTrimThreshold a heap)
  std::string reason;  // why it is or is not (the tests check it)
};

// glibc's heap, kept up to this many bytes free at the top of each heap before it goes back to
// the kernel; allocations below kHeapMmapThreshold come from the heaps.
inline constexpr size_t kHeapTrimThreshold = size_t{256} << 20;
inline constexpr size_t kHeapMmapThreshold = size_t{32} << 20;

// On a CPU device, unless CAUSTICA_KEEP_FREED_MEMORY=0 or GLIBC_TUNABLES sets glibc.malloc values
// of its own: sets the two thresholds above for the whole process (glibc's mallopt). Elsewhere, or
// where the allocator is not glibc's (a sanitizer's), leaves the heap as it is and says why.
HostHeapPolicy keep_freed_memory(VkPhysicalDeviceType device_type);

}  // namespace caustica::vk
