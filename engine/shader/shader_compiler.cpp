#include "shader/shader_compiler.h"

#include <glslang/MachineIndependent/localintermediate.h>
#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <cctype>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "core/paths.h"
#include "io/json_document.h"
#include "shader/shader_disk_cache.h"

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

// glslang's log as one message a line, each naming its file and line once: without the "ERROR: "
// before each, and without the lines that only say that compiling stopped.
std::string log_messages(const std::string& log) {
  std::string out;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    if (line.starts_with("ERROR: ")) line.erase(0, 7);
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (line.empty() || line.ends_with("'' : compilation terminated") || line.ends_with("No code generated.")) continue;
    out += (out.empty() ? "" : "\n") + line;
  }
  return out;
}

// Whether every file a compile read still has the text it had.
bool unchanged(const std::vector<std::pair<std::filesystem::path, std::string>>& sources) {
  for (const auto& [file, text] : sources) {
    std::error_code ec;
    if (!std::filesystem::exists(file, ec) || read_text_file(file.string(), kMaxShaderBytes) != text) return false;
  }
  return true;
}

std::string preamble(const Defines& defines) {
  // Every shader may keep a loop rolled ([[dont_unroll]]): the library's image-space searches do
  // (refraction/refraction.glsl), and a user pass that includes them needs the extension too.
  std::string text = "#extension GL_EXT_control_flow_attributes : enable\n";
  for (const auto& [name, value] : defines) text += "#define " + name + " " + value + "\n";
  return text;
}

SourcePlace place_of(const glslang::TSourceLoc& loc, const std::string& main_file) {
  const char* file = loc.getFilename();
  return {file ? file : main_file, loc.line};
}

// A type as GLSL writes it ("float", "vec2", "uvec4", "mat4x3", "float[]"), for messages.
std::string glsl_type_name(const glslang::TType& type) {
  std::string name = type.getBasicType() == glslang::EbtStruct ? type.getTypeName().c_str() : type.getBasicTypeString().c_str();
  if (type.isVector()) {
    const std::string prefix = name == "float"    ? ""
                               : name == "int"    ? "i"
                               : name == "uint"   ? "u"
                               : name == "bool"   ? "b"
                               : name == "double" ? "d"
                                                  : "?";
    name = prefix + "vec" + std::to_string(type.getVectorSize());
  } else if (type.isMatrix()) {
    name = "mat" + std::to_string(type.getMatrixCols()) + "x" + std::to_string(type.getMatrixRows());
  }
  return type.isArray() ? name + "[]" : name;
}

bool has_word(const std::string& line, const std::string& word) {
  for (size_t at = line.find(word); at != std::string::npos; at = line.find(word, at + 1)) {
    auto identifier = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
    const bool starts = at == 0 || !identifier(line[at - 1]);
    const bool ends = at + word.size() == line.size() || !identifier(line[at + word.size()]);
    if (starts && ends) return true;
  }
  return false;
}

// Where a global is declared: glslang's linker objects carry no line, so the first line of the
// files read (the shader, then its includes) that declares `name` with one of `keywords`.
SourcePlace declaration_place(const std::vector<std::pair<std::filesystem::path, std::string>>& sources, const std::string& name,
                              std::initializer_list<const char*> keywords) {
  for (const auto& [file, text] : sources) {
    std::istringstream lines(text);
    int number = 0;
    for (std::string line; std::getline(lines, line);) {
      ++number;
      if (!has_word(line, name)) continue;
      for (const char* keyword : keywords) {
        if (has_word(line, keyword)) return {file.string(), number};
      }
    }
  }
  return {sources.front().first.string(), 0};
}

