#pragma once
// What the references' shard files have in common (photon_shard.h: photons of the caustic map;
// camera_shard.h: rows of the ray-traced camera image; docs/cluster.md): shard I of K did a
// contiguous range of the work's items, and its EXR says in its header what it is a part of (the
// range, the seed, the scene's and the engine's identity); it is written under a temporary name
// and renamed, so a shard killed while writing leaves no file; and a merge checks that the shards
// are parts of one whole and tile its items exactly, naming every problem.
#include <OpenEXR/ImfForward.h>  // the OpenEXR types by name only: the command line includes this header without OpenEXR's paths

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"

namespace caustica::reference {

// What every shard's header says about it.
struct ShardHeader {
  uint64_t first = 0, end = 0;  // the items done, [first, end)
  uint64_t total = 0;           // of all the shards together: photons, image rows
  uint64_t seed = 1;
  uint64_t index = 0, count = 1;  // --shard index/count that did them
  std::string scene_name;
  std::string scene_identity;   // a hash of what the items met in the loaded scene
  std::string engine_identity;  // the build that did them
};

// A kind of shard: its header's caustica.kind and the words its messages use.
struct ShardKind {
  const char* kind;    // "caustica photon shard"
  const char* noun;    // "photon shard"
  const char* items;   // "photons"
  const char* total;   // "photon count": what `total` is called where two shards' differ
  const char* makes;   // "the map": what merge makes of them
  const char* writer;  // "caustica reference --photons N --shard I/K"
};

// Shard `index` of `count` of `total` items: contiguous, together exactly [0, total), sizes
// differing by at most one.
std::pair<uint64_t, uint64_t> shard_range(uint64_t total, uint64_t index, uint64_t count);

// "photons 0 to 999", "rows 36 to 71".
std::string range_text(const ShardKind& kind, uint64_t first, uint64_t end);

// A 64-bit count as a decimal string attribute caustica.NAME (EXR has no 64-bit integer attribute).
void set_shard_count(Imf::Header& header, const std::string& name, uint64_t value);
// caustica.kind and every ShardHeader field, into a header.
void write_shard_header(Imf::Header& header, const ShardKind& kind, const ShardHeader& shard);
// Writes the header's data window of `frame` to `path` through a temporary file and a rename.
void write_shard_file(const std::string& path, const Imf::Header& header, const Imf::FrameBuffer& frame);

// A shard file's caustica.* attributes, each read with a clear message where it is missing or
// not what it should be.
class ShardAttributes {
 public:
  ShardAttributes(const Imf::Header& header, const std::string& path, const ShardKind& kind) : header_(header), path_(path), kind_(kind) {}
  uint64_t count(const std::string& name) const;
  const std::string& text(const std::string& name) const;
  double number(const std::string& name) const;
  int integer(const std::string& name) const;
  // InputError: "PATH: a damaged photon shard (WHAT)".
  [[noreturn]] void damaged(const std::string& what) const;

 private:
  template <typename Attribute>
  const Attribute& find(const std::string& name) const;
  const Imf::Header& header_;
  const std::string& path_;
  const ShardKind& kind_;
};

// Opens a shard of `kind` and reads its ShardHeader; then `rest` reads what is the kind's own
// (attributes, pixels). Throws InputError when the file is missing, not an EXR, not a shard of
// this kind (naming the kind it is, where it is another shard), damaged or unreadable.
ShardHeader read_shard_file(const std::string& path, const ShardKind& kind,
                            const std::function<void(Imf::InputFile& file, const ShardAttributes& attributes)>& rest);

// The caustica.kind in an EXR's header ("caustica photon shard", "caustica camera shard"), or ""
// where the file is not a shard or cannot be read (reading it as a shard then says why).
std::string shard_file_kind(const std::string& path);

// Checks that shards (headers[k] read from paths[k]) make one whole: the same scene, seed, total
// and engine, and the same `identity(k)` (the kind's own settings, as (what, value) pairs), and
// ranges that tile [0, total) exactly. Returns the shards' indices in the order of their ranges;
// throws InputError naming every problem: a missing range with the shard indices that do it, an
// overlap, a duplicate, a file given twice, a shard of another run.
std::vector<size_t> check_shards(const ShardKind& kind, const std::vector<std::string>& paths,
                                 const std::vector<const ShardHeader*>& headers,
                                 const std::function<std::vector<std::pair<std::string, std::string>>(size_t k)>& identity);

// Lets OpenEXR decode a file's blocks on every core (its global thread pool): a merge reads one
// file at a time, and zlib's inflate and OpenEXR's unpacking are most of its time.
void decode_on_every_core();

// Reads every shard's header with `read` (a path -> a Shard, derived from ShardHeader) and checks
// them with check_shards, `identity(shard)` giving the kind's own settings; returns the shards
// with their paths in the order of their ranges.
template <typename Shard, typename Read, typename Identity>
std::vector<std::pair<Shard, std::string>> read_checked_shards(const ShardKind& kind, const std::vector<std::string>& paths, Read read,
                                                               Identity identity) {
  if (paths.empty()) throw InputError(std::string("merge needs at least one ") + kind.noun);
  decode_on_every_core();
  std::vector<Shard> shards;
  for (const auto& path : paths) shards.push_back(read(path));
  std::vector<const ShardHeader*> headers;
  for (const auto& shard : shards) headers.push_back(&shard);
  std::vector<std::pair<Shard, std::string>> ordered;
  for (const size_t k : check_shards(kind, paths, headers, [&](size_t n) { return identity(shards[n]); }))
    ordered.emplace_back(std::move(shards[k]), paths[k]);
  return ordered;
}

}  // namespace caustica::reference
