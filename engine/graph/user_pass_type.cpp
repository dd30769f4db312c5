#include "graph/user_pass_type.h"

#include <algorithm>
#include <filesystem>
#include <mutex>

#include "core/paths.h"
#include "core/suggest.h"
#include "shader/shader_compiler.h"
#include "shader/shader_interface.h"

namespace caustica::graph {
namespace {

using shader::BindingKind;
using shader::ReflectedBinding;

std::string place(const shader::SourcePlace& at) {
  return at.file + ":" + std::to_string(at.line);
}

BindingKind binding_kind_of(const PortDecl& port) {
  if (port.kind == ResourceKind::buffer)
    return port.usage == PortUsage::uniform ? BindingKind::uniform_buffer : BindingKind::storage_buffer;
  return port.usage == PortUsage::sampled ? BindingKind::sampled_image : BindingKind::storage_image;
}

// The scene's bindings of set 0 (is_scene_binding): its blocks at 0..2 (shaders/scene/scene.glsl),
// its tracer's structure and triangles at 14 and 15 (scene/trace.glsl).
BindingKind scene_binding_kind(uint32_t binding) {
  return binding == 0                   ? BindingKind::uniform_buffer
         : binding == kSceneTlasBinding ? BindingKind::acceleration_structure
                                        : BindingKind::storage_buffer;
}

SceneResource scene_resource(uint32_t binding) {
  return binding == 0                   ? SceneResource::frame
         : binding == 1                 ? SceneResource::vertices
         : binding == 2                 ? SceneResource::objects
         : binding == kSceneTlasBinding ? SceneResource::acceleration_structure
                                        : SceneResource::triangles;
}

const char* scene_library_of(uint32_t binding) {
  return binding < kUserSceneBindings ? "shaders/scene/scene.glsl" : "shaders/scene/trace.glsl";
}

// What a port or counter buffer at one of the scene's bindings is told.
std::string taken_by_the_scene(uint32_t binding) {
  return "binding " + std::to_string(binding) + ", which the scene has (bindings 0 to " + std::to_string(kUserSceneBindings - 1) +
         ", and " + std::to_string(kSceneTlasBinding) + " and " + std::to_string(kSceneTrianglesBinding) +
         " for ray queries, with \"scene\": true)";
}

std::filesystem::path find_shader(const GraphDesc& graph, const PassDesc& pass, const std::string& pointer) {
  const std::string& name = pass.user->shader;
  std::error_code ec;
  const std::filesystem::path beside = std::filesystem::path(graph.doc.path()).parent_path() / name;
  if (std::filesystem::is_regular_file(beside, ec)) return std::filesystem::absolute(beside);
  const std::filesystem::path in_data = data_dir() / name;
  if (std::filesystem::is_regular_file(in_data, ec)) return std::filesystem::absolute(in_data);
  throw graph.error(pointer, "shader '" + name + "' of pass '" + pass.name + "' is neither beside the graph (" + beside.string() +
                                 ") nor in the data folder (" + in_data.string() + ")");
}

// Whether parameter-block member type `glsl` carries a parameter of type `type` (4 bytes each).
bool carries(const std::string& glsl, ParamType type) {
  switch (type) {
    case ParamType::float_: return glsl == "float";
    case ParamType::int_: return glsl == "int" || glsl == "uint";
    case ParamType::bool_: return glsl == "bool" || glsl == "uint" || glsl == "int";
    case ParamType::choice: return glsl == "uint" || glsl == "int";
  }
  return false;
}

// What a parameter block may hold: parameters are 4-byte scalars (carries).
bool is_scalar(const std::string& glsl) {
  return glsl == "float" || glsl == "int" || glsl == "uint" || glsl == "bool";
}

const char* member_type_for(ParamType type) {
  switch (type) {
    case ParamType::float_: return "float";
    case ParamType::int_: return "int";
    case ParamType::bool_: return "bool";
    case ParamType::choice: return "uint (the index of the choice)";
  }
  return "?";
}

class Checker {
 public:
  Checker(const GraphDesc& graph, const PassDesc& pass, const shader::Reflection& reflection, UserShader& shader, PassTypeDecl& decl)
      : graph_(graph), pass_(pass), user_(*pass.user), reflection_(reflection), shader_(shader), decl_(decl) {}

