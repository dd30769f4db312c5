#include "reference/camera_shard.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>

#include <cinttypes>
#include <cstdio>
#include <tuple>

#include "core/content_hash.h"
#include "core/engine_identity.h"
#include "core/error.h"
#include "reference/photon_shard.h"
#include "reference/refraction_reference.h"

namespace caustica::reference {
namespace {

const ShardKind kCamera{"caustica camera shard", "camera shard", "rows",
                        "image height",          "the image",    "caustica reference --size WxH --shard I/K"};
constexpr const char* kCameraChannels[] = {"R", "G", "B", "A"};

std::string hex(uint64_t value) {
  char text[17];
  std::snprintf(text, sizeof(text), "%016" PRIx64, value);
  return text;
}

// The image's rows as EXR slices: pixel (x, y) of the whole image at rgba[(y - first_row) * width + x].
Imf::FrameBuffer camera_frame(float* rgba, uint32_t width, uint64_t first_row) {
  constexpr size_t pixel = 4 * sizeof(float);
  Imf::FrameBuffer frame;
  for (size_t c = 0; c < 4; ++c) {
    char* base = reinterpret_cast<char*>(rgba + c) - static_cast<ptrdiff_t>(first_row * width * pixel);
    frame.insert(kCameraChannels[c], Imf::Slice(Imf::FLOAT, base, pixel, pixel * width));
  }
  return frame;
}

// Reads the header, and with `image` (the whole image) also the shard's rows into it.
CameraShard read_camera_rows(const std::string& path, io::ImageData* image) {
  CameraShard shard;
  static_cast<ShardHeader&>(shard) = read_shard_file(path, kCamera, [&](Imf::InputFile& file, const ShardAttributes& attributes) {
    const Imf::Header& header = file.header();
    shard.width = static_cast<uint32_t>(std::min<uint64_t>(attributes.count("width"), 1u << 20));
    shard.caustics_identity = attributes.text("caustics");
    const uint64_t first = attributes.count("first"), end = attributes.count("end"), height = attributes.count("rows");
    const Imath::Box2i data = header.dataWindow(), display = header.displayWindow();
    if (shard.width == 0 || shard.width > 65536 || height > 65536 || display.min.x != 0 || display.min.y != 0 ||
        uint64_t(display.max.x) + 1 != shard.width || uint64_t(display.max.y) + 1 != height || data.min.x != 0 ||
        data.max.x != display.max.x || uint64_t(data.min.y) != first || uint64_t(data.max.y) + 1 != end) {
      attributes.damaged("its windows are not its rows of the image");
    }
    for (const char* name : kCameraChannels) {
      const Imf::Channel* channel = header.channels().findChannel(name);
      if (channel == nullptr || channel->type != Imf::FLOAT) attributes.damaged(std::string("no float channel ") + name);
    }
    if (image == nullptr) return;
    file.setFrameBuffer(camera_frame(image->rgba.data(), image->width, 0));
    file.readPixels(data.min.y, data.max.y);
  });
  return shard;
}

}  // namespace

std::string camera_scene_identity(const scene::Scene& scene) {
  ContentHash hash;
  const std::string photons = scene_identity(scene);
  hash.bytes(photons.data(), photons.size());
  hash.add(scene.camera);
  hash.add(scene.sky);
  hash.add(scene.ambient);
  return hex(hash.value());
}

std::string caustics_identity(const io::ImageData& caustic_map) {
  ContentHash hash;
  hash.add(caustic_map.width);
  hash.add(caustic_map.height);
  hash.add(caustic_map.rgba);
  return hex(hash.value());
}

std::string caustics_identity(const CausticMaps& caustic_maps) {
  std::string identity;
  for (size_t i = 0; i < caustic_maps.size(); ++i) {
    if (caustic_maps[i]) identity += (identity.empty() ? "" : ",") + std::to_string(i) + ":" + caustics_identity(*caustic_maps[i]);
  }
  if (identity.empty()) return "none";
  return identity.rfind("0:", 0) == 0 && identity.find(',') == std::string::npos ? identity.substr(2) : identity;
}

TracedCameraShard trace_camera_shard(const scene::Scene& scene, uint32_t width, uint32_t height, const CausticMaps& caustic_maps,
                                     uint64_t seed, uint64_t index, uint64_t count) {
  TracedCameraShard traced;
  CameraShard& shard = traced.shard;
  std::tie(shard.first, shard.end) = shard_range(height, index, count);
  shard.total = height;
  shard.seed = seed;
  shard.index = index;
  shard.count = count;
  shard.width = width;
  shard.caustics_identity = caustics_identity(caustic_maps);
  shard.scene_name = scene.name;
  shard.scene_identity = camera_scene_identity(scene);
  shard.engine_identity = engine_identity();
  const ImageRows rows{static_cast<uint32_t>(shard.first), static_cast<uint32_t>(shard.end)};
  traced.rows = render_refraction_reference(scene, width, height, caustic_maps, seed, rows).radiance;
  return traced;
}

void write_camera_shard(const std::string& path, const CameraShard& shard, const io::ImageData& rows) {
  Imf::Header header(
      Imath::Box2i({0, 0}, {static_cast<int>(shard.width) - 1, static_cast<int>(shard.total) - 1}),
      Imath::Box2i({0, static_cast<int>(shard.first)}, {static_cast<int>(shard.width) - 1, static_cast<int>(shard.end) - 1}));
  header.compression() = Imf::ZIP_COMPRESSION;
  write_shard_header(header, kCamera, shard);
  set_shard_count(header, "width", shard.width);
  header.insert("caustica.caustics", Imf::StringAttribute(shard.caustics_identity));
  for (const char* name : kCameraChannels) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  std::vector<float> rgba = rows.rgba;  // the frame buffer takes non-const pointers
  write_shard_file(path, header, camera_frame(rgba.data(), shard.width, shard.first));
}

CameraShard read_camera_shard(const std::string& path) {
  return read_camera_rows(path, nullptr);
}

MergedCamera merge_camera_shards(const std::vector<std::string>& paths) {
  const auto shards = read_checked_shards<CameraShard>(kCamera, paths, read_camera_shard, [](const CameraShard& s) {
    return std::vector<std::pair<std::string, std::string>>{{"image width", std::to_string(s.width)}, {"caustic map", s.caustics_identity}};
  });
  const CameraShard& base = shards.front().first;
  MergedCamera merged;
  merged.whole = base;
  merged.whole.first = 0;
  merged.whole.end = base.total;
  merged.image.width = base.width;
  merged.image.height = static_cast<uint32_t>(base.total);
  merged.image.rgba.assign(size_t{base.width} * base.total * 4, 1.0f);
  for (const auto& [shard, path] : shards) read_camera_rows(path, &merged.image);
  return merged;
}

}  // namespace caustica::reference
