#ifndef CAUSTICA_GROUP_TOTALS_GLSL
#define CAUSTICA_GROUP_TOTALS_GLSL
// Per-workgroup totals for the photon counters, added to the counter buffer once per group instead
// of once per photon. Counts use shared uint atomics; sums are reduced in shared memory without
// float atomics on shared memory (an optional feature). Needs `counters`, `sums` and the slots:
// count k at slot GROUP_COUNTER_SLOT(k), sum k at GROUP_COUNTER_SLOT(sum_base + k). The built-in
// passes push theirs (params.counter_slot[]); a user pass defines GROUP_COUNTER_SLOT(k) as (k), its
// counters' order in the graph file (docs/shader_api.md). Workgroups of 64 invocations.
#ifndef GROUP_COUNTER_SLOT
#define GROUP_COUNTER_SLOT(k) params.counter_slot[k]
#endif
const uint MAX_COUNTS = 8u, MAX_SUMS = 3u;
shared uint group_counts[MAX_COUNTS];
shared float group_sums[MAX_SUMS][64];
float sums_here[MAX_SUMS];

void begin_group_totals() {
  if (gl_LocalInvocationIndex < MAX_COUNTS) group_counts[gl_LocalInvocationIndex] = 0u;
  for (uint k = 0u; k < MAX_SUMS; ++k) sums_here[k] = 0.0;
  barrier();
}

void count(uint k) { atomicAdd(group_counts[k], 1u); }
void count_n(uint k, uint n) { atomicAdd(group_counts[k], n); }
void add_sum(uint k, float v) { sums_here[k] += v; }

void end_group_totals(uint counts, uint sum_base, uint n_sums) {
  for (uint k = 0u; k < MAX_SUMS; ++k) group_sums[k][gl_LocalInvocationIndex] = sums_here[k];
  barrier();
  for (uint stride = 32u; stride > 0u; stride >>= 1) {
    if (gl_LocalInvocationIndex < stride) {
      for (uint k = 0u; k < MAX_SUMS; ++k) group_sums[k][gl_LocalInvocationIndex] += group_sums[k][gl_LocalInvocationIndex + stride];
    }
    barrier();
  }
  if (gl_LocalInvocationIndex < counts && group_counts[gl_LocalInvocationIndex] != 0u) {
    atomicAdd(counters[GROUP_COUNTER_SLOT(gl_LocalInvocationIndex)], group_counts[gl_LocalInvocationIndex]);
  }
  if (gl_LocalInvocationIndex < n_sums) atomicAdd(sums[GROUP_COUNTER_SLOT(sum_base + gl_LocalInvocationIndex)], group_sums[gl_LocalInvocationIndex][0]);
}

#endif