  void run() {
    for (size_t i = 0; i < user_.ports.size(); ++i) {
      errors_.attempt([&] { check_port(decl_.ports[i], user_.port_pointers[i]); });
    }
    for (const auto& b : reflection_.bindings) errors_.attempt([&] { check_binding(b); });
    errors_.attempt([&] { check_counters(); });
    errors_.attempt([&] { check_parameters(); });
    errors_.attempt([&] { check_dispatch_port(); });
    for (const auto& in : reflection_.inputs) errors_.attempt([&] { check_input(in); });
    errors_.throw_if_any();
  }

 private:
  const GraphDesc& graph_;
  const PassDesc& pass_;
  const UserPassDesc& user_;
  const shader::Reflection& reflection_;
  UserShader& shader_;
  PassTypeDecl& decl_;
  ErrorList errors_;

  std::string of_pass() const { return " of pass '" + pass_.name + "'"; }

  // A fragment input that the fullscreen vertex stage does not give would read undefined values.
  void check_input(const shader::ReflectedInput& in) {
    if (shader_.kind != UserShaderKind::fullscreen) return;
    if (in.name == kFullscreenUv && in.type == "vec2" && in.location == 0) {
      shader_.reads_uv = true;
      return;
    }
    throw graph_.error(pass_.pointer + "/shader", place(in.place) + ": fragment input '" + in.name + "' (" + in.type + " at location " +
                                                      std::to_string(in.location) +
                                                      ") is not given by a fullscreen pass's vertex stage, which gives only 'uv' (vec2 at "
                                                      "location 0: 0 to 1 across the target from its top-left corner)");
  }

  std::vector<std::string> binding_names() const {
    std::vector<std::string> names;
    for (const auto& b : reflection_.outputs) names.push_back(b.name);
    for (const auto& b : reflection_.bindings) names.push_back(b.name);
    return names;
  }

  void check_port(PortDecl& port, const std::string& pointer) {
    if (port.usage == PortUsage::color_attachment) return check_output(port, pointer);
    auto found = std::find_if(reflection_.bindings.begin(), reflection_.bindings.end(),
                              [&](const ReflectedBinding& b) { return b.name == port.name || b.block == port.name; });
    const BindingKind wanted = binding_kind_of(port);
    if (found == reflection_.bindings.end()) {
      throw graph_.error(pointer, "port '" + port.name + "'" + of_pass() + " has no binding in " + shader_.path + ": it declares no " +
                                      std::string(binding_kind_name(wanted)).substr(2) + " named '" + port.name + "'" +
                                      did_you_mean(port.name, binding_names()));
    }
    const ReflectedBinding& b = *found;
    const std::string at = place(b.place) + ": ";
    if (b.kind != wanted) {
      throw graph_.error(pointer, "port '" + port.name + "'" + of_pass() + " is " + binding_kind_name(wanted) + ", but " + at + "'" +
                                      b.name + "' is " + binding_kind_name(b.kind));
    }
    if (b.set != 0) throw graph_.error(pointer, at + "'" + b.name + "' is in set " + std::to_string(b.set) + "; user passes bind set 0");
    if (shader_.scene && is_scene_binding(b.binding)) {
      throw graph_.error(pointer, at + "'" + b.name + "' takes " + taken_by_the_scene(b.binding) + "; bind port '" + port.name +
                                      "' at another binding from " + std::to_string(kUserSceneBindings));
    }
    if (port.kind == ResourceKind::image && b.arrayed != (port.layers > 1)) {
      throw graph_.error(
          pointer, "port '" + port.name + "'" + of_pass() + " takes an image of " + std::to_string(port.layers) + " layer(s), but " + at +
                       "'" + b.name + "' is " + (b.arrayed ? "an array" : "not an array") +
                       (port.layers > 1 ? "; declare it sampler2DArray or image2DArray" : "; declare it sampler2D or image2D"));
    }
    if (port.access == PortAccess::read && (b.kind == BindingKind::storage_image || b.kind == BindingKind::storage_buffer) && !b.readonly) {
      throw graph_.error(pointer, "port '" + port.name + "'" + of_pass() + " is read, but " + at + "'" + b.name +
                                      "' is not readonly: declare it readonly, or the port read_write");
    }
    if (b.kind == BindingKind::storage_image) check_format(port, b, pointer);
    shader_.bindings.push_back({port.name, b.name, b.binding});
  }

