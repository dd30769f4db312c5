#pragma once
// What a pipeline's shaders declare, by name: how a pass binds its resources and checks the C++
// structs that mirror its shaders' blocks, so that neither side keeps binding numbers, descriptor
// types or offsets of its own. Needs no device: a mistake is refused with the pass, the shader and
// the variable or member it is about.
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "shader/shader_compiler.h"

namespace caustica::shader {

// One shader of a pipeline: its path under the shader root (for messages) and what it declares.
struct NamedReflection {
  std::string path;
  const Reflection* reflection = nullptr;
};

struct InterfaceBinding {
  std::string name;  // the GLSL variable, or a block's instance name (its type name where it has none)
  uint32_t set = 0;
  uint32_t binding = 0;
  BindingKind kind = BindingKind::other;
  uint32_t count = 1;  // descriptors: an array's elements, each written by the pass
  std::string shader;  // the first of the pipeline's shaders that declares it
};

// A C++ struct's member as it must lie in a GLSL block: the member's GLSL name and its offset in
// the struct (offsetof).
struct MirroredMember {
  std::string name;
  size_t offset = 0;
};

// A member of C++ struct `type` whose GLSL counterpart has its name.
#define CAUSTICA_MIRRORED(type, member) \
  ::caustica::shader::MirroredMember {  \
#member, offsetof(type, member)     \
  }

class ShaderInterface {
 public:
  // `pass` names the pass in messages. The shaders' bindings merge by (set, binding); two shaders
  // that declare one binding differently are refused.
  ShaderInterface(std::string pass, const std::vector<NamedReflection>& shaders);

  const std::string& pass() const { return pass_; }
  // Every binding, set 0's then set 1's, each set by binding number.
  const std::vector<InterfaceBinding>& bindings() const { return bindings_; }
  uint32_t push_size() const { return push_size_; }
  // For what a pass binds only where a shader variant declares it (the scene's blocks, whichever of
  // them a shader includes).
  bool declares(const std::string& name) const;
  // The binding the shaders declare as `name`; refuses a name none declares, and one whose kind is
  // none of `kinds` (what the pass writes there).
  const InterfaceBinding& find(const std::string& name, const std::vector<BindingKind>& kinds) const;
  // Refuses a set-0 binding with an element that `written` (index in bindings(), element) lacks:
  // every descriptor a shader declares, each element of an array, is written each time the pass
  // binds it.
  void check_written(const std::vector<std::pair<size_t, uint32_t>>& written) const;
  // Refuses `cpp_type` (a C++ struct of `size` bytes) as the mirror of the push-constant block
  // unless it has the block's size and every member of the block at the block's offset, by name.
  void check_push(const std::string& cpp_type, size_t size, const std::vector<MirroredMember>& members) const;

 private:
  std::string where(const std::string& shader) const;
  std::string pass_;
  std::vector<std::string> shaders_;
  std::vector<InterfaceBinding> bindings_;
  uint32_t push_size_ = 0;
  std::string push_block_, push_shader_;
  std::vector<ReflectedMember> push_members_;
};

// "a sampled image (sampler2D)"...: a kind as messages name it.
const char* binding_kind_name(BindingKind kind);

}  // namespace caustica::shader