// The globals of the linked program (its linker objects: every uniform, buffer and output it
// declares, used or not), as a user pass's declarations are checked against them.
Reflection reflect(const glslang::TIntermediate& intermediate, const std::vector<std::pair<std::filesystem::path, std::string>>& sources) {
  const std::string main_file = sources.front().first.string();
  Reflection out;
  for (int d = 0; d < 3; ++d) out.local_size[static_cast<size_t>(d)] = intermediate.getLocalSize(d);
  glslang::TIntermAggregate* root = intermediate.getTreeRoot() ? intermediate.getTreeRoot()->getAsAggregate() : nullptr;
  if (!root || root->getSequence().empty()) return out;
  glslang::TIntermAggregate* linker = root->getSequence().back()->getAsAggregate();
  if (!linker || linker->getOp() != glslang::EOpLinkerObjects) return out;
  for (TIntermNode* node : linker->getSequence()) {
    const glslang::TIntermSymbol* symbol = node->getAsSymbolNode();
    if (!symbol) continue;
    const glslang::TType& type = symbol->getType();
    const glslang::TQualifier& q = type.getQualifier();
    if (q.builtIn != glslang::EbvNone) continue;
    if (q.storage == glslang::EvqVaryingIn) {
      const std::string name = symbol->getName().c_str();
      out.inputs.push_back({name, glsl_type_name(type), q.hasLocation() ? q.layoutLocation : 0u, declaration_place(sources, name, {"in"})});
      continue;
    }
    ReflectedBinding b;
    b.name = symbol->getName().c_str();
    if (type.getBasicType() == glslang::EbtBlock) {
      b.block = type.getTypeName().c_str();
      if (b.name.starts_with("anon@")) b.name = b.block;
    }
    b.place = declaration_place(sources, b.block.empty() ? b.name : b.block, {"uniform", "buffer", "out"});
    if (q.storage == glslang::EvqVaryingOut) {
      b.binding = q.hasLocation() ? q.layoutLocation : 0;
      out.outputs.push_back(std::move(b));
      continue;
    }
    if (type.getBasicType() == glslang::EbtBlock) {
      // Laid out by glslang's rules for the block's packing, from an explicit offset where the
      // shader gives one (TIntermediate::getOffset would place the members after it as if it had none).
      int offset = 0, size = 0;
      for (const glslang::TTypeLoc& member : *type.getStruct()) {
        if (member.type->getQualifier().hasOffset())
          offset = member.type->getQualifier().layoutOffset;
        else
          offset += size;
        glslang::TIntermediate::updateOffset(type, *member.type, offset, size);
        b.members.push_back({member.type->getFieldName().c_str(), glsl_type_name(*member.type), place_of(member.loc, main_file),
                             static_cast<uint32_t>(offset)});
      }
      // A block ending in a runtime array (a storage buffer's) has no size of its own.
      if (!type.getStruct()->empty() && !type.getStruct()->back().type->isUnsizedArray()) b.size = static_cast<uint32_t>(offset + size);
    }
    if (q.storage == glslang::EvqUniform && q.layoutPushConstant) {
      out.push_block = b.block;
      out.push_place = b.place;
      out.push_members = std::move(b.members);
      out.push_size = b.size;
      continue;
    }
    if (q.storage != glslang::EvqUniform && q.storage != glslang::EvqBuffer) continue;
    b.set = q.hasSet() ? q.layoutSet : 0;
    b.binding = q.hasBinding() ? q.layoutBinding : 0;
    b.readonly = q.readonly;
    b.writeonly = q.writeonly;
    if (type.isSizedArray()) b.count = static_cast<uint32_t>(type.getOuterArraySize());
    if (type.getBasicType() == glslang::EbtSampler) {
      const glslang::TSampler& sampler = type.getSampler();
      b.arrayed = sampler.isArrayed();
      if (sampler.isImage()) {
        b.kind = BindingKind::storage_image;
        if (q.hasFormat()) b.format = glslang::TQualifier::getLayoutFormatString(q.layoutFormat);
      } else if (sampler.isCombined()) {
        b.kind = BindingKind::sampled_image;
      }
    } else if (type.getBasicType() == glslang::EbtAccStruct) {
      b.kind = BindingKind::acceleration_structure;
    } else if (type.getBasicType() == glslang::EbtBlock) {
      b.kind = q.storage == glslang::EvqBuffer ? BindingKind::storage_buffer : BindingKind::uniform_buffer;
    }
    out.bindings.push_back(std::move(b));
  }
  return out;
}

}  // namespace

ShaderCompiler& process_shader_compiler() {
  static ShaderCompiler compiler = [] {
    const auto folder = ShaderDiskCache::default_folder();
    if (!folder) return ShaderCompiler(data_dir() / "shaders");
    return ShaderCompiler(data_dir() / "shaders", std::make_unique<ShaderDiskCache>(*folder, ShaderDiskCache::build_id()));
  }();
  return compiler;
}

ShaderCompiler::ShaderCompiler(std::filesystem::path root) : ShaderCompiler(std::move(root), nullptr) {}

ShaderCompiler::ShaderCompiler(std::filesystem::path root, std::unique_ptr<ShaderDiskCache> disk)
    : root_(std::move(root)), disk_(std::move(disk)) {
  initialize_glslang();
}

ShaderCompiler::~ShaderCompiler() = default;

ReflectedShader ShaderCompiler::compiled(const CompiledShader& entry) {
  ReflectedShader out{entry.spirv, entry.reflection, {}, {}};
  for (const auto& [file, source] : entry.sources) {
    out.sources += file.string() + "\n" + source + "\n";
    out.files.push_back(file);
  }
  if (file_log_) file_log_->insert(file_log_->end(), out.files.begin(), out.files.end());
  return out;
}

void ShaderCompiler::log_files_to(std::vector<std::filesystem::path>* files) {
  std::lock_guard lock(mutex_);
  file_log_ = files;
}

CompileStats ShaderCompiler::stats() const {
  std::lock_guard lock(mutex_);
  return stats_;
}

std::vector<uint32_t> ShaderCompiler::compile(const std::string& relative, const Defines& defines) {
  return compile_reflected(relative, defines).spirv;
}

ReflectedShader ShaderCompiler::compile_reflected(const std::string& relative, const Defines& defines) {
  std::lock_guard lock(mutex_);
  const std::filesystem::path path = root_ / relative;
  const std::string key = relative + "\n" + preamble(defines);
  if (auto it = cache_.find(key); it != cache_.end() && unchanged(it->second.sources)) {
    ++stats_.cache_hits;
    return compiled(it->second);
  }
  // On disk by the absolute path: another process may resolve the same relative path elsewhere.
  const std::string disk_key = path.string() + "\n" + preamble(defines);
  if (disk_) {
    if (std::optional<CompiledShader> stored = disk_->load(disk_key); stored && unchanged(stored->sources)) {
      ++stats_.disk_hits;
      return compiled(cache_[key] = std::move(*stored));
    }
  }
  CompiledShader entry = compile_now(path, defines);
  ++stats_.compiles;
  if (disk_) disk_->store(disk_key, entry);
  return compiled(cache_[key] = std::move(entry));
}

CompiledShader ShaderCompiler::compile_now(const std::filesystem::path& path, const Defines& defines) const {
  CompiledShader entry;
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
    // Each message names the file and line it is about (an #include's own).
    const std::string log = log_messages(shader.getInfoLog());
    throw InputError(log.empty() ? name + ": does not compile" : log);
  }
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages)) throw InputError(name + ": does not link: " + log_messages(program.getInfoLog()));
  glslang::SpvOptions options;
  options.disableOptimizer = false;
  options.validate = true;
  glslang::GlslangToSpv(*program.getIntermediate(stage), entry.spirv, &options);
  entry.reflection = reflect(*program.getIntermediate(stage), entry.sources);
  return entry;
}

}  // namespace caustica::shader