  void check_format(PortDecl& port, const ReflectedBinding& b, const std::string& pointer) {
    const std::string at = place(b.place) + ": ";
    if (b.format.empty() && port.access != PortAccess::write) {
      throw graph_.error(
          pointer, at + "storage image '" + b.name + "' has no format qualifier, which the device needs to read it (r32f, rgba16f...)");
    }
    if (b.format.empty()) return;
    std::vector<Format> with_qualifier;
    for (const auto& name : format_names()) {
      const Format f = *parse_format(name);
      if (format_info(f).glsl_qualifier == b.format) with_qualifier.push_back(f);
    }
    if (port.formats.empty()) {
      port.formats = with_qualifier;  // the shader's declaration says what the port takes
      return;
    }
    for (Format f : port.formats) {
      if (std::find(with_qualifier.begin(), with_qualifier.end(), f) == with_qualifier.end()) {
        throw graph_.error(pointer, "format mismatch: port '" + port.name + "'" + of_pass() + " takes " + format_info(f).name + ", but " +
                                        at + "'" + b.name + "' is declared " + b.format);
      }
    }
  }

  void check_output(PortDecl& port, const std::string& pointer) {
    auto found = std::find_if(reflection_.outputs.begin(), reflection_.outputs.end(),
                              [&](const ReflectedBinding& b) { return b.name == port.name; });
    if (found == reflection_.outputs.end()) {
      throw graph_.error(pointer, "port '" + port.name + "'" + of_pass() + " has no binding in " + shader_.path +
                                      ": it declares no fragment output (layout(location = N) out vec4) named '" + port.name + "'" +
                                      did_you_mean(port.name, binding_names()));
    }
    // Outputs of one draw cover one extent.
    if (port.extent_group.empty()) port.extent_group = "fullscreen outputs";
    shader_.bindings.push_back({port.name, found->name, found->binding});
  }

  // A counter buffer: a storage buffer block whose one member is `counters` or `sums` (the names
  // caustics/group_totals.glsl adds to).
  static const shader::ReflectedMember* counter_member(const ReflectedBinding& b) {
    if (b.kind != BindingKind::storage_buffer || b.members.size() != 1) return nullptr;
    const shader::ReflectedMember& m = b.members.front();
    return m.name == "counters" || m.name == "sums" ? &m : nullptr;
  }

  void check_counter_binding(const ReflectedBinding& b, const shader::ReflectedMember& member) const {
    const std::string at = place(member.place) + ": ";
    const bool counts = member.name == "counters";
    const char* wanted = counts ? "uint[]" : "float[]";
    if (member.type != wanted) {
      throw graph_.error(user_.counters_pointer, at + "member '" + member.name + "' of counter buffer '" + b.block + "' is " + member.type +
                                                     "; the counter buffer is uint counters[] (counts) or float sums[] (sums)");
    }
    if (b.readonly) throw graph_.error(user_.counters_pointer, at + "counter buffer '" + b.block + "' is readonly; the shader adds to it");
    if (b.set != 0)
      throw graph_.error(user_.counters_pointer,
                         at + "counter buffer '" + b.block + "' is in set " + std::to_string(b.set) + "; user passes bind set 0");
    if (shader_.scene && is_scene_binding(b.binding)) {
      throw graph_.error(user_.counters_pointer, at + "counter buffer '" + b.block + "' takes " + taken_by_the_scene(b.binding));
    }
    std::optional<UserShaderBinding>& buffer = counts ? shader_.counts_buffer : shader_.sums_buffer;
    if (buffer) {
      throw graph_.error(user_.counters_pointer, at + "a second counter buffer of " + member.name + " (binding " +
                                                     std::to_string(b.binding) + "); the first is at binding " +
                                                     std::to_string(buffer->binding));
    }
    buffer = UserShaderBinding{b.name, b.binding};
  }

  void check_counters() const {
    shader_.counters = user_.counters;
    const bool counts = std::any_of(user_.counters.begin(), user_.counters.end(), [](const auto& c) { return !c.sum; });
    const bool sums = std::any_of(user_.counters.begin(), user_.counters.end(), [](const auto& c) { return c.sum; });
    const char* missing = counts && !shader_.counts_buffer
                              ? "layout(set = 0, binding = N) buffer Counts { uint counters[]; } for its counts"
                          : sums && !shader_.sums_buffer ? "layout(set = 0, binding = N) buffer Sums { float sums[]; } for its sums"
                                                         : nullptr;
    if (missing) {
      throw graph_.error(user_.counters_pointer,
                         "pass '" + pass_.name + "' declares counters, and " + shader_.path + " declares no counter buffer " + missing);
    }
  }

