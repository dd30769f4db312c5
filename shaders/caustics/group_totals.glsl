#ifndef CAUSTICA_GROUP_TOTALS_GLSL
#define CAUSTICA_GROUP_TOTALS_GLSL
#extension GL_KHR_shader_subgroup_basic : require
#extension GL_KHR_shader_subgroup_arithmetic : require
// Per-subgroup totals for the photon counters, added to the counter buffer once per subgroup
// instead of once per photon: each invocation counts and sums in its own registers, and the
// subgroup adds them up. No shared memory and no barrier: llvmpipe runs a kernel that holds a
// barrier as coroutines whose frames it allocates for every workgroup (the adaptive kernel's
// caustic pass took 64 ms a frame so at 640x360, and 866 ms under AddressSanitizer, whose
// allocator maps and unmaps each frame). Needs `counters`, `sums` and the slots: count k at slot
// GROUP_COUNTER_SLOT(k), sum k at GROUP_COUNTER_SLOT(sum_base + k). The built-in passes push theirs
// (params.counter_slot[]); a user pass defines GROUP_COUNTER_SLOT(k) as (k), its counters' order
// in the graph file (docs/shader_api.md). begin_group_totals and end_group_totals are called by
// every invocation of the subgroup together (uniform control flow).
#ifndef GROUP_COUNTER_SLOT
#define GROUP_COUNTER_SLOT(k) params.counter_slot[k]
#endif
const uint MAX_COUNTS = 8u, MAX_SUMS = 3u;
uint counts_here[MAX_COUNTS];
float sums_here[MAX_SUMS];

void begin_group_totals() {
  for (uint k = 0u; k < MAX_COUNTS; ++k) counts_here[k] = 0u;
  for (uint k = 0u; k < MAX_SUMS; ++k) sums_here[k] = 0.0;
}

void count(uint k) { counts_here[k] += 1u; }
void count_n(uint k, uint n) { counts_here[k] += n; }
void add_sum(uint k, float v) { sums_here[k] += v; }

void end_group_totals(uint counts, uint sum_base, uint n_sums) {
  for (uint k = 0u; k < counts; ++k) {
    uint total = subgroupAdd(counts_here[k]);
    if (subgroupElect() && total != 0u) atomicAdd(counters[GROUP_COUNTER_SLOT(k)], total);
  }
  for (uint k = 0u; k < n_sums; ++k) {
    float total = subgroupAdd(sums_here[k]);
    if (subgroupElect()) atomicAdd(sums[GROUP_COUNTER_SLOT(sum_base + k)], total);
  }
}

#endif
