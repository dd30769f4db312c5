#pragma once
// A graph's user passes: a "compute" or "fullscreen" pass names its shader and declares its ports,
// parameters and dispatch in the graph file (UserPassDesc). The compiler makes each such pass a
// pass type of its own, checked against what its shader declares (glslang's linked program)
// before any device runs: every binding a port, every port a binding of its kind and format, the
// parameter block (push constants, or a uniform block Params) the declared parameters.
#include <array>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "graph/graph_desc.h"
#include "shader/shader_compiler.h"

namespace caustica::graph {

// What a port is in the shader: the name the pass binds it by (shader::ShaderInterface's: the
// variable, or a block's instance name, its type name where it has none) and its binding in set 0
// (a fragment output: its location, which orders the colour attachments).
struct UserPortBinding {
  std::string port;
  std::string name;
  uint32_t binding = 0;
};

// A binding of the shader's own that is no port (the parameter block, a counter buffer): its name
// as the pass binds it, and its number for messages.
struct UserShaderBinding {
  std::string name;
  uint32_t binding = 0;
};

// The first bindings of set 0 that a pass with "scene": true gives the scene (shaders/scene/
// scene.glsl: SCENE_FRAME, SCENE_VERTICES, SCENE_OBJECTS); its ports bind after them.
inline constexpr uint32_t kUserSceneBindings = 3;
// Where the built-in passes' shaders have the rest of the scene, which the shader library declares
// there: the texture array (set 1, scene/textures.glsl), and for tracing the scene's structure (the
// top-level acceleration structure, or the compute tracer's BVH) and its triangles' vertex indices
// (set 0, scene/trace.glsl). A pass with "scene": true gets those its shader declares.
inline constexpr uint32_t kSceneTextureSet = 1;
inline constexpr uint32_t kSceneTlasBinding = 14;
inline constexpr uint32_t kSceneTrianglesBinding = 15;
// Whether binding `binding` of set 0 is the scene's in a pass with "scene": true.
constexpr bool is_scene_binding(uint32_t binding) {
  return binding < kUserSceneBindings || binding == kSceneTlasBinding || binding == kSceneTrianglesBinding;
}

// What the scene gives at each of those bindings, in order: 0, 1, 2, 14, 15.
enum class SceneResource { frame, vertices, objects, acceleration_structure, triangles };
// A binding of the scene's that a user shader declares: under the shader's own name for it.
struct UserSceneBinding {
  std::string name;
  SceneResource resource = SceneResource::frame;
};

// A uniform block of this type name in a user pass's shader, and no port of it, holds the pass's
// parameters instead of a push-constant block (docs/shader_passes.md): for more than the 128 bytes
// of push constants, up to kMaxParamsBlockBytes, the uniform buffer range every device allows.
inline constexpr const char* kParamsBlock = "Params";
inline constexpr uint32_t kMaxParamsBlockBytes = 16384;

// The one varying a fullscreen pass's vertex stage (shaders/common/fullscreen.vert, with
// FULLSCREEN_UV) gives its fragment shader: `layout(location = 0) in vec2 uv`, 0 to 1 across the
// target from its top-left corner, (x + 0.5) / width at a pixel's centre.
inline constexpr const char* kFullscreenUv = "uv";

struct UserShader {
  UserShaderKind kind = UserShaderKind::compute;
  std::string path;                          // the shader file as found
  std::vector<std::filesystem::path> files;  // it and everything it includes: what a reload watches
  std::vector<uint32_t> spirv;
  shader::Reflection reflection;  // what the pass's pipeline is laid out and bound by
  // A shader that traces through the library (scene/trace.glsl) compiled again for the compute
  // tracer (CAUSTICA_COMPUTE_TRACER), which a plan with that tracer runs; unset where the shader
  // declares the acceleration structure itself (it then traces with ray queries alone).
  struct TracerVariant {
    std::vector<uint32_t> spirv;
    shader::Reflection reflection;
  };
  std::optional<TracerVariant> compute_tracer;
  std::vector<UserPortBinding> bindings;  // one per port
  // Where the parameters go: the push-constant block, or the uniform block kParamsBlock at
  // `params_block` (a buffer of the pass's own, written each time it records). Each is a 4-byte
  // member at its offset in the block (a choice is the index of its value, a bool 0 or 1).
  struct ParamMember {
    std::string name;
    uint32_t offset = 0;
  };
  std::vector<ParamMember> params;
  uint32_t params_bytes = 0;
  std::optional<UserShaderBinding> params_block;
  bool scene = false;
  std::vector<UserSceneBinding> scene_bindings;  // those the shader declares
  // With the scene: whether the shader samples its textures (set 1), and whether it traces it
  // (declares binding 14 or 15, as scene/trace.glsl does).
  bool scene_textures = false;
  bool ray_queries = false;
  // The pass's counters, in order, and where the shader declares its counter buffer: as uints
  // (a block holding `uint counters[]`) and as floats (`float sums[]`), the same buffer.
  std::vector<UserPassDesc::Counter> counters;
  std::optional<UserShaderBinding> counts_buffer, sums_buffer;
  std::array<uint32_t, 3> local_size{1, 1, 1};
  // Fullscreen: the fragment shader reads kFullscreenUv, which the vertex stage then gives.
  bool reads_uv = false;
  // Compute: one invocation per texel of this port's image, or else `invocations` (the compiler
  // evaluates the file's expressions).
  std::string dispatch_port;
  std::array<uint32_t, 3> invocations{1, 1, 1};
};

// The pass type of user pass `pass` (of registry kind `kind`): its ports, parameters and shader,
// with `shader` set to the UserShader that the type holds, for the compiler to complete with the
// dispatch once the parameters are resolved. Throws an InputError that names the graph file's
// place and, for a disagreement with the shader, the shader's file and line.
std::shared_ptr<PassTypeDecl> make_user_pass_type(const PassTypeDecl& kind, const GraphDesc& graph, const PassDesc& pass,
                                                  std::shared_ptr<UserShader>& shader);

}  // namespace caustica::graph
