#pragma once
// The compiled, read-only form of a graph: passes in execution order with their barriers, every
// resource with its lifetime and its place in memory. Nothing here touches a device, so the compiler
// is tested on the CPU; the executor turns a Plan into Vulkan objects and command buffers.
#include <vulkan/vulkan_core.h>

#include <cstdint>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "graph/instance.h"
#include "graph/pass_type.h"
#include "graph/result_identity.h"

namespace caustica::graph {

// How the passes that trace exact paths walk the scene (shaders/scene/trace.glsl): with ray queries
// over the driver's acceleration structures, or with the compute tracer over the host-built BVH
// (engine/scene/bvh.h), which every device runs.
enum class Tracer { none, ray_query, compute };
const char* tracer_name(Tracer tracer);
// "ray_query" or "compute"; nullopt for anything else.
std::optional<Tracer> parse_tracer(std::string_view name);
// CAUSTICA_TRACER (ray_query or compute; what --tracer sets) where it is set, nullopt for auto or
// unset; an InputError naming it for another value.
std::optional<Tracer> tracer_from_environment();

inline constexpr uint32_t kNoPass = UINT32_MAX;
inline constexpr uint32_t kNoBlock = UINT32_MAX;
inline constexpr uint32_t kNoResource = UINT32_MAX;
// A pass input bound to "NAME@previous" reads resource NAME as the previous frame left it.
inline constexpr std::string_view kPreviousSuffix = "@previous";
// The resource whose previous frame `binding` reads ("NAME@previous" -> "NAME"); empty when the
// binding reads a resource as this frame has it.
inline std::string history_source(std::string_view binding) {
  return binding.ends_with(kPreviousSuffix) ? std::string(binding.substr(0, binding.size() - kPreviousSuffix.size())) : std::string();
}
inline std::string history_of(std::string_view resource) {
  return std::string(resource) + std::string(kPreviousSuffix);
}
// Layered images hold one value per layer (an RGB caustic map: three r32f layers, because image
// atomics are single-channel), or a point light's six cube faces; up to four read back and dump
// with layer k as colour channel k, more as a strip of layers side by side.
inline constexpr uint32_t kMaxImageLayers = 6;

struct MemoryRequirements {
  uint64_t size = 0;
  uint64_t alignment = 1;
  uint32_t type_bits = ~0u;  // memory types the resource may live in
};

// Where a resource stands after an access: its layout, and the stages/accesses a later barrier waits on.
struct AccessState {
  VkImageLayout layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkPipelineStageFlags2 stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 access = VK_ACCESS_2_NONE;
};

struct PlannedBarrier {
  uint32_t resource = 0;
  VkPipelineStageFlags2 src_stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 src_access = VK_ACCESS_2_NONE;
  VkPipelineStageFlags2 dst_stages = VK_PIPELINE_STAGE_2_NONE;
  VkAccessFlags2 dst_access = VK_ACCESS_2_NONE;
  VkImageLayout old_layout = VK_IMAGE_LAYOUT_UNDEFINED;
  VkImageLayout new_layout = VK_IMAGE_LAYOUT_UNDEFINED;
  bool aliasing = false;  // first use of memory that an earlier resource used in this frame
};

struct PlannedResource {
  std::string name;
  std::string pointer;  // in the graph file
  ResourceKind kind = ResourceKind::image;
  Format format = Format::rgba8;
  uint32_t width = 0;
  uint32_t height = 0;
  uint32_t mips = 1;
  uint32_t layers = 1;
  uint64_t buffer_size = 0;
  VkImageUsageFlags image_usage = 0;
  VkBufferUsageFlags buffer_usage = 0;
  bool transient = true;  // false for outputs and retained resources, which get memory of their own
  bool output = false;
  uint32_t first_use = kNoPass;  // index into Plan::passes
  uint32_t last_use = kNoPass;
  MemoryRequirements memory;
  uint32_t block = kNoBlock;  // transient resources: which shared block, and where in it
  uint64_t offset = 0;
  AccessState final_state;  // after the last pass of the frame
  // A history resource (an input bound to "NAME@previous"): resource `previous_of` as the previous
  // frame left it, copied in before the frame's first pass (Granite's history inputs keep two
  // images and swap them; one copy a frame keeps every barrier static in the plan). All zero on a
  // plan's first frame and after a change of a scene part in `history_depends` (SceneDependency
  // bits: what the writers of `previous_of` depend on), when the passes that read it restart too.
  uint32_t previous_of = kNoResource;
  uint32_t history_depends = 0;
  // Its content carries from one frame to the next (a history resource and its source; in a plan
  // that reuses unchanged passes, every non-transient image): a frame's first barrier on it starts
  // from final_state, and the executor puts it there before the plan's first frame.
  bool kept_across_frames = false;