  void check_binding(const ReflectedBinding& b) const {
    if (&b == uniform_params()) return;  // check_parameters'
    const bool port =
        std::any_of(user_.ports.begin(), user_.ports.end(), [&](const PortDecl& p) { return p.name == b.name || p.name == b.block; });
    if (port) return;
    const shader::ReflectedMember* counter = counter_member(b);
    if (counter && !user_.counters.empty()) return check_counter_binding(b, *counter);
    if (b.set == kSceneTextureSet) return check_scene_textures(b);
    if (shader_.scene && b.set == 0 && is_scene_binding(b.binding)) {
      if (b.kind != scene_binding_kind(b.binding)) {
        throw graph_.error(pass_.pointer + "/scene",
                           place(b.place) + ": '" + b.name + "' at binding " + std::to_string(b.binding) + " is " +
                               binding_kind_name(b.kind) + ", but the scene's binding " + std::to_string(b.binding) + " is " +
                               binding_kind_name(scene_binding_kind(b.binding)) + " (" + scene_library_of(b.binding) + ")");
      }
      // The acceleration structure, or the triangles that only its hits index.
      if (b.binding >= kUserSceneBindings) shader_.ray_queries = true;
      shader_.scene_bindings.push_back({b.name, scene_resource(b.binding)});
      return;
    }
    if (b.kind == BindingKind::acceleration_structure) {
      throw graph_.error(pass_.pointer + (shader_.scene ? "/scene" : ""),
                         place(b.place) + ": '" + b.name + "' at binding " + std::to_string(b.binding) +
                             " is an acceleration structure; a user pass has one only as the scene's, binding " +
                             std::to_string(kSceneTlasBinding) + " of set 0 (shaders/scene/trace.glsl)" +
                             (shader_.scene ? "" : ", with \"scene\": true"));
    }
    std::vector<std::string> ports;
    for (const auto& p : user_.ports) ports.push_back(p.name);
    const bool scene_block = b.block == "FrameBlock" || b.block == "VertexBlock" || b.block == "ObjectBlock" || b.block == "TriangleBlock";
    throw graph_.error(pass_.pointer + (user_.ports.empty() ? "" : "/ports"),
                       place(b.place) + ": binding " + std::to_string(b.binding) + " '" + b.name + "', " + binding_kind_name(b.kind) +
                           ", is no port" + of_pass() + "; declare it under \"ports\"" +
                           (scene_block && !shader_.scene ? ", or give the pass the scene with \"scene\": true"
                            : counter                     ? ", or the counters the shader adds to under \"counters\""
                                                          : did_you_mean(b.name, ports)));
  }

  // Set 1 is the scene's texture array, one binding of sampler2D (shaders/scene/textures.glsl).
  void check_scene_textures(const ReflectedBinding& b) const {
    const std::string at = place(b.place) + ": '" + b.name + "' in set " + std::to_string(kSceneTextureSet);
    if (!shader_.scene) {
      throw graph_.error(pass_.pointer, at + " is the scene's texture array (shaders/scene/textures.glsl); give the pass the scene with "
                                             "\"scene\": true, or bind it in set 0 as a port");
    }
    if (b.binding != 0 || b.kind != BindingKind::sampled_image || b.arrayed) {
      throw graph_.error(pass_.pointer + "/scene", at + " at binding " + std::to_string(b.binding) + " is " + binding_kind_name(b.kind) +
                                                       (b.arrayed ? " array" : "") + ", but set " + std::to_string(kSceneTextureSet) +
                                                       " is the scene's texture array, binding 0, sampler2D[] "
                                                       "(shaders/scene/textures.glsl)");
    }
    shader_.scene_textures = true;
  }

  // The uniform block that holds the parameters: kParamsBlock, unless a port names it.
  const ReflectedBinding* uniform_params() const {
    for (const auto& b : reflection_.bindings) {
      if (b.kind != BindingKind::uniform_buffer || b.block != kParamsBlock) continue;
      const bool port =
          std::any_of(user_.ports.begin(), user_.ports.end(), [&](const PortDecl& p) { return p.name == b.name || p.name == b.block; });
      if (!port) return &b;
    }
    return nullptr;
  }

