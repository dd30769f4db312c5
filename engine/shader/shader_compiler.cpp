#include "shader/shader_compiler.h"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <memory>

#include "core/error.h"
#include "io/json_document.h"

namespace caustica::shader {
namespace {

constexpr size_t kMaxShaderBytes = 4u << 20;

EShLanguage stage_of(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  if (ext == ".vert") return EShLangVertex;
  if (ext == ".frag") return EShLangFragment;
  if (ext == ".comp") return EShLangCompute;
  if (ext == ".geom") return EShLangGeometry;
  throw InputError(path.string() + ": unknown shader stage for extension '" + ext + "' (use .vert .frag .comp .geom)");
}

void initialize_glslang() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

// Resolves includes and records every file it reads, so the cache can tell when one changed.
class Includer : public glslang::TShader::Includer {
 public:
  Includer(std::filesystem::path root, std::vector<std::pair<std::filesystem::path, std::string>>& sources)
      : root_(std::move(root)), sources_(sources) {}

  IncludeResult* includeLocal(const char* header, const char* includer, size_t) override {
    std::filesystem::path relative = std::filesystem::path(includer).parent_path() / header;
    if (std::filesystem::exists(relative)) return load(relative);
    return includeSystem(header, includer, 0);
  }

  IncludeResult* includeSystem(const char* header, const char*, size_t) override {
    std::filesystem::path path = root_ / header;
    if (!std::filesystem::exists(path)) return nullptr;  // glslang reports the failed #include
    return load(path);
  }

  void releaseInclude(IncludeResult* result) override {
    if (result) {
      delete static_cast<std::string*>(result->userData);
      delete result;
    }
  }

 private:
  IncludeResult* load(const std::filesystem::path& path) {
    auto* text = new std::string(read_text_file(path.string(), kMaxShaderBytes));
    sources_.emplace_back(path, *text);
    return new IncludeResult(path.string(), text->data(), text->size(), text);
  }
  std::filesystem::path root_;
  std::vector<std::pair<std::filesystem::path, std::string>>& sources_;
};

std::string preamble(const Defines& defines) {
  std::string text;
  for (const auto& [name, value] : defines) text += "#define " + name + " " + value + "\n";
  return text;
}

}  // namespace

ShaderCompiler::ShaderCompiler(std::filesystem::path root) : root_(std::move(root)) { initialize_glslang(); }

CompileStats ShaderCompiler::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::vector<uint32_t> ShaderCompiler::compile(const std::string& relative, const Defines& defines) {
  std::lock_guard lock(mutex_);
  const std::filesystem::path path = root_ / relative;
  const std::string key = relative + "\n" + preamble(defines);
  if (auto it = cache_.find(key); it != cache_.end()) {
    bool unchanged = true;
    for (const auto& [file, text] : it->second.sources) {
      std::error_code ec;
      unchanged = unchanged && std::filesystem::exists(file, ec) && read_text_file(file.string(), kMaxShaderBytes) == text;
    }
    if (unchanged) {
      ++stats_.cache_hits;
      return it->second.spirv;
    }
  }

  Entry entry;
  const EShLanguage stage = stage_of(path);
  std::string source = read_text_file(path.string(), kMaxShaderBytes);
  entry.sources.emplace_back(path, source);
  std::string defines_text = preamble(defines);
  const std::string name = path.string();
  glslang::TShader shader(stage);
  const char* strings[] = {source.c_str()};
  const char* names[] = {name.c_str()};
  shader.setStringsWithLengthsAndNames(strings, nullptr, names, 1);
  shader.setPreamble(defines_text.c_str());
  shader.setEnvInput(glslang::EShSourceGlsl, stage, glslang::EShClientVulkan, 100);
  shader.setEnvClient(glslang::EShClientVulkan, glslang::EShTargetVulkan_1_3);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_6);
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules | EShMsgVulkanRules);
  Includer includer(root_, entry.sources);
  if (!shader.parse(GetDefaultResources(), 460, false, messages, includer)) {
    throw InputError("shader compile failed: " + name + "\n" + shader.getInfoLog());
  }
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages)) throw InputError("shader link failed: " + name + "\n" + program.getInfoLog());
  glslang::SpvOptions options;
  options.disableOptimizer = false;
  options.validate = true;
  glslang::GlslangToSpv(*program.getIntermediate(stage), entry.spirv, &options);
  ++stats_.compiles;
  auto& stored = cache_[key] = std::move(entry);
  return stored.spirv;
}

}  // namespace caustica::shader
