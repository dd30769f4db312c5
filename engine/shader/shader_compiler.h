#pragma once
// GLSL -> SPIR-V through the glslang library at load time. #include resolves relative to the
// including file, then the shader root. The cache key is the stage, the defines and the text of the
// file and of everything it includes, so an edited include recompiles and an unchanged file does not.
#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace caustica::shader {

using Defines = std::map<std::string, std::string>;

// What a shader declares, from glslang's linked program: the descriptor bindings, the push-constant
// block's members, each block's layout and the fragment outputs, each with the file and line that declares it (an
// included file's own), so that a graph's user pass can be checked against it without a device.
enum class BindingKind { sampled_image, storage_image, storage_buffer, uniform_buffer, acceleration_structure, other };
struct SourcePlace {
  std::string file;
  int line = 0;
  bool operator==(const SourcePlace&) const = default;
};
struct ReflectedMember {
  std::string name;
  std::string type;  // GLSL's name of it: "float", "int", "uint", "bool", "vec2", "uint[]"...
  SourcePlace place;
  uint32_t offset = 0;  // in the block, by its layout (std140, std430, or an explicit offset)
  bool operator==(const ReflectedMember&) const = default;
};
struct ReflectedBinding {
  std::string name;                      // the variable, or a block's instance name (its type name where it has none)
  std::string block;                     // a block's type name
  std::vector<ReflectedMember> members;  // a block's
  uint32_t size = 0;                     // a block's, in bytes
  uint32_t set = 0;
  uint32_t binding = 0;  // a fragment output: its location
  BindingKind kind = BindingKind::other;
  std::string format;  // a storage image's format qualifier ("r32f"), else empty
  bool arrayed = false;
  uint32_t count = 1;  // descriptors: an array's size (uniform sampler2DArray shadow_maps[8])
  bool readonly = false;
  bool writeonly = false;
  SourcePlace place;
  bool operator==(const ReflectedBinding&) const = default;
};
// A shader's user input (a fragment shader's varying): what its stage before must give.
struct ReflectedInput {
  std::string name;
  std::string type;
  uint32_t location = 0;
  SourcePlace place;
  bool operator==(const ReflectedInput&) const = default;
};
struct Reflection {
  std::vector<ReflectedBinding> bindings;
  std::vector<ReflectedBinding> outputs;  // a fragment shader's user outputs
  std::vector<ReflectedInput> inputs;
  std::string push_block;  // empty where the shader has no push constants
  SourcePlace push_place;
  std::vector<ReflectedMember> push_members;
  uint32_t push_size = 0;
  std::array<uint32_t, 3> local_size{1, 1, 1};
  bool operator==(const Reflection&) const = default;
};
struct ReflectedShader {
  std::vector<uint32_t> spirv;
  Reflection reflection;
  // The text of the file and of everything it includes: what a result computed with it follows from.
  std::string sources;
  std::vector<std::filesystem::path> files;  // the file and everything it includes
};

// What a compile made, and from what: the cache's entry, in memory and on disk (ShaderDiskCache).
struct CompiledShader {
  std::vector<std::pair<std::filesystem::path, std::string>> sources;  // every file read, with its text
  std::vector<uint32_t> spirv;
  Reflection reflection;
};

struct CompileStats {
  uint64_t compiles = 0;    // by glslang
  uint64_t cache_hits = 0;  // in this compiler's memory
  uint64_t disk_hits = 0;   // from its disk cache
};

class ShaderDiskCache;

class ShaderCompiler {
 public:
  explicit ShaderCompiler(std::filesystem::path root);
  // Also keeping what it compiles in `disk` and looking there first (the process's compiler does).
  ShaderCompiler(std::filesystem::path root, std::unique_ptr<ShaderDiskCache> disk);
  ~ShaderCompiler();

  // `path` is relative to the root (e.g. "core/box_blur.comp"); the stage comes from the extension
  // (.vert .frag .comp .geom). Throws InputError with "file:line: message" lines from glslang.
  std::vector<uint32_t> compile(const std::string& path, const Defines& defines = {});
  // The same, with what the shader declares.
  ReflectedShader compile_reflected(const std::string& path, const Defines& defines = {});

  const std::filesystem::path& root() const { return root_; }
  CompileStats stats() const;
  // While set, every compile adds the files it read to `files`: how the executor learns which passes
  // a saved shader or include touches. nullptr stops it.
  void log_files_to(std::vector<std::filesystem::path>* files);

 private:
  ReflectedShader compiled(const CompiledShader& entry);
  CompiledShader compile_now(const std::filesystem::path& path, const Defines& defines) const;
  std::filesystem::path root_;
  std::map<std::string, CompiledShader> cache_;  // by path + defines
  std::unique_ptr<ShaderDiskCache> disk_;
  mutable std::mutex mutex_;
  CompileStats stats_;
  std::vector<std::filesystem::path>* file_log_ = nullptr;
};

// The process's one compiler of the engine's shader library (data_dir()/shaders), which user
// shaders #include too: every executor, user pass type and viewer in a process shares its cache,
// so a shader compiles once however many of them ask for it, and with the disk cache of
// ShaderDiskCache::default_folder(), once however many processes do.
ShaderCompiler& process_shader_compiler();

}  // namespace caustica::shader
