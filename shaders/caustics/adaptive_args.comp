#version 460
// Between two levels of the adaptive traversal: the indirect dispatch for the clusters the last
// level appended, and the peak memory of the two live lists.
#extension GL_GOOGLE_include_directive : require
#include "caustics/adaptive_common.glsl"

layout(local_size_x = 1) in;

void main() {
  uint n = min(counts[params.level], list_capacity());
  uint groups = (n + GROUP - 1u) / GROUP;
  const uint MAX_X = 65535u;  // the minimum maxComputeWorkGroupCount[0] every device has
  args[params.level][0] = min(groups, MAX_X);
  args[params.level][1] = groups == 0u ? 0u : (groups + MAX_X - 1u) / MAX_X;
  args[params.level][2] = 1u;
  uint live = n + min(counts[params.level - 1u], list_capacity());
  atomicMax(counters[params.counter_slot[7]], live * 4u);
}
