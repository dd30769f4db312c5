#include "shader/shader_disk_cache.h"

#include <elf.h>
#include <link.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>

#include "core/content_hash.h"
#include "core/error.h"
#include "io/files.h"
#include "io/json_document.h"

namespace caustica::shader {

NLOHMANN_JSON_SERIALIZE_ENUM(BindingKind, {{BindingKind::sampled_image, "sampled_image"},
                                           {BindingKind::storage_image, "storage_image"},
                                           {BindingKind::storage_buffer, "storage_buffer"},
                                           {BindingKind::uniform_buffer, "uniform_buffer"},
                                           {BindingKind::acceleration_structure, "acceleration_structure"},
                                           {BindingKind::other, "other"}})
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(SourcePlace, file, line)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ReflectedMember, name, type, place, offset)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ReflectedBinding, name, block, members, size, set, binding, kind, format, arrayed, count, readonly,
                                   writeonly, place)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(ReflectedInput, name, type, location, place)
NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(Reflection, bindings, outputs, inputs, push_block, push_place, push_members, push_size, local_size)

namespace {

// The first line of an entry: a file in another format (an older one, or not an entry) is a miss.
constexpr std::string_view kMagic = "caustica shader cache 1\n";
// Builds' folders are removed when unused this long, and beyond this many the least recently used
// go: a test suite runs a score of programs, each a build of its own, side by side.
constexpr auto kUnusedFor = std::chrono::hours(24 * 7);
constexpr size_t kMaxBuilds = 32;
constexpr size_t kMaxFileBytes = 4u << 20;

// An entry's fields in order, each prefixed by its length: the key, the sources (path, text), the
// reflection as JSON, the SPIR-V words.
class Writer {
 public:
  Writer() : out_(kMagic) {}
  void text(const std::string& value) {
    number(value.size());
    out_ += value;
  }
  void number(uint64_t value) { out_.append(reinterpret_cast<const char*>(&value), sizeof value); }
  void words(const std::vector<uint32_t>& values) {
    number(values.size());
    out_.append(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(uint32_t));
  }
  const std::string& bytes() const { return out_; }

 private:
  std::string out_;
};

// Reads what Writer wrote; any field that runs past the end makes the entry a miss.
class Reader {
 public:
  explicit Reader(std::string bytes) : in_(std::move(bytes)) {
    ok_ = in_.starts_with(kMagic);
    at_ = kMagic.size();
  }
  bool ok() const { return ok_; }
  uint64_t number() {
    uint64_t value = 0;
    if (!take(sizeof value)) return 0;
    std::memcpy(&value, in_.data() + at_ - sizeof value, sizeof value);
    return value;
  }
  std::string text() {
    const uint64_t size = number();
    if (!take(size)) return {};
    return in_.substr(at_ - size, size);
  }
  std::vector<uint32_t> words() {
    const uint64_t count = number();
    if (count > in_.size() / sizeof(uint32_t) || !take(count * sizeof(uint32_t))) return {};
    std::vector<uint32_t> out(count);
    std::memcpy(out.data(), in_.data() + at_ - count * sizeof(uint32_t), count * sizeof(uint32_t));
    return out;
  }

 private:
  bool take(uint64_t size) {
    if (!ok_ || size > in_.size() - at_) return ok_ = false;
    at_ += size;
    return true;
  }
  std::string in_;
  size_t at_ = 0;
  bool ok_ = false;
};

// The file's bytes; none where it cannot be read (a miss, never an error).
std::optional<std::string> read_file(const std::filesystem::path& path) {
  try {
    return read_text_file(path.string(), kMaxFileBytes);
  } catch (const InputError&) {
    return std::nullopt;
  }
}

bool is_build_folder(const std::filesystem::directory_entry& entry) {
  const std::string name = entry.path().filename().string();
  return entry.is_directory() && name.size() >= 16 && std::all_of(name.begin(), name.end(), [](char c) { return std::isxdigit(c); });
}

// Removes the folders of builds unused for kUnusedFor, and beyond kMaxBuilds the least recently
// used (a folder's time is its last use), `kept` aside.
void remove_old_builds(const std::filesystem::path& root, const std::filesystem::path& kept) {
  std::error_code ec;
  std::vector<std::pair<std::filesystem::file_time_type, std::filesystem::path>> others;
  for (const auto& entry : std::filesystem::directory_iterator(root, ec))
    if (entry.path() != kept && is_build_folder(entry)) others.emplace_back(entry.last_write_time(ec), entry.path());
  std::sort(others.rbegin(), others.rend());
  const auto stale = std::filesystem::file_time_type::clock::now() - kUnusedFor;
  for (size_t i = 0; i < others.size(); ++i)
    if (i + 1 >= kMaxBuilds || others[i].first < stale) std::filesystem::remove_all(others[i].second, ec);
}

}  // namespace

