#pragma once
// The ray-traced camera reference (refraction_reference.h) split over processes or machines
// (docs/cluster.md), as the photon reference is (photon_shard.h): shard I of K traces a contiguous
// range of the image's rows and writes them, exactly (32-bit floats, a pixel's random numbers keyed
// on the seed and its place in the whole image), with what it is a part of in the file's header;
// merging places the shards that tile the image's rows into the image that one process writes,
// bit for bit, and refuses shards that do not belong together.
#include <cstdint>
#include <string>
#include <vector>

#include "io/image_io.h"
#include "reference/refraction_reference.h"
#include "reference/shard_file.h"
#include "scene/scene.h"

namespace caustica::reference {

// What a camera shard file's header says about it: its rows [first, end) of `total` (the image's
// height), the image's width and the caustic map that lit it.
struct CameraShard : ShardHeader {
  uint32_t width = 0;
  std::string caustics_identity = "none";  // caustics_identity() of the --caustics maps, "none" without
};

// A hash of what the camera reference sees in a loaded scene: scene_identity() and the camera,
// the sky and the ambient light.
std::string camera_scene_identity(const scene::Scene& scene);
// A hash of a caustic map's size and values; of several, each light's with its index ("0:HASH,2:HASH"),
// or the hash alone where light 0 has the only one; "none" without.
std::string caustics_identity(const io::ImageData& caustic_map);
std::string caustics_identity(const CausticMaps& caustic_maps);

struct TracedCameraShard {
  CameraShard shard;
  io::ImageData rows;  // width x (end - first): the radiance of the shard's rows
};
// Traces shard `index` of `count` of a width x height camera reference, lit by `caustic_maps` (per light).
TracedCameraShard trace_camera_shard(const scene::Scene& scene, uint32_t width, uint32_t height, const CausticMaps& caustic_maps,
                                     uint64_t seed, uint64_t index, uint64_t count);

// An EXR of the shard's rows (RGBA floats; its data window is the rows, its display window the whole
// image) with `shard` in its header; through a temporary file and a rename.
void write_camera_shard(const std::string& path, const CameraShard& shard, const io::ImageData& rows);
// Throws InputError when the file is not a camera shard.
CameraShard read_camera_shard(const std::string& path);

struct MergedCamera {
  CameraShard whole;  // the rows [0, height)
  io::ImageData image;
};
// Reads the headers, then the rows, one file at a time, into the image (memory: the image and
// one shard's rows). Throws InputError naming every problem: missing rows (and the shard indices
// that trace them), an overlap, a duplicate, a shard of another scene, seed, size, caustic map or
// engine build.
MergedCamera merge_camera_shards(const std::vector<std::string>& paths);

}  // namespace caustica::reference
