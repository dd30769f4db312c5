#pragma once
// What a pass type declares before anything runs (Falcor's "reflect"): its ports, its parameters,
// the queue work it records and whether it has side effects. The compiler sees only this; the
// executor later creates the pass object and calls execute() with real resources.
#include <nlohmann/json.hpp>

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "graph/format.h"

namespace caustica::graph {

class Pass;

enum class ResourceKind { image, buffer };
enum class PortAccess { read, write, read_write };
enum class PortUsage {
  sampled,           // image read through a sampler
  storage,           // storage image or storage buffer
  color_attachment,  // image rendered to
  depth_attachment,  // depth image rendered to or tested against
  transfer_src,
  transfer_dst,
  uniform,   // uniform buffer
  indirect,  // indirect dispatch or draw arguments
};
enum class PassQueue { graphics, compute, transfer };

// What a pass's result depends on besides its inputs and parameters. A plan compiled with
// CompileOptions::reuse_unchanged_passes keeps the outputs of passes that do not depend on the
// frame, and the executor skips such a pass while none of the scene parts it depends on (directly
// or through its inputs) changed since it last ran: the light's view while only the camera moves.
enum SceneDependency : uint32_t {
  kDependsOnGeometry = 1u << 0,  // meshes, transforms, materials, textures
  kDependsOnLights = 1u << 1,
  kDependsOnCamera = 1u << 2,  // the camera, the sky and the output size
  kDependsOnFrame = 1u << 3,   // differs every frame (a jittered grid, history): never skipped
};
inline constexpr uint32_t kDependsOnScene = kDependsOnGeometry | kDependsOnLights | kDependsOnCamera;
// Of the lights, every one (bit K: light K; PlannedPass::lights).
inline constexpr uint32_t kAllLights = ~0u;
inline constexpr std::array<uint32_t, 3> kSceneParts = {kDependsOnGeometry, kDependsOnLights, kDependsOnCamera};
// "geometry", "lights", "camera", "frame": for plans, traces and messages.
std::vector<std::string> dependency_names(uint32_t dependencies);

struct PortDecl {
  std::string name;
  PortAccess access = PortAccess::read;
  ResourceKind kind = ResourceKind::image;
  PortUsage usage = PortUsage::sampled;
  std::vector<Format> formats;  // accepted formats; empty accepts any
  bool optional = false;
  // Ports of one pass sharing a non-empty group must be bound to images of equal extent.
  std::string extent_group;
  std::string description;
  // The pass also samples the image between its own draws (and transitions it itself), so the
  // image is created with sampled usage; the plan's barriers still see only `usage`.
  bool also_sampled = false;
  // Array layers the bound image must have: the shader declares an array (image2DArray) when above 1.
  uint32_t layers = 1;
  // Also takes an image of six layers: a point light's cube faces (shadow maps).
  bool cube_layers = false;
  // One resource per light (graph/per_light.h): bound to a per-light resource, element K is light K's
  // instance ("PORT[K]" in PlannedPass::ports); bound to one resource, that is element 0.
  bool per_light = false;
};

enum class ParamType { float_, int_, bool_, choice };

struct ParamDecl {
  std::string name;
  ParamType type = ParamType::float_;
  nlohmann::json default_value;
  std::optional<double> min;
  std::optional<double> max;
  std::vector<std::string> choices;  // for ParamType::choice
  std::string description;
  // Read while the pass records each frame (not when it is set up), so a graph may make it an
  // expression of the frame block ("frame.since_reset", kFrameNames), evaluated before every frame.
  bool per_frame = false;
  // An int that must be a power of two (a photon grid that a traversal refines by halving it): the
  // checks name the nearest powers, the schema lists them and the viewer's slider doubles and halves.
  bool power_of_two = false;
  // How fast a running result converges, not to what (caustic_map.slice_side: the mean of quarter
  // grids and of ninth grids is the same grid's map): a running result goes on into a new plan whose
  // passes differ only in such parameters (PlannedPass::running_id).
  bool sampling_only = false;
};

// The frame block that a per-frame parameter's expression may name (graph::FrameInfo).
inline constexpr const char* kFrameNames[] = {"frame.index", "frame.since_reset", "frame.jitter_x", "frame.jitter_y"};

struct PlannedResource;
// A pass's ports' resources as the compiler sized them (PassTypeDecl::check): nullptr where unbound.
using PortResources = std::function<const PlannedResource*(std::string_view port)>;
// What a pass type's own rule says of a pass: an error that refuses the graph, a warning the plan
// carries; empty where nothing is wrong.
struct PassCheck {
  std::string error;
  std::string warning;
};

// A pass type whose shader, ports and parameters each pass of it declares in the graph file
// (graph/user_pass_type.h): the registry holds the kind, and the compiler makes each such pass a
// type of its own from the file and its shader's reflection (Plan::user_types).
enum class UserShaderKind { none, compute, fullscreen };
inline constexpr std::string_view kUserPassTypes[] = {"compute", "fullscreen"};
struct UserShader;

struct PassTypeDecl {
  std::string type;
  std::string description;
  PassQueue queue = PassQueue::graphics;
  std::vector<PortDecl> ports;
  std::vector<ParamDecl> params;
  bool side_effects = false;  // kept even when it reaches no output
  std::function<std::unique_ptr<Pass>()> create;
  bool needs_scene = false;  // draws or reads the scene: running it without one is an input error
  // Whether the pass, with these resolved parameters, traces exact paths through the scene's
  // geometry (shaders/scene/trace.glsl, by the plan's Tracer). Unset: never.
  std::function<bool(const nlohmann::json& params)> traces_scene;
  // A pass that traces with ray queries alone (a user shader that declares the acceleration
  // structure itself): its plan takes the ray-query tracer, and a device without it refuses the pass.
  bool ray_queries_only = false;
  // Whether the pass, with these parameters, draws from its light's view (parameter "light", default
  // 0): only spot and directional lights have one, so with a point light the plan warns that the pass
  // contributes nothing (Plan::warnings). Unset: never.
  std::function<bool(const nlohmann::json& params)> uses_light_view;
  // What the pass, with these parameters, depends on besides its inputs (SceneDependency bits).
  // Unset: the frame, so a pass type that does not say is never skipped.
  std::function<uint32_t(const nlohmann::json& params)> depends_on;
  // Whether the pass, with these parameters, wants the camera moved within its pixels from frame to
  // frame while it stands still (an average of still frames that antialiases: temporal_mean). A plan
  // with such a pass jitters the camera for every pass, which then re-draw every frame. Unset: never.
  std::function<bool(const nlohmann::json& params)> jitters_camera;
  // Its output is a running result that each frame moves from its own last one (a mean over
  // frames), as a pass reading a history input's is. A plan that reuses unchanged passes keeps such
  // results, so that frames which only refine them (FramePart::refine) and frames which only show
  // them (FramePart::display) can run apart.
  bool accumulates = false;
  // A rule about the pass's parameters and its resources' sizes that the declarations above cannot
  // state (a light map a power of two wide, an output twice another's width). The compiler checks
  // it, so that `validate` refuses what a render would. Unset: none.
  std::function<PassCheck(const nlohmann::json& params, const PortResources& resource)> check;
  // What to suggest instead where a pass that traces with ray queries alone (ray_queries_only)
  // cannot: a user pass's, naming its shader.
  std::string ray_query_alternative;
  // The registry's "compute" and "fullscreen": each pass of this type declares its own in the file.
  UserShaderKind user_kind = UserShaderKind::none;
  // A user pass's own type: its shader as compiled and reflected, and where its ports bind.
  std::shared_ptr<const UserShader> user_shader;
  // What the pass's result follows from besides its parameters and inputs (a user pass's shader
  // text, includes and all): part of PlannedPass::result_id, so that an edited shader runs again.
  std::string result_source;

  const PortDecl* find_port(std::string_view name) const;  // also "PORT[K]", element K of a per-light port
  const ParamDecl* find_param(std::string_view name) const;
};

std::string_view param_type_name(ParamType type);

// Checks a parameter value against its declaration; returns the reason it is wrong, or "".
std::string check_param_value(const ParamDecl& decl, const nlohmann::json& value);
// The values a power_of_two parameter (which declares min and max) may take, smallest first.
std::vector<int64_t> powers_of_two_within(const ParamDecl& decl);
// The value of a numeric or boolean parameter that an expression evaluated to: an int rounded
// down, a bool true where non-zero; `clamped` keeps it within the declared range (a per-frame
// expression, which no check can bound for every frame).
nlohmann::json param_value_of_number(const ParamDecl& decl, double value, bool clamped);

class PassRegistry {
 public:
  void add(PassTypeDecl decl);
  const PassTypeDecl* find(std::string_view type) const;
  std::vector<std::string> names() const;
  const std::map<std::string, PassTypeDecl, std::less<>>& types() const { return types_; }

 private:
  std::map<std::string, PassTypeDecl, std::less<>> types_;
};

}  // namespace caustica::graph
