#pragma once
// The photon reference split over processes or machines (docs/cluster.md): shard I of K traces a
// contiguous range of the photons and writes its sums, exactly, with what it is a part of in the
// file's header; merging adds the shards that tile the whole range into the map that one process
// writes, bit for bit, and refuses shards that do not belong together.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "io/image_io.h"
#include "reference/photon_reference.h"
#include "reference/shard_file.h"
#include "scene/scene.h"

namespace caustica::reference {

// What a photon shard file's header says about it: its photons [first, end) of `total` (the
// photon count), what else makes its map, and the flux totals of its photons.
struct PhotonShard : ShardHeader {
  uint32_t light = 0;  // the scene's light whose photons these are
  uint32_t map_size = 0;
  bool fresnel = true;
  double unit = 1;  // flux per unit of the sums
  PhotonTotals totals;
};

// A hash of what the photons meet in a loaded scene (lights, meshes, materials, textures): two
// machines that load the same scene from different paths agree, and a change to the scene file or
// to a file it loads that changes the photons is seen.
std::string scene_identity(const scene::Scene& scene);

// Traces shard `index` of `count` of options.photons (options' own range is replaced).
struct TracedShard {
  PhotonShard shard;
  std::vector<uint64_t> map_units;
};
TracedShard trace_photon_shard(const scene::Scene& scene, PhotonOptions options, uint64_t index, uint64_t count);

// An EXR of the shard's sums (each channel's 64-bit units as two 32-bit halves, so that adding
// shards is exact) with `shard` in its header; through a temporary file and a rename, so that a
// shard killed while writing leaves no file.
void write_photon_shard(const std::string& path, const PhotonShard& shard, const std::vector<uint64_t>& map_units);
// Throws InputError when the file is not a photon shard.
PhotonShard read_photon_shard(const std::string& path);

struct MergedPhotons {
  PhotonShard whole;  // the range [0, total) with the shards' totals added
  io::ImageData caustic_map;
};

// Adds the shards in the order of their photon ranges, one file at a time (memory: two maps' sums).
// Throws InputError naming every problem: a missing range (and the shard indices that trace it), an
// overlap, a duplicate, a shard of another scene, light, seed, photon count, map size, Fresnel
// setting or engine build.
MergedPhotons merge_photon_shards(const std::vector<std::string>& paths);

}  // namespace caustica::reference
