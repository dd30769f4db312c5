// The host heap's policy for a CPU device (engine/vk/host_heap.h), on the CPU: no device is made.
#include <gtest/gtest.h>

#include <cstdlib>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "vk/host_heap.h"

using caustica::vk::keep_freed_memory;

TEST(HostHeap, AGpuLeavesTheHeapAsItIs) {
  const auto policy = keep_freed_memory(VK_PHYSICAL_DEVICE_TYPE_DISCRETE_GPU);
  EXPECT_FALSE(policy.kept);
  EXPECT_EQ(policy.reason, "not a CPU device");
}

TEST(HostHeap, TheSwitchLeavesTheHeapAsItIs) {
  ::setenv("CAUSTICA_KEEP_FREED_MEMORY", "0", 1);
  const auto policy = keep_freed_memory(VK_PHYSICAL_DEVICE_TYPE_CPU);
  ::unsetenv("CAUSTICA_KEEP_FREED_MEMORY");
  EXPECT_FALSE(policy.kept);
  EXPECT_EQ(policy.reason, "switched off by CAUSTICA_KEEP_FREED_MEMORY=0");
}

TEST(HostHeap, OnACpuDeviceFreedMemoryStaysWithTheProcess) {
  const auto policy = keep_freed_memory(VK_PHYSICAL_DEVICE_TYPE_CPU);
#if defined(CAUSTICA_SANITIZER_ALLOCATOR)
  EXPECT_FALSE(policy.kept);
  EXPECT_EQ(policy.reason, "the sanitizer's allocator, not glibc's");
#else
  ASSERT_TRUE(policy.kept) << policy.reason;
  // 64 blocks of 1 MB, then freed. glibc's defaults map each block of over 128 KB on its own and
  // unmap it when it is freed; kept, they come from the heap, and the heap keeps them when freed.
  constexpr size_t kBlock = size_t{1} << 20;
  const size_t mapped_before = mallinfo2().hblkhd;
  std::vector<char*> blocks;
  for (int i = 0; i < 64; ++i) {
    blocks.push_back(static_cast<char*>(std::malloc(kBlock)));
    for (size_t at = 0; at < kBlock; at += 4096) blocks.back()[at] = 1;
  }
  const struct mallinfo2 held = mallinfo2();
  for (auto it = blocks.rbegin(); it != blocks.rend(); ++it) std::free(*it);
  const struct mallinfo2 freed = mallinfo2();
  EXPECT_LT(held.hblkhd - mapped_before, 4 * kBlock);  // from the heap, not mapped each on its own
  EXPECT_GE(freed.arena, 64 * kBlock);                 // and still the process's once freed
  EXPECT_GE(freed.fordblks, 64 * kBlock);
#endif
}