  bool used() const { return first_use != kNoPass; }
};

struct PlannedPass {
  std::string name;
  std::string type;
  std::string pointer;
  const PassTypeDecl* decl = nullptr;
  nlohmann::json params;  // every declared parameter, resolved (for the first frame)
  // Parameters given as expressions of the frame block (ParamDecl::per_frame): the executor
  // evaluates them before the pass records each frame, with Plan::expression_values.
  std::map<std::string, std::string> frame_params;
  std::map<std::string, uint32_t> ports;  // bound port -> resource index
  std::vector<PlannedBarrier> barriers;   // recorded before the pass
  // SceneDependency bits: its own and its inputs' writers', and those of any later pass that
  // rewrites what it wrote (which needs it to run first). Without kDependsOnFrame in a plan that
  // reuses unchanged passes, it runs only when one of these changed.
  uint32_t depends = kDependsOnFrame;
  // With kDependsOnLights, the lights whose changes it follows (bit K: light K): a per-light
  // instance's own light and what its inputs follow (graph/per_light.h); kAllLights otherwise.
  uint32_t lights = kAllLights;
  Instance instance;  // a per-light or per-view pass's instance
  bool reusable(bool plan_reuses) const { return plan_reuses && !(depends & kDependsOnFrame); }
  // With Plan::refines_apart: the pass moves a running result or writes what such a pass reads, and
  // runs in FramePart::refine frames; the others run in FramePart::display frames.
  bool refines = false;
  // With Plan::refines_apart, for a pass that does not refine: its number among those, in plan
  // order, by which a display frame shows in steps (DisplayStep).
  uint32_t showing = 0;
  // In a plan that reuses unchanged passes, for a reusable pass: everything its result follows
  // from besides the scene (its name, type and parameters, its ports' formats and extents, and the
  // identities of what it reads). A later plan's pass with an equal identity computes the same
  // images from the same scene, so the executor carries them over (a frame-budget step, an edit).
  std::optional<ResultIdentity> result_id;
  // In such a plan, for a pass that refines (a running mean, and the passes it reads that follow
  // the frame) and reads no history input: the same, without its sampling-only parameters
  // (ParamDecl::sampling_only), although the pass follows the frame. A later plan's pass with an
  // equal one continues the running result where this one left it (the hand-over of a plan
  // change): an exposure edit, a resize or a frame-budget step does not restart the mean, nor does
  // a plan in between (the viewer's while_moving values during an orbit), nor one that differs only
  // in sampling-only parameters.
  std::optional<ResultIdentity> running_id;
  // In a plan that refines apart, for a showing pass that follows the frame (it reads a running
  // result): its identity as running_id's. A later plan's pass with an equal one shows the same
  // running results as this one last did, so its images are carried over as a result's: a still
  // level's step (a sampling-only change) then goes on refining at once, its picture standing,
  // instead of showing it again in a frame of its own.
  std::optional<ResultIdentity> showing_id;
};

struct MemoryBlock {
  uint64_t size = 0;
  uint64_t alignment = 1;
  uint32_t type_bits = ~0u;
};

struct Plan {
  std::string graph_name;
  std::string graph_path;
  uint32_t output_width = 0;
  uint32_t output_height = 0;
  std::vector<PlannedPass> passes;    // execution order
  std::vector<std::string> culled;    // enabled passes that reach no output and have no side effect
  std::vector<std::string> disabled;  // passes whose "enabled" is 0 for this scene and these parameters
  // Each disabled pass's "enabled" as it was evaluated: a per-light instance's with its light's
  // names ("scene.light2.objects": light 2 reaches no object), so that a plan says why.
  std::map<std::string, std::string> disabled_by;
  // Every instance of a per-light or per-view pass (graph/per_light.h), planned or not: whose it is.
  std::map<std::string, Instance> instances;
  std::map<std::string, std::string> fallbacks;  // resource -> the resource read in its place
  std::vector<std::string> warnings;  // what compiles but will not do what the graph is for (a caustic pass lit by a point light)
  // Passes that trace the scene's exact geometry, and the tracer they all use (none without any):
  // the executor builds that tracer's structures for the scene.
  std::vector<std::string> traced_passes;
  Tracer tracer = Tracer::none;
  std::vector<PlannedResource> resources;
  // The types of the graph's user passes ("compute", "fullscreen"), one per pass, made from the file
  // and their shaders: PlannedPass::decl points here for them.
  std::vector<std::shared_ptr<const PassTypeDecl>> user_types;
  // What the expressions of PlannedPass::frame_params name besides the frame block: the output
  // size, the scene's values and the graph's parameters, as compiled.
  std::map<std::string, double> expression_values;
  std::vector<MemoryBlock> blocks;
  std::vector<uint32_t> outputs;  // resource indices, in the graph's order
  uint64_t transient_bytes_aliased = 0;
  uint64_t transient_bytes_unaliased = 0;
  // The most transient bytes alive at once over the order: no placement can use less.
  uint64_t transient_bytes_lifetime_bound = 0;
  uint64_t persistent_bytes = 0;
  // Compiled with CompileOptions::reuse_unchanged_passes: what the reusable passes write is kept
  // from frame to frame (persistent), so that the executor may skip them.
  bool reuses_unchanged_passes = false;
  // A pass asks for the camera to move within its pixels from frame to frame while it stands still
  // (PassTypeDecl::jitters_camera): the passes that see the camera then depend on the frame too.
  bool jitters_camera = false;
  // In a plan that reuses unchanged passes, with a pass that accumulates (PassTypeDecl::accumulates
  // or a history input): the passes that refine its running result can run without those that show
  // it, every resource that the showing passes read from the refining ones being kept. The viewer
  // at rest then refines for several frames within its budget for each frame that shows the result.
  bool refines_apart = false;

  int find_resource(std::string_view name) const;
  // `name`, or the resource read in its place when it fell back; a per-light resource's own name is
  // light 0's instance ("caustics" -> "caustics#0").
  std::string resolve(const std::string& name) const;
};

nlohmann::json plan_to_json(const Plan& plan);
std::string plan_to_dot(const Plan& plan);

std::string stage_names(VkPipelineStageFlags2 stages);
std::string access_names(VkAccessFlags2 access);
std::string layout_name(VkImageLayout layout);

}  // namespace caustica::graph
