#include "reference/shard_file.h"

#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfTestFile.h>
#include <OpenEXR/ImfThreading.h>

#include <algorithm>
#include <exception>
#include <filesystem>
#include <numeric>
#include <thread>

#include "core/error.h"
#include "io/files.h"

namespace caustica::reference {
namespace {

// The kinds of shard there are, to name the one a file is where another was expected.
constexpr const char* kShardKinds[] = {"caustica photon shard", "caustica camera shard"};

std::string part_text(const ShardKind& kind, const std::string& path, const ShardHeader& shard) {
  return path + " (" + range_text(kind, shard.first, shard.end) + ")";
}

// "2", "2, 5" or "3 to 7": the indices of a sharding that do [first, end).
std::string indices_doing(uint64_t first, uint64_t end, uint64_t total, uint64_t count) {
  std::vector<uint64_t> indices;
  for (uint64_t i = 0; i < count; ++i) {
    const auto [a, b] = shard_range(total, i, count);
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

std::pair<uint64_t, uint64_t> shard_range(uint64_t total, uint64_t index, uint64_t count) {
  // total * i / count, without the product's overflow.
  const auto at = [&](uint64_t i) { return total / count * i + total % count * i / count; };
  return {at(index), at(index + 1)};
}

std::string range_text(const ShardKind& kind, uint64_t first, uint64_t end) {
  return std::string(kind.items) + " " + std::to_string(first) + " to " + std::to_string(end - 1);
}

void set_shard_count(Imf::Header& header, const std::string& name, uint64_t value) {
  header.insert("caustica." + name, Imf::StringAttribute(std::to_string(value)));
}

void write_shard_header(Imf::Header& header, const ShardKind& kind, const ShardHeader& shard) {
  header.insert("caustica.kind", Imf::StringAttribute(kind.kind));
  set_shard_count(header, "first", shard.first);
  set_shard_count(header, "end", shard.end);
  set_shard_count(header, kind.items, shard.total);
  set_shard_count(header, "seed", shard.seed);
  set_shard_count(header, "index", shard.index);
  set_shard_count(header, "count", shard.count);
  header.insert("caustica.scene", Imf::StringAttribute(shard.scene_name));
  header.insert("caustica.scene_identity", Imf::StringAttribute(shard.scene_identity));
  header.insert("caustica.engine", Imf::StringAttribute(shard.engine_identity));
}

void write_shard_file(const std::string& path, const Imf::Header& header, const Imf::FrameBuffer& frame) {
  io::check_output_file(path);
  const std::filesystem::path target(path), temp = io::temporary_name(target);
  try {
    Imf::OutputFile file(temp.c_str(), header);
    file.setFrameBuffer(frame);
    const Imath::Box2i window = header.dataWindow();
    file.writePixels(window.max.y - window.min.y + 1);
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(temp, ec);
    throw InputError(path + ": cannot write: " + e.what());
  }
  io::commit(temp, target);
}

template <typename Attribute>
const Attribute& ShardAttributes::find(const std::string& name) const {
  const auto* found = header_.findTypedAttribute<Attribute>("caustica." + name);
  if (found == nullptr) throw InputError(path_ + ": not a " + kind_.noun + ": its header has no caustica." + name);
  return *found;
}

uint64_t ShardAttributes::count(const std::string& name) const {
  const std::string& value = text(name);
  if (value.empty() || value.find_first_not_of("0123456789") != std::string::npos || value.size() > 19) {
    throw InputError(path_ + ": caustica." + name + " '" + value + "' is not a count");
  }
  return std::stoull(value);
}

const std::string& ShardAttributes::text(const std::string& name) const {
  return find<Imf::StringAttribute>(name).value();
}

double ShardAttributes::number(const std::string& name) const {
  return find<Imf::DoubleAttribute>(name).value();
}

int ShardAttributes::integer(const std::string& name) const {
  return find<Imf::IntAttribute>(name).value();
}

void ShardAttributes::damaged(const std::string& what) const {
  throw InputError(path_ + ": a damaged " + kind_.noun + " (" + what + ")");
}

ShardHeader read_shard_file(const std::string& path, const ShardKind& kind,
                            const std::function<void(Imf::InputFile& file, const ShardAttributes& attributes)>& rest) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path + ": cannot read: " + (std::filesystem::exists(path, ec) ? "not a file" : "no such file"));
  }
  if (!Imf::isOpenExrFile(path.c_str())) throw InputError(path + ": not a " + kind.noun + ": not an EXR file");
  try {
    Imf::InputFile file(path.c_str());
    const Imf::Header& header = file.header();
    const auto* found = header.findTypedAttribute<Imf::StringAttribute>("caustica.kind");
    if (found == nullptr || found->value() != kind.kind) {
      const bool other =
          found != nullptr && std::find(std::begin(kShardKinds), std::end(kShardKinds), found->value()) != std::end(kShardKinds);
      throw InputError(path + ": not a " + kind.noun + " (" +
                       (other ? "a " + found->value().substr(9) + "; merge the kinds apart" : kind.writer + std::string(" writes them")) +
                       ")");
    }
    const ShardAttributes attributes(header, path, kind);
    ShardHeader shard;
    shard.first = attributes.count("first");
    shard.end = attributes.count("end");
    shard.total = attributes.count(kind.items);
    shard.seed = attributes.count("seed");
    shard.index = attributes.count("index");
    shard.count = attributes.count("count");
    shard.scene_name = attributes.text("scene");
    shard.scene_identity = attributes.text("scene_identity");
    shard.engine_identity = attributes.text("engine");
    if (shard.first >= shard.end || shard.end > shard.total || shard.count == 0 || shard.index >= shard.count) {
      attributes.damaged("its range does not hold together");
    }
    rest(file, attributes);
    return shard;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": cannot read the " + kind.noun + ": " + e.what());
  }
}

