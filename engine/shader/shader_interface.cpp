#include "shader/shader_interface.h"

#include <algorithm>

#include "core/error.h"

namespace caustica::shader {

const char* binding_kind_name(BindingKind kind) {
  switch (kind) {
    case BindingKind::sampled_image: return "a sampled image (sampler2D)";
    case BindingKind::storage_image: return "a storage image (image2D)";
    case BindingKind::storage_buffer: return "a storage buffer (buffer block)";
    case BindingKind::uniform_buffer: return "a uniform block";
    case BindingKind::acceleration_structure: return "an acceleration structure";
    case BindingKind::other: break;
  }
  return "a binding of a kind no port has";
}

ShaderInterface::ShaderInterface(std::string pass, const std::vector<NamedReflection>& shaders) : pass_(std::move(pass)) {
  for (const NamedReflection& shader : shaders) {
    shaders_.push_back(shader.path);
    for (const ReflectedBinding& b : shader.reflection->bindings) {
      const auto same = std::find_if(bindings_.begin(), bindings_.end(),
                                     [&](const InterfaceBinding& known) { return known.set == b.set && known.binding == b.binding; });
      if (same == bindings_.end()) {
        bindings_.push_back({b.name, b.set, b.binding, b.kind, b.count, shader.path});
      } else if (same->name != b.name || same->kind != b.kind || same->count != b.count) {
        throw InputError(where(shader.path) + ": declares '" + b.name + "' at set " + std::to_string(b.set) + " binding " +
                         std::to_string(b.binding) + ", where " + same->shader + " declares '" + same->name + "'");
      }
    }
    // Stages that declare push constants declare a prefix of one block (a vertex stage's transform,
    // its fragment stage's more): a C++ mirror must match the longest.
    if (!shader.reflection->push_block.empty() && (push_block_.empty() || shader.reflection->push_size > push_size_)) {
      push_size_ = shader.reflection->push_size;
      push_block_ = shader.reflection->push_block;
      push_shader_ = shader.path;
      push_members_ = shader.reflection->push_members;
    }
  }
  std::sort(bindings_.begin(), bindings_.end(),
            [](const InterfaceBinding& a, const InterfaceBinding& b) { return std::pair(a.set, a.binding) < std::pair(b.set, b.binding); });
}

std::string ShaderInterface::where(const std::string& shader) const {
  return "pass '" + pass_ + "', shader " + shader;
}

bool ShaderInterface::declares(const std::string& name) const {
  return std::any_of(bindings_.begin(), bindings_.end(), [&](const InterfaceBinding& b) { return b.name == name; });
}

const InterfaceBinding& ShaderInterface::find(const std::string& name, const std::vector<BindingKind>& kinds) const {
  const auto found = std::find_if(bindings_.begin(), bindings_.end(), [&](const InterfaceBinding& b) { return b.name == name; });
  if (found == bindings_.end()) {
    std::string shaders;
    for (const std::string& shader : shaders_) shaders += (shaders.empty() ? "" : ", ") + shader;
    throw InputError("pass '" + pass_ + "' binds '" + name + "', which its shaders (" + shaders + ") do not declare");
  }
  if (std::find(kinds.begin(), kinds.end(), found->kind) == kinds.end()) {
    throw InputError(where(found->shader) + ": '" + name + "' is " + binding_kind_name(found->kind) + ", and the pass binds " +
                     binding_kind_name(kinds.front()) + " to it");
  }
  return *found;
}

void ShaderInterface::check_written(const std::vector<std::pair<size_t, uint32_t>>& written) const {
  for (size_t i = 0; i < bindings_.size(); ++i) {
    if (bindings_[i].set != 0) continue;
    for (uint32_t element = 0; element < bindings_[i].count; ++element) {
      if (std::find(written.begin(), written.end(), std::pair(i, element)) != written.end()) continue;
      const std::string which =
          bindings_[i].count > 1 ? "element " + std::to_string(element) + " of '" + bindings_[i].name + "'" : "'" + bindings_[i].name + "'";
      throw InputError(where(bindings_[i].shader) + ": declares " + which + " (binding " + std::to_string(bindings_[i].binding) +
                       "), which the pass leaves unbound");
    }
  }
}

void ShaderInterface::check_push(const std::string& cpp_type, size_t size, const std::vector<MirroredMember>& members) const {
  const std::string block = where(push_shader_) + ": push-constant block " + push_block_;
  if (push_block_.empty())
    throw InputError("pass '" + pass_ + "': " + cpp_type + " mirrors a push-constant block its shaders do not declare");
  for (const ReflectedMember& glsl : push_members_) {
    const auto cpp = std::find_if(members.begin(), members.end(), [&](const MirroredMember& m) { return m.name == glsl.name; });
    if (cpp == members.end()) throw InputError(block + ": member '" + glsl.name + "' has no counterpart in " + cpp_type);
    if (cpp->offset != glsl.offset) {
      throw InputError(block + ": member '" + glsl.name + "' is at offset " + std::to_string(glsl.offset) + ", " + cpp_type +
                       " has it at " + std::to_string(cpp->offset));
    }
  }
  for (const MirroredMember& cpp : members) {
    const bool declared =
        std::any_of(push_members_.begin(), push_members_.end(), [&](const ReflectedMember& glsl) { return glsl.name == cpp.name; });
    if (!declared) throw InputError(block + " has no member '" + cpp.name + "', which " + cpp_type + " mirrors");
  }
  if (size != push_size_) {
    throw InputError(block + " is " + std::to_string(push_size_) + " bytes, " + cpp_type + " is " + std::to_string(size));
  }
}

}  // namespace caustica::shader
