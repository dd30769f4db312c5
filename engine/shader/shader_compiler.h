#pragma once
// GLSL -> SPIR-V through the glslang library at load time. #include resolves relative to the
// including file, then the shader root. The cache key is the stage, the defines and the text of the
// file and of everything it includes, so an edited include recompiles and an unchanged file does not.
#include <cstdint>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <vector>

namespace caustica::shader {

using Defines = std::map<std::string, std::string>;

struct CompileStats {
  uint64_t compiles = 0;
  uint64_t cache_hits = 0;
};

class ShaderCompiler {
 public:
  explicit ShaderCompiler(std::filesystem::path root);

  // `path` is relative to the root (e.g. "core/box_blur.comp"); the stage comes from the extension
  // (.vert .frag .comp .geom). Throws InputError with "file:line: message" lines from glslang.
  std::vector<uint32_t> compile(const std::string& path, const Defines& defines = {});

  const std::filesystem::path& root() const { return root_; }
  CompileStats stats() const;

 private:
  struct Entry {
    std::vector<std::pair<std::filesystem::path, std::string>> sources;  // every file read, with its text
    std::vector<uint32_t> spirv;
  };
  std::filesystem::path root_;
  std::map<std::string, Entry> cache_;  // by path + defines
  mutable std::mutex mutex_;
  CompileStats stats_;
};

}  // namespace caustica::shader
