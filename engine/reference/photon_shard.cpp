#include "reference/photon_shard.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>

#include <cinttypes>
#include <cstdio>
#include <tuple>

#include "core/content_hash.h"
#include "core/engine_identity.h"
#include "core/error.h"

namespace caustica::reference {
namespace {

const ShardKind kPhotons{"caustica photon shard", "photon shard", "photons",
                         "photon count",          "the map",      "caustica reference --photons N --shard I/K"};
constexpr const char* kColours[] = {"R", "G", "B"};

// The totals' doubles by their header names, for writing and reading alike.
constexpr std::pair<const char*, double PhotonTotals::*> kTotals[] = {
    {"emitted", &PhotonTotals::emitted}, {"direct", &PhotonTotals::direct},   {"entering", &PhotonTotals::entering},
    {"landed", &PhotonTotals::landed},   {"off_map", &PhotonTotals::off_map}, {"reflected", &PhotonTotals::reflected},
    {"escaped", &PhotonTotals::escaped}, {"trapped", &PhotonTotals::trapped}, {"absorbed", &PhotonTotals::absorbed}};

// The two halves of every channel's units, as the file stores them.
struct SplitUnits {
  std::vector<uint32_t> high, low;
  explicit SplitUnits(size_t values) : high(values), low(values) {}
};

// The file's channels: units_high.R, units_low.R, ... (layers that an EXR viewer shows apart).
std::vector<std::pair<std::string, std::vector<uint32_t> SplitUnits::*>> channels() {
  std::vector<std::pair<std::string, std::vector<uint32_t> SplitUnits::*>> list;
  for (const char* colour : kColours) {
    list.emplace_back(std::string("units_high.") + colour, &SplitUnits::high);
    list.emplace_back(std::string("units_low.") + colour, &SplitUnits::low);
  }
  return list;
}

Imf::FrameBuffer frame_buffer(SplitUnits& units, uint32_t width) {
  constexpr size_t stride = 3 * sizeof(uint32_t);
  Imf::FrameBuffer frame;
  size_t n = 0;
  for (const auto& [name, half] : channels()) {
    uint32_t* first = (units.*half).data() + n++ / 2;
    frame.insert(name, Imf::Slice(Imf::UINT, reinterpret_cast<char*>(first), stride, stride * width));
  }
  return frame;
}

}  // namespace

std::string scene_identity(const scene::Scene& scene) {
  ContentHash hash;
  for (const auto& light : scene.lights) {
    hash.add(light.type);
    hash.add(light.view);
    hash.add(light.intensity);
    hash.add(light.color);
    hash.add(light.extent);
    // What its photons leave through: fitted to the refractors or the light's own (a scene's
    // "caustic_view"), a cached reference of one is not the other's.
    hash.add(light.caustic_view);
    hash.add(light.caustic_extent);
    hash.add(light.has_caustic_view);
    hash.add(light.caustic_faces);
  }
  for (const auto& object : scene.objects) {
    const scene::Mesh& mesh = object.mesh;
    hash.add(mesh.positions);
    hash.add(mesh.normals);
    hash.add(mesh.indices);
    hash.add(mesh.normal_distance);
    hash.add(mesh.texcoords);
    hash.add(mesh.tangents);
    // Field by field: a bool's padding has no defined bytes.
    const scene::Material& m = object.material;
    for (const glm::vec3& v : {m.albedo, m.absorption, m.tint, m.tint_factor, m.emissive}) hash.add(v);
    for (const float v : {m.ior, m.transmission, m.transmission_roughness, m.dispersion, m.transmission_factor, m.metallic, m.roughness,
                          m.normal_scale, m.occlusion_strength, m.alpha, m.alpha_cutoff}) {
      hash.add(v);
    }
    for (const bool v : {m.refractor, m.thin, m.metallic_roughness, m.coverage_transmits, m.double_sided}) hash.add(v);
    for (const scene::TextureRef& t : {m.transmission_texture, m.base_color_texture, m.metallic_roughness_texture, m.normal_texture,
                                       m.emissive_texture, m.occlusion_texture}) {
      hash.add(t);
    }
    hash.add(m.alpha_mode);
  }
  for (const auto& texture : scene.textures) {
    hash.add(texture.width);
    hash.add(texture.height);
    hash.add(texture.rgba);
    for (const bool v : {texture.srgb, texture.nearest}) hash.add(v);
    for (const scene::Wrap w : {texture.wrap_u, texture.wrap_v}) hash.add(w);
  }
  char text[17];
  std::snprintf(text, sizeof(text), "%016" PRIx64, hash.value());
  return text;
}

TracedShard trace_photon_shard(const scene::Scene& scene, PhotonOptions options, uint64_t index, uint64_t count) {
  std::tie(options.first_photon, options.end_photon) = shard_range(options.photons, index, count);
  PhotonSums sums = trace_photon_sums(scene, options);
  TracedShard traced;
  PhotonShard& shard = traced.shard;
  shard.first = options.first_photon;
  shard.end = options.end_photon;
  shard.total = options.photons;
  shard.seed = options.seed;
  shard.index = index;
  shard.count = count;
  shard.light = options.light;
  shard.map_size = options.map_size;
  shard.fresnel = options.fresnel;
  shard.unit = sums.unit;
  shard.scene_name = scene.name;
  shard.scene_identity = scene_identity(scene);
  shard.engine_identity = engine_identity();
  shard.totals = sums.totals;
  traced.map_units = std::move(sums.map);
  return traced;
}

void write_photon_shard(const std::string& path, const PhotonShard& shard, const std::vector<uint64_t>& map_units) {
  const uint32_t size = shard.map_size;
  Imf::Header header(static_cast<int>(size), static_cast<int>(size));
  // RLE: the high halves are almost all zero, and so is every texel the caustic misses. Against ZIP
  // the bunny's 64 shards of 10^8 photons at 512^2 are 52 MB, not 40, and merge in 1.5 s of CPU, not
  // 2.1 (zlib's inflate and ZIP's predictor are gone; docs/cluster.md).
  header.compression() = Imf::RLE_COMPRESSION;
  write_shard_header(header, kPhotons, shard);
  set_shard_count(header, "landed_photons", shard.totals.landed_photons);
  header.insert("caustica.fresnel", Imf::IntAttribute(shard.fresnel ? 1 : 0));
  header.insert("caustica.light", Imf::IntAttribute(static_cast<int>(shard.light)));
  header.insert("caustica.unit", Imf::DoubleAttribute(shard.unit));
  for (const auto& [name, member] : kTotals)
    header.insert(std::string("caustica.totals.") + name, Imf::DoubleAttribute(shard.totals.*member));
  SplitUnits units(map_units.size());
  for (size_t i = 0; i < map_units.size(); ++i) {
    units.high[i] = static_cast<uint32_t>(map_units[i] >> 32);
    units.low[i] = static_cast<uint32_t>(map_units[i]);
  }
  const Imf::FrameBuffer frame = frame_buffer(units, size);
  for (const auto& [name, half] : channels()) header.channels().insert(name, Imf::Channel(Imf::UINT));

  write_shard_file(path, header, frame);
}

namespace {

// Reads the header, and with `add_to` also adds the file's units into it.
// `units`: where the file's halves are read, kept from one file to the next by a merge.
PhotonShard read_shard(const std::string& path, std::vector<uint64_t>* add_to, SplitUnits* units = nullptr) {
  PhotonShard shard;
  static_cast<ShardHeader&>(shard) = read_shard_file(path, kPhotons, [&](Imf::InputFile& file, const ShardAttributes& attributes) {
    const Imf::Header& header = file.header();
    shard.totals.landed_photons = attributes.count("landed_photons");
    shard.fresnel = attributes.integer("fresnel") != 0;
    const int light = attributes.integer("light");
    if (light < 0) attributes.damaged("its light is " + std::to_string(light));
    shard.light = static_cast<uint32_t>(light);
    shard.unit = attributes.number("unit");
    for (const auto& [name, member] : kTotals) shard.totals.*member = attributes.number(std::string("totals.") + name);
    const Imath::Box2i window = header.dataWindow();
    const long width = long{window.max.x} - window.min.x + 1, height = long{window.max.y} - window.min.y + 1;
    if (window.min.x != 0 || window.min.y != 0 || width != height || width > 65536) attributes.damaged("its size does not hold together");
    shard.map_size = static_cast<uint32_t>(width);
    if (add_to == nullptr) return;
    const size_t values = size_t{shard.map_size} * shard.map_size * 3;
    SplitUnits own(0);
    SplitUnits& halves = units ? *units : own;
    halves.high.resize(values);
    halves.low.resize(values);
    for (const auto& [name, half] : channels()) {
      const Imf::Channel* channel = header.channels().findChannel(name);
      if (channel == nullptr || channel->type != Imf::UINT) attributes.damaged("no channel " + name);
    }
    file.setFrameBuffer(frame_buffer(halves, shard.map_size));
    file.readPixels(0, static_cast<int>(shard.map_size) - 1);
    for (size_t i = 0; i < values; ++i) (*add_to)[i] += uint64_t{halves.high[i]} << 32 | halves.low[i];
  });
  shard.totals.photons = shard.end - shard.first;
  return shard;
}

}  // namespace

PhotonShard read_photon_shard(const std::string& path) {
  return read_shard(path, nullptr);
}

MergedPhotons merge_photon_shards(const std::vector<std::string>& paths) {
  const auto shards = read_checked_shards<PhotonShard>(kPhotons, paths, read_photon_shard, [](const PhotonShard& s) {
    return std::vector<std::pair<std::string, std::string>>{
        {"light", std::to_string(s.light)}, {"map size", std::to_string(s.map_size)}, {"Fresnel", s.fresnel ? "on" : "off"}};
  });
  const PhotonShard& base = shards.front().first;
  MergedPhotons merged;
  merged.whole = base;
  merged.whole.first = 0;
  merged.whole.end = base.total;
  merged.whole.totals = {};
  std::vector<uint64_t> units(size_t{base.map_size} * base.map_size * 3, 0);
  SplitUnits halves(0);
  for (const auto& [shard, path] : shards) add_totals(merged.whole.totals, read_shard(path, &units, &halves).totals);
  merged.caustic_map = caustic_map_from_sums(units, base.map_size, base.unit);
  return merged;
}

}  // namespace caustica::reference
