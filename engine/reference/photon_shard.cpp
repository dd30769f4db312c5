#include "reference/photon_shard.h"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>

#include <algorithm>
#include <cinttypes>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <numeric>
#include <tuple>

#include "core/content_hash.h"
#include "core/engine_identity.h"
#include "core/error.h"
#include "io/files.h"

namespace caustica::reference {
namespace {

constexpr const char* kKind = "caustica photon shard";
constexpr const char* kColours[] = {"R", "G", "B"};

// The totals' doubles by their header names, for writing and reading alike.
constexpr std::pair<const char*, double PhotonTotals::*> kTotals[] = {
    {"emitted", &PhotonTotals::emitted}, {"direct", &PhotonTotals::direct},   {"entering", &PhotonTotals::entering},
    {"landed", &PhotonTotals::landed},   {"off_map", &PhotonTotals::off_map}, {"reflected", &PhotonTotals::reflected},
    {"escaped", &PhotonTotals::escaped}, {"trapped", &PhotonTotals::trapped}, {"absorbed", &PhotonTotals::absorbed}};

// 64-bit counts as decimal strings: EXR has no 64-bit integer attribute.
void set_count(Imf::Header& header, const std::string& name, uint64_t value) {
  header.insert("caustica." + name, Imf::StringAttribute(std::to_string(value)));
}

template <typename Attribute>
const Attribute& attribute(const Imf::Header& header, const std::string& path, const std::string& name) {
  const auto* found = header.findTypedAttribute<Attribute>("caustica." + name);
  if (found == nullptr) throw InputError(path + ": not a photon shard: its header has no caustica." + name);
  return *found;
}

uint64_t count(const Imf::Header& header, const std::string& path, const std::string& name) {
  const std::string& text = attribute<Imf::StringAttribute>(header, path, name).value();
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 19) {
    throw InputError(path + ": caustica." + name + " '" + text + "' is not a count");
  }
  return std::stoull(text);
}

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

std::string range_text(uint64_t first, uint64_t end) {
  return "photons " + std::to_string(first) + " to " + std::to_string(end - 1);
}

std::string shard_text(const std::string& path, const PhotonShard& shard) {
  return path + " (" + range_text(shard.first, shard.end) + ")";
}

// "2", "2, 5" or "3 to 7": the indices of a sharding that trace [first, end).
std::string indices_tracing(uint64_t first, uint64_t end, uint64_t photons, uint64_t count) {
  std::vector<uint64_t> indices;
  for (uint64_t i = 0; i < count; ++i) {
    const auto [a, b] = shard_range(photons, i, count);
    if (a < end && first < b) indices.push_back(i);
  }
  if (indices.size() > 2 && indices.back() - indices.front() + 1 == indices.size()) {
    return std::to_string(indices.front()) + " to " + std::to_string(indices.back());
  }
  std::string text;
  for (const uint64_t i : indices) text += (text.empty() ? "" : ", ") + std::to_string(i);
  return text;
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

std::pair<uint64_t, uint64_t> shard_range(uint64_t photons, uint64_t index, uint64_t count) {
  // photons * i / count, without the product's overflow.
  const auto at = [&](uint64_t i) { return photons / count * i + photons % count * i / count; };
  return {at(index), at(index + 1)};
}

TracedShard trace_photon_shard(const scene::Scene& scene, PhotonOptions options, uint64_t index, uint64_t count) {
  std::tie(options.first_photon, options.end_photon) = shard_range(options.photons, index, count);
  PhotonSums sums = trace_photon_sums(scene, options);
  TracedShard traced;
  PhotonShard& shard = traced.shard;
  shard.first = options.first_photon;
  shard.end = options.end_photon;
  shard.photons = options.photons;
  shard.seed = options.seed;
  shard.index = index;
  shard.count = count;
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
  header.compression() = Imf::ZIP_COMPRESSION;
  header.insert("caustica.kind", Imf::StringAttribute(kKind));
  set_count(header, "first", shard.first);
  set_count(header, "end", shard.end);
  set_count(header, "photons", shard.photons);
  set_count(header, "seed", shard.seed);
  set_count(header, "index", shard.index);
  set_count(header, "count", shard.count);
  set_count(header, "landed_photons", shard.totals.landed_photons);
  header.insert("caustica.fresnel", Imf::IntAttribute(shard.fresnel ? 1 : 0));
  header.insert("caustica.unit", Imf::DoubleAttribute(shard.unit));
  header.insert("caustica.scene", Imf::StringAttribute(shard.scene_name));
  header.insert("caustica.scene_identity", Imf::StringAttribute(shard.scene_identity));
  header.insert("caustica.engine", Imf::StringAttribute(shard.engine_identity));
  for (const auto& [name, member] : kTotals)
    header.insert(std::string("caustica.totals.") + name, Imf::DoubleAttribute(shard.totals.*member));
  SplitUnits units(map_units.size());
  for (size_t i = 0; i < map_units.size(); ++i) {
    units.high[i] = static_cast<uint32_t>(map_units[i] >> 32);
    units.low[i] = static_cast<uint32_t>(map_units[i]);
  }
  const Imf::FrameBuffer frame = frame_buffer(units, size);
  for (const auto& [name, half] : channels()) header.channels().insert(name, Imf::Channel(Imf::UINT));

  io::check_output_file(path);
  const std::filesystem::path target(path), temp = io::temporary_name(target);
  try {
    Imf::OutputFile file(temp.c_str(), header);
    file.setFrameBuffer(frame);
    file.writePixels(static_cast<int>(size));
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw InputError(path + ": cannot write: " + e.what());
  }
  io::commit(temp, target);
}

namespace {

// Reads the header, and with `add_to` also adds the file's units into it.
PhotonShard read_shard(const std::string& path, std::vector<uint64_t>* add_to) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path + ": cannot read: " + (std::filesystem::exists(path, ec) ? "not a file" : "no such file"));
  }
  if (!Imf::isOpenExrFile(path.c_str())) throw InputError(path + ": not a photon shard: not an EXR file");
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const auto* kind = header.findTypedAttribute<Imf::StringAttribute>("caustica.kind");
    if (kind == nullptr || kind->value() != kKind) {
      throw InputError(path + ": not a photon shard (caustica reference --shard writes them)");
    }
    PhotonShard shard;
    shard.first = count(header, path, "first");
    shard.end = count(header, path, "end");
    shard.photons = count(header, path, "photons");
    shard.seed = count(header, path, "seed");
    shard.index = count(header, path, "index");
    shard.count = count(header, path, "count");
    shard.totals.landed_photons = count(header, path, "landed_photons");
    shard.totals.photons = shard.end - shard.first;
    shard.fresnel = attribute<Imf::IntAttribute>(header, path, "fresnel").value() != 0;
    shard.unit = attribute<Imf::DoubleAttribute>(header, path, "unit").value();
    shard.scene_name = attribute<Imf::StringAttribute>(header, path, "scene").value();
    shard.scene_identity = attribute<Imf::StringAttribute>(header, path, "scene_identity").value();
    shard.engine_identity = attribute<Imf::StringAttribute>(header, path, "engine").value();
    for (const auto& [name, member] : kTotals)
      shard.totals.*member = attribute<Imf::DoubleAttribute>(header, path, std::string("totals.") + name).value();
    const Imath::Box2i window = header.dataWindow();
    const long width = long{window.max.x} - window.min.x + 1, height = long{window.max.y} - window.min.y + 1;
    if (window.min.x != 0 || window.min.y != 0 || width != height || width > 65536 || shard.first >= shard.end ||
        shard.end > shard.photons || shard.count == 0 || shard.index >= shard.count) {
      throw InputError(path + ": a damaged photon shard (its size or range does not hold together)");
    }
    shard.map_size = static_cast<uint32_t>(width);
    if (add_to == nullptr) return shard;
    const size_t values = size_t{shard.map_size} * shard.map_size * 3;
    SplitUnits units(values);
    for (const auto& [name, half] : channels()) {
      const Imf::Channel* channel = header.channels().findChannel(name);
      if (channel == nullptr || channel->type != Imf::UINT) throw InputError(path + ": a damaged photon shard (no channel " + name + ")");
    }
    file.setFrameBuffer(frame_buffer(units, shard.map_size));
    file.readPixels(0, static_cast<int>(shard.map_size) - 1);
    for (size_t i = 0; i < values; ++i) (*add_to)[i] += uint64_t{units.high[i]} << 32 | units.low[i];
    return shard;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read the photon shard: " + e.what());
  }
}

}  // namespace