void decode_on_every_core() {
  const int cores = static_cast<int>(std::thread::hardware_concurrency());
  if (cores > 1 && Imf::globalThreadCount() < cores) Imf::setGlobalThreadCount(cores);
}

std::string shard_file_kind(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) || !Imf::isOpenExrFile(path.c_str())) return "";
  try {
    const Imf::InputFile file(path.c_str());
    const auto* kind = file.header().findTypedAttribute<Imf::StringAttribute>("caustica.kind");
    return kind ? kind->value() : "";
  } catch (const std::exception&) {
    return "";
  }
}

std::vector<size_t> check_shards(const ShardKind& kind, const std::vector<std::string>& paths,
                                 const std::vector<const ShardHeader*>& headers,
                                 const std::function<std::vector<std::pair<std::string, std::string>>(size_t k)>& identity) {
  std::vector<size_t> order(headers.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    return std::pair(headers[a]->first, headers[a]->end) < std::pair(headers[b]->first, headers[b]->end);
  });

  // Everything that makes shards parts of one whole, against the first by range.
  std::vector<std::string> problems;
  const ShardHeader& base = *headers[order.front()];
  const std::string& base_path = paths[order.front()];
  const auto base_identity = identity(order.front());
  for (const size_t k : order) {
    const ShardHeader& s = *headers[k];
    auto differs = [&](const std::string& what, const std::string& value, const std::string& base_value) {
      if (value != base_value) problems.push_back(paths[k] + ": " + what + " " + value + ", where " + base_path + " has " + base_value);
    };
    differs("scene", s.scene_name + " (identity " + s.scene_identity + ")", base.scene_name + " (identity " + base.scene_identity + ")");
    differs("seed", std::to_string(s.seed), std::to_string(base.seed));
    differs(kind.total, std::to_string(s.total), std::to_string(base.total));
    const auto own = identity(k);
    for (size_t i = 0; i < own.size() && i < base_identity.size(); ++i) differs(own[i].first, own[i].second, base_identity[i].second);
    differs("engine", s.engine_identity, base.engine_identity);
  }
  if (problems.empty()) {
    // The ranges, in order, must tile [0, total): name each gap (with the shard indices that do
    // it, where every shard was cut alike), overlap and duplicate.
    const bool one_sharding = std::all_of(headers.begin(), headers.end(), [&](const ShardHeader* s) { return s->count == base.count; });
    auto missing = [&](uint64_t first, uint64_t end) {
      std::string text = range_text(kind, first, end) + " are missing";
      if (one_sharding) text += ": shard " + indices_doing(first, end, base.total, base.count) + " of " + std::to_string(base.count);
      problems.push_back(text);
    };
    uint64_t covered = 0;
    size_t reaching = order.front();  // the shard that reaches `covered`
    for (size_t n = 0; n < order.size(); ++n) {
      const size_t k = order[n];
      const ShardHeader& s = *headers[k];
      const ShardHeader& before = *headers[order[n > 0 ? n - 1 : 0]];
      if (n > 0 && s.first == before.first && s.end == before.end) {
        const std::string& other = paths[order[n - 1]];
        problems.push_back(other == paths[k]
                               ? paths[k] + " is given twice"
                               : paths[k] + " and " + other + " are the same shard (" + range_text(kind, s.first, s.end) + ")");
        continue;
      }
      if (s.first < covered)
        problems.push_back(part_text(kind, paths[k], s) + " overlaps " + part_text(kind, paths[reaching], *headers[reaching]));
      if (s.first > covered) missing(covered, s.first);
      if (s.end > covered) {
        covered = s.end;
        reaching = k;
      }
    }
    if (covered < base.total) missing(covered, base.total);
  }
  if (!problems.empty()) {
    std::string text = std::string("cannot merge the ") + kind.noun + "s:";
    for (const auto& p : problems) text += "\n  " + p;
    throw InputError(text);
  }
  return order;
}

}  // namespace caustica::reference