  // Where the uniform parameter block may be: set 0, at a binding of its own.
  void check_uniform_params(const ReflectedBinding& block) const {
    const std::string name = "uniform block '" + block.block + "'";
    const std::string at = place(block.place) + ": " + name;
    const std::string pointer = pass_.pointer + "/parameters";
    if (!reflection_.push_block.empty()) {
      throw graph_.error(pointer, at + " holds the parameters" + of_pass() + ", and so does push-constant block '" +
                                      reflection_.push_block + "' (" + place(reflection_.push_place) +
                                      "); declare the parameters in one of them");
    }
    if (block.set != 0) throw graph_.error(pointer, at + " is in set " + std::to_string(block.set) + "; user passes bind set 0");
    if (shader_.scene && is_scene_binding(block.binding)) {
      throw graph_.error(pointer, at + " takes " + taken_by_the_scene(block.binding) + "; bind it at another binding from " +
                                      std::to_string(kUserSceneBindings));
    }
    if (block.size > kMaxParamsBlockBytes) {
      throw graph_.error(pointer, at + " is " + std::to_string(block.size) + " bytes; a parameter block may have " +
                                      std::to_string(kMaxParamsBlockBytes) + " (the uniform buffer range every device allows)");
    }
    for (const auto& b : reflection_.bindings) {
      if (&b == &block || b.set != 0 || b.binding != block.binding) continue;
      throw graph_.error(pointer, place(b.place) + ": '" + b.name + "' takes binding " + std::to_string(b.binding) + ", which " + name +
                                      " has (" + place(block.place) + "), the parameters" + of_pass() + "; bind '" + b.name +
                                      "' at another binding");
    }
  }

  // The declared parameters are the members of the parameter block (a push-constant block, or the
  // uniform block Params), one 4-byte scalar each, by name.
  void check_parameters() {
    std::vector<std::string> declared;
    for (const auto& p : user_.params) declared.push_back(p.name);
    const ReflectedBinding* uniform = uniform_params();
    if (reflection_.push_block.empty() && !uniform) {
      if (user_.params.empty()) return;
      throw graph_.error(pass_.pointer + "/parameters",
                         "pass '" + pass_.name + "' declares parameters, and " + shader_.path +
                             " has no parameter block for them: a push-constant block (layout(push_constant) uniform Params { ... }) "
                             "or a uniform block Params (layout(binding = N) uniform Params { ... })");
    }
    if (uniform) check_uniform_params(*uniform);
    const std::vector<shader::ReflectedMember>& members = uniform ? uniform->members : reflection_.push_members;
    const std::string block = uniform ? "uniform block '" + uniform->block + "'" : "push-constant block '" + reflection_.push_block + "'";
    const shader::SourcePlace& block_place = uniform ? uniform->place : reflection_.push_place;
    ErrorList errors;
    for (const auto& member : members) {
      errors.attempt([&] {
        const std::string at = place(member.place) + ": member '" + member.name + "' of " + block + " is ";
        auto param = std::find_if(user_.params.begin(), user_.params.end(), [&](const ParamDecl& p) { return p.name == member.name; });
        if (param == user_.params.end()) {
          if (!is_scalar(member.type)) {
            throw graph_.error(pass_.pointer + "/parameters",
                               at + member.type + "; a parameter block holds 4-byte scalars (float, int, uint, bool), one per parameter");
          }
          throw graph_.error(pass_.pointer + "/parameters", at + "no parameter" + of_pass() + did_you_mean(member.name, declared));
        }
        const size_t index = static_cast<size_t>(param - user_.params.begin());
        if (!carries(member.type, param->type)) {
          throw graph_.error(user_.param_pointers[index], at + member.type + ", and parameter '" + param->name + "' (" +
                                                              std::string(param_type_name(param->type)) + ") needs " +
                                                              member_type_for(param->type));
        }
        shader_.params.push_back({member.name, member.offset});
      });
    }
    for (size_t i = 0; i < user_.params.size(); ++i) {
      errors.attempt([&] {
        const auto& name = user_.params[i].name;
        const bool in_block = std::any_of(members.begin(), members.end(), [&](const shader::ReflectedMember& m) { return m.name == name; });
        if (!in_block) {
          throw graph_.error(user_.param_pointers[i],
                             "parameter '" + name + "'" + of_pass() + " is not in " + block + " (" + place(block_place) + ")");
        }
      });
    }
    errors.throw_if_any();
    shader_.params_bytes = uniform ? uniform->size : reflection_.push_size;
    if (uniform) shader_.params_block = UserShaderBinding{uniform->name, uniform->binding};
  }