PhotonShard read_photon_shard(const std::string& path) {
  return read_shard(path, nullptr);
}

MergedPhotons merge_photon_shards(const std::vector<std::string>& paths) {
  if (paths.empty()) throw InputError("merge needs at least one photon shard");
  std::vector<PhotonShard> shards;
  for (const auto& path : paths) shards.push_back(read_photon_shard(path));
  std::vector<size_t> order(shards.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::pair(shards[a].first, shards[a].end) < std::pair(shards[b].first, shards[b].end);
  });

  // Everything that makes shards parts of one map, against the first by range.
  std::vector<std::string> problems;
  const PhotonShard& base = shards[order.front()];
  const std::string& base_path = paths[order.front()];
  for (const size_t k : order) {
    const PhotonShard& s = shards[k];
    auto differs = [&](const std::string& what, const std::string& value, const std::string& base_value) {
      if (value != base_value) problems.push_back(paths[k] + ": " + what + " " + value + ", where " + base_path + " has " + base_value);
    };
    differs("scene", s.scene_name + " (identity " + s.scene_identity + ")", base.scene_name + " (identity " + base.scene_identity + ")");
    differs("seed", std::to_string(s.seed), std::to_string(base.seed));
    differs("photon count", std::to_string(s.photons), std::to_string(base.photons));
    differs("map size", std::to_string(s.map_size), std::to_string(base.map_size));
    differs("Fresnel", s.fresnel ? "on" : "off", base.fresnel ? "on" : "off");
    differs("engine", s.engine_identity, base.engine_identity);
  }
  if (problems.empty()) {
    // The ranges, in order, must tile [0, photons): name each gap (with the shard indices that
    // trace it, where every shard was cut alike), overlap and duplicate.
    const bool one_sharding = std::all_of(shards.begin(), shards.end(), [&](const PhotonShard& s) { return s.count == base.count; });
    auto missing = [&](uint64_t first, uint64_t end) {
      std::string text = range_text(first, end) + " are missing";
      if (one_sharding) text += ": shard " + indices_tracing(first, end, base.photons, base.count) + " of " + std::to_string(base.count);
      problems.push_back(text);
    };
    uint64_t covered = 0;
    size_t reaching = order.front();  // the shard that reaches `covered`
    for (size_t n = 0; n < order.size(); ++n) {
      const size_t k = order[n];
      const PhotonShard& s = shards[k];
      if (n > 0 && s.first == shards[order[n - 1]].first && s.end == shards[order[n - 1]].end) {
        const std::string& other = paths[order[n - 1]];
        problems.push_back(other == paths[k] ? paths[k] + " is given twice"
                                             : paths[k] + " and " + other + " are the same shard (" + range_text(s.first, s.end) + ")");
        continue;
      }
      if (s.first < covered) problems.push_back(shard_text(paths[k], s) + " overlaps " + shard_text(paths[reaching], shards[reaching]));
      if (s.first > covered) missing(covered, s.first);
      if (s.end > covered) {
        covered = s.end;
        reaching = k;
      }
    }
    if (covered < base.photons) missing(covered, base.photons);
  }
  if (!problems.empty()) {
    std::string text = "cannot merge the photon shards:";
    for (const auto& p : problems) text += "\n  " + p;
    throw InputError(text);
  }

  MergedPhotons merged;
  merged.whole = base;
  merged.whole.first = 0;
  merged.whole.end = base.photons;
  merged.whole.totals = {};
  std::vector<uint64_t> units(size_t{base.map_size} * base.map_size * 3, 0);
  for (const size_t k : order) add_totals(merged.whole.totals, read_shard(paths[k], &units).totals);
  merged.caustic_map = caustic_map_from_sums(units, base.map_size, base.unit);
  return merged;
}

}  // namespace caustica::reference
