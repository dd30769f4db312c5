#include "vk/host_heap.h"

#include <cstdlib>
#include <cstring>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace caustica::vk {

// Why: lavapipe's binning, descriptor and command memory is malloc'd and freed tens of megabytes
// a frame. glibc gives the top of a heap back to the kernel whenever more than its trim threshold
// is free there (by default twice a threshold that adapts to the largest freed block), so each
// frame faulted the same pages in again: 2,300 page faults a frame rendering the default graph at
// 320x180 with 256^2 light maps, the raster passes three times slower for it, the viewer's moving
// frames 100 ms instead of 35 (docs/lavapipe.md). A GPU driver's frames allocate little on the host,
// so the heap is left alone there.
HostHeapPolicy keep_freed_memory(VkPhysicalDeviceType device_type) {
  if (device_type != VK_PHYSICAL_DEVICE_TYPE_CPU) return {false, "not a CPU device"};
  if (const char* env = std::getenv("CAUSTICA_KEEP_FREED_MEMORY"); env && std::strcmp(env, "0") == 0)
    return {false, "switched off by CAUSTICA_KEEP_FREED_MEMORY=0"};
  if (const char* tunables = std::getenv("GLIBC_TUNABLES"); tunables && std::strstr(tunables, "glibc.malloc.") != nullptr)
    return {false, "GLIBC_TUNABLES sets the heap"};
#if defined(CAUSTICA_SANITIZER_ALLOCATOR)
  return {false, "the sanitizer's allocator, not glibc's"};
#elif defined(__GLIBC__)
  const bool set = mallopt(M_MMAP_THRESHOLD, static_cast<int>(kHeapMmapThreshold)) == 1 &&
                   mallopt(M_TRIM_THRESHOLD, static_cast<int>(kHeapTrimThreshold)) == 1;
  return {set, set ? "kept" : "mallopt refused the thresholds"};
#else
  return {false, "not glibc's allocator"};
#endif
}

}  // namespace caustica::vk