  void check_dispatch_port() const {
    if (user_.dispatch_port.empty()) return;
    const PortDecl* port = decl_.find_port(user_.dispatch_port);
    std::vector<std::string> images;
    for (const auto& p : user_.ports) {
      if (p.kind == ResourceKind::image) images.push_back(p.name);
    }
    if (!port || port->kind != ResourceKind::image) {
      throw graph_.error(user_.dispatch_pointer, "\"dispatch\": '" + user_.dispatch_port + "' is no image port" + of_pass() +
                                                     did_you_mean(user_.dispatch_port, images));
    }
  }
};

// The shader compiled for the compute tracer, where it traces through scene/trace.glsl: nothing
// where it still declares an acceleration structure (its own, not the library's).
std::optional<UserShader::TracerVariant> compute_tracer_variant(const std::filesystem::path& path, const std::string& shader_pointer,
                                                                const GraphDesc& graph, const PassDesc& pass) {
  shader::ReflectedShader compiled;
  try {
    compiled = shader::process_shader_compiler().compile_reflected(path.string(), {{"CAUSTICA_COMPUTE_TRACER", "1"}});
  } catch (const InputError& e) {
    throw graph.error(shader_pointer, "the shader of pass '" + pass.name + "' does not compile for the compute tracer: " + e.what());
  }
  const auto& bindings = compiled.reflection.bindings;
  if (std::any_of(bindings.begin(), bindings.end(),
                  [](const ReflectedBinding& b) { return b.kind == BindingKind::acceleration_structure; }))
    return std::nullopt;
  return UserShader::TracerVariant{std::move(compiled.spirv), std::move(compiled.reflection)};
}

}  // namespace

std::shared_ptr<PassTypeDecl> make_user_pass_type(const PassTypeDecl& kind, const GraphDesc& graph, const PassDesc& pass,
                                                  std::shared_ptr<UserShader>& shader) {
  const UserPassDesc& user = *pass.user;
  const std::string shader_pointer = pass.pointer + "/shader";
  const std::filesystem::path path = find_shader(graph, pass, shader_pointer);
  const char* extension = kind.user_kind == UserShaderKind::fullscreen ? ".frag" : ".comp";
  if (path.extension() != extension) {
    throw graph.error(shader_pointer, "a " + kind.type + " pass's shader is a " + extension + " file, not '" + user.shader + "'");
  }
  shader::ReflectedShader compiled;
  try {
    compiled = shader::process_shader_compiler().compile_reflected(path.string());
  } catch (const InputError& e) {
    throw graph.error(shader_pointer, "the shader of pass '" + pass.name + "' does not compile: " + e.what());
  }
  shader = std::make_shared<UserShader>();
  shader->kind = kind.user_kind;
  shader->path = path.string();
  shader->files = compiled.files;
  shader->spirv = std::move(compiled.spirv);
  shader->scene = user.scene;
  shader->local_size = compiled.reflection.local_size;
  shader->dispatch_port = user.dispatch_port;

  auto decl = std::make_shared<PassTypeDecl>(kind);
  decl->description = pass.user->shader + ": " + kind.description;
  decl->ports = user.ports;
  decl->params = user.params;
  // The pass writes its parameters into its parameter block each time it records, so any of them may be an
  // expression of the frame (frame.index...), evaluated before every frame; only a dispatch that
  // names one is refused, being fixed for the plan (Compiler::resolve_dispatch).
  for (auto& param : decl->params) param.per_frame = true;
  decl->needs_scene = user.scene;
  // Without the scene its result follows from its inputs and parameters alone; with it, from
  // whatever of the scene the shader reads.
  decl->depends_on = [scene = user.scene](const nlohmann::json&) { return scene ? kDependsOnScene : 0u; };
  decl->result_source = std::move(compiled.sources);
  Checker(graph, pass, compiled.reflection, *shader, *decl).run();
  shader->reflection = std::move(compiled.reflection);
  if (shader->ray_queries) {
    decl->traces_scene = [](const nlohmann::json&) { return true; };
    shader->compute_tracer = compute_tracer_variant(path, shader_pointer, graph, pass);
    decl->ray_queries_only = !shader->compute_tracer;
    decl->ray_query_alternative =
        "its shader " + shader->path + " declares the scene's acceleration structure itself (binding " + std::to_string(kSceneTlasBinding) +
        "); trace through shaders/scene/trace.glsl's trace_surface and occluded instead, which every device runs, or run the graph "
        "on a device that has ray queries";
  }
  decl->user_shader = shader;
  return decl;
}

}  // namespace caustica::graph
