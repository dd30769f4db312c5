#pragma once
// Compiled shaders kept on disk between processes. Most of a short command's start is the GLSL
// front end (glslang took 0.3 s of a 1.2 s render of sphere_plane on lavapipe, 0.66 of 2.45 s in
// the sanitizer build; docs/testing.md), and every `caustica` process compiles the same library.
// Mesa keeps its own cache of what the driver makes from the SPIR-V; this one keeps the SPIR-V and
// its reflection.
//
// An entry is found by its key (the shader, the root it resolves includes from, the defines) and
// holds the text of every file the compile read: it is used only while each of those files still
// has that text, byte for byte, so an edited shader or include compiles again. Entries live in a
// folder per build of the running program (its GNU build ID), so that a program built from other
// code (another glslang, another reflection) never reads what this one wrote; a build's folder is
// removed when unused for a week or when 31 others were used since. A cache that cannot be read or
// written is a miss, never an error.
#include <filesystem>
#include <optional>
#include <string>

#include "shader/shader_compiler.h"

namespace caustica::shader {

class ShaderDiskCache {
 public:
  // Where the process keeps its entries: CAUSTICA_SHADER_CACHE_DIR, else $XDG_CACHE_HOME/caustica/shaders,
  // else ~/.cache/caustica/shaders; none where CAUSTICA_SHADER_CACHE_DIR is "off" or nothing names a folder.
  static std::optional<std::filesystem::path> default_folder();
  // The running program's GNU build ID in hex; empty where it has none (then nothing is cached).
  static std::string build_id();

  // Entries under folder/<build_id>; with an empty build_id, none.
  ShaderDiskCache(const std::filesystem::path& folder, const std::string& build_id);

  // The entry stored under `key` as it was stored: whether its sources still have their text is
  // the compiler's check, the same as for what it keeps in memory.
  std::optional<CompiledShader> load(const std::string& key) const;
  void store(const std::string& key, const CompiledShader& shader) const;
  const std::filesystem::path& folder() const { return folder_; }

 private:
  std::filesystem::path entry_path(const std::string& key) const;
  std::filesystem::path folder_;  // empty: caches nothing
};

}  // namespace caustica::shader