std::optional<std::filesystem::path> ShaderDiskCache::default_folder() {
  if (const char* dir = std::getenv("CAUSTICA_SHADER_CACHE_DIR"); dir && *dir) {
    if (std::string_view(dir) == "off") return std::nullopt;
    return std::filesystem::path(dir);
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::filesystem::path(xdg) / "caustica" / "shaders";
  if (const char* home = std::getenv("HOME"); home && *home) return std::filesystem::path(home) / ".cache" / "caustica" / "shaders";
  return std::nullopt;
}

std::string ShaderDiskCache::build_id() {
  std::string id;
  // The first object dl_iterate_phdr reports is the program itself.
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* out) {
        for (int i = 0; i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& header = info->dlpi_phdr[i];
          if (header.p_type != PT_NOTE) continue;
          const auto* at = reinterpret_cast<const unsigned char*>(info->dlpi_addr + header.p_vaddr);
          const unsigned char* end = at + header.p_memsz;
          while (at + sizeof(ElfW(Nhdr)) <= end) {
            const auto* note = reinterpret_cast<const ElfW(Nhdr)*>(at);
            const unsigned char* name = at + sizeof(ElfW(Nhdr));
            const unsigned char* desc = name + ((note->n_namesz + 3) & ~3u);
            if (note->n_type == NT_GNU_BUILD_ID && note->n_namesz == 4 && std::memcmp(name, "GNU", 4) == 0 &&
                desc + note->n_descsz <= end) {
              static const char* hex = "0123456789abcdef";
              auto& hex_id = *static_cast<std::string*>(out);
              for (uint32_t b = 0; b < note->n_descsz; ++b) hex_id += {hex[desc[b] >> 4], hex[desc[b] & 15]};
              return 1;
            }
            at = desc + ((note->n_descsz + 3) & ~3u);
          }
        }
        return 1;
      },
      &id);
  return id;
}

ShaderDiskCache::ShaderDiskCache(const std::filesystem::path& folder, const std::string& build_id) {
  if (build_id.empty()) return;
  std::error_code ec;
  const std::filesystem::path mine = folder / build_id;
  if (std::filesystem::exists(mine, ec)) {
    std::filesystem::last_write_time(mine, std::filesystem::file_time_type::clock::now(), ec);  // in use
  } else {
    if (!std::filesystem::create_directories(mine, ec) && !std::filesystem::is_directory(mine, ec)) return;
    remove_old_builds(folder, mine);
  }
  folder_ = mine;
}

std::filesystem::path ShaderDiskCache::entry_path(const std::string& key) const {
  ContentHash hash;
  hash.bytes(key.data(), key.size());
  char name[32];
  std::snprintf(name, sizeof name, "%016llx.spv", static_cast<unsigned long long>(hash.value()));
  return folder_ / name;
}

std::optional<CompiledShader> ShaderDiskCache::load(const std::string& key) const {
  if (folder_.empty()) return std::nullopt;
  std::optional<std::string> bytes = read_file(entry_path(key));
  if (!bytes) return std::nullopt;
  Reader in(std::move(*bytes));
  if (in.text() != key) return std::nullopt;  // another key with the same hash, or not an entry
  CompiledShader out;
  for (uint64_t i = 0, count = in.number(); in.ok() && i < count; ++i) {
    std::filesystem::path file = in.text();
    out.sources.emplace_back(std::move(file), in.text());
  }
  const std::string reflection = in.text();
  out.spirv = in.words();
  if (!in.ok() || out.spirv.empty()) return std::nullopt;
  try {
    out.reflection = nlohmann::json::parse(reflection).get<Reflection>();
  } catch (const nlohmann::json::exception&) {
    return std::nullopt;
  }
  return out;
}

void ShaderDiskCache::store(const std::string& key, const CompiledShader& shader) const {
  if (folder_.empty()) return;
  Writer out;
  out.text(key);
  out.number(shader.sources.size());
  for (const auto& [file, text] : shader.sources) {
    out.text(file.string());
    out.text(text);
  }
  out.text(nlohmann::json(shader.reflection).dump());
  out.words(shader.spirv);
  try {
    io::write_text_atomically(entry_path(key).string(), out.bytes());
  } catch (const std::exception&) {
    // A cache that cannot be written is only slower.
  }
}

}  // namespace caustica::shader
