#include "refraction.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <utility>

#include "core/error.h"
#include "graph/user_pass_type.h"

namespace caustica::passes {

std::vector<graph::ParamDecl> refraction_params() {
  using graph::ParamType;
  return {{"distance",
           ParamType::choice,
           "dv_dn",
           {},
           {},
           {"dv", "dv_dn", "search"},
           "distance to the back surface: d_V (along the view ray), Wyman's d_V/d_N blend by refraction angle, or search (an "
           "image-space search along the refracted ray against the back-surface buffer, from the blend)"},
          {"search_steps", ParamType::int_, 48, 4.0, 512.0, {}, "linear steps of the background search along the exit ray"},
          {"search_distance",
           ParamType::float_,
           0.0,
           0.0,
           1e6,
           {},
           "how far the background search goes, in scene units; 0: the diagonal of the box around the scene, so that a ray finds "
           "whatever it meets in the scene, however large"}};
}

std::vector<graph::ParamDecl> with_search_bounces(std::vector<graph::ParamDecl> params) {
  params.push_back({"search_bounces",
                    graph::ParamType::int_,
                    3,
                    0.0,
                    8.0,
                    {},
                    "search: total internal reflections followed inside a refractor, each found by another search (Davis and Wyman "
                    "2007); light still inside after them is dropped, as d_V and d_V/d_N drop it at the first"});
  return params;
}

std::vector<graph::ParamDecl> exact_path_params(const std::string& what) {
  using graph::ParamType;
  auto params = with_search_bounces(refraction_params());
  params[0].choices = {"dv", "dv_dn", "search", "ray_query", "hybrid", "material"};
  params[0].description =
      "where " + what +
      " leaves the refractor: d_V or the d_V/d_N blend (estimates), search (image-space search along the "
      "refracted ray against the back-surface buffer, from the blend; every device), ray_query (traced exactly through the scene, by "
      "ray queries or the compute tracer: every device), or hybrid (the search, traced exactly where it cannot be trusted: total "
      "internal reflection at the exit, no back surface there, an exit point off the back surface by more than hybrid_tolerance, or "
      "another refractor in the way), or material (chosen from the material it meets first: traced exactly through a solid "
      "refractor, in image space through a thin wall, where image space is exact)";
  params.push_back({"max_interfaces",
                    ParamType::int_,
                    32,
                    1.0,
                    64.0,
                    {},
                    "exact paths: refractor interfaces a ray may cross before it counts as trapped"});
  params.push_back(
      {"hybrid_tolerance",
       ParamType::float_,
       0.05,
       0.0,
       10.0,
       {},
       "hybrid: how far the estimated exit point may lie off the back surface, as a fraction of the distance travelled inside"});
  return params;
}

namespace {
float search_distance(const graph::PassContext& ctx) {
  const float chosen = ctx.params()["search_distance"].get<float>();
  if (chosen > 0.0f) return chosen;
  return std::max(ctx.scene().scene().diagonal(), 1e-3f);
}

// A pass's `distance`, numbered as shaders/refraction/refraction.glsl's DISTANCE_* constants.
enum DistanceMode : uint32_t { kDv, kDvDn, kRayQuery, kHybrid, kSearch, kMaterial };
DistanceMode distance_mode(const nlohmann::json& params) {
  const std::string distance = params.value("distance", std::string());
  return distance == "dv"          ? kDv
         : distance == "dv_dn"     ? kDvDn
         : distance == "ray_query" ? kRayQuery
         : distance == "hybrid"    ? kHybrid
         : distance == "search"    ? kSearch
                                   : kMaterial;
}
}  // namespace

RefractionPush refraction_push(const graph::PassContext& ctx, uint32_t tir_counter, uint32_t exact_counters) {
  const auto& p = ctx.params();
  return {distance_mode(p),
          p["search_steps"].get<uint32_t>() | p.value("search_bounces", 0u) << 16,
          search_distance(ctx),
          tir_counter,
          p.value("max_interfaces", 1u),
          ctx.scene().scene().ray_epsilon(),
          p.value("hybrid_tolerance", 0.0f),
          exact_counters};
}

std::vector<shader::MirroredMember> refraction_push_members(size_t at) {
  return {{"distance_mode", at + offsetof(RefractionPush, distance_mode)},
          {"search", at + offsetof(RefractionPush, search)},
          {"search_distance", at + offsetof(RefractionPush, search_distance)},
          {"tir_counter", at + offsetof(RefractionPush, tir_counter)},
          {"exact_max_interfaces", at + offsetof(RefractionPush, exact_max_interfaces)},
          {"exact_epsilon", at + offsetof(RefractionPush, exact_epsilon)},
          {"hybrid_tolerance", at + offsetof(RefractionPush, hybrid_tolerance)},
          {"exact_counters", at + offsetof(RefractionPush, exact_counters)}};
}

bool traces_exact_paths(const nlohmann::json& params) {
  const std::string distance = params.value("distance", std::string());
  return distance == "ray_query" || distance == "hybrid" || distance == "material";
}

uint32_t add_consecutive_counters(graph::PassSetup& setup,
                                  const std::vector<std::pair<std::string, graph::PassSetup::CounterKind>>& names) {
  uint32_t first = 0;
  for (size_t i = 0; i < names.size(); ++i) {
    const uint32_t slot = setup.add_counter(names[i].first, names[i].second);
    if (i == 0) first = slot;
    if (slot != first + i)
      throw DeviceError("pass '" + setup.pass().name + "': its counters '" + names[0].first + "'... are not consecutive");
  }
  return first;
}

void TracedScene::setup(const graph::PassSetup& setup) {
  traced_ = traces_exact_paths(setup.pass().params);
  tracer_ = setup.tracer();
  mode_ = distance_mode(setup.pass().params);
  layer_textures_ = setup.scene_value("scene.layer_textures") > 0.0;
}

shader::Defines TracedScene::defines(shader::Defines defines) const {
  if (!traced_) return defines;
  defines["CAUSTICA_RAY_QUERY"] = "1";
  if (tracer_ == graph::Tracer::compute) defines["CAUSTICA_COMPUTE_TRACER"] = "1";
  if (mode_ == kHybrid) defines["CAUSTICA_HYBRID"] = "1";
  // The layers' textures per texel only where the scene has them: reading them lengthened the
  // exact kernels' cold compile on lavapipe by about a tenth.
  if (layer_textures_) defines["CAUSTICA_LAYER_TEXTURES"] = "1";
  defines["CAUSTICA_DISTANCE_MODE"] = std::to_string(mode_) + "u";
  return defines;
}

void TracedScene::bind(const graph::PassContext& ctx, vk::DescriptorWriter& writer) const {
  if (!traced_) return;
  if (tracer_ == graph::Tracer::compute) {
    const auto* bvh = ctx.scene().built_tracer_bvh();
    assert(bvh && "the executor builds the scene's BVH for every plan that traces with the compute tracer");
    writer.buffer("BvhBlock", bvh->bvh.get()).buffer("TriangleBlock", bvh->triangles.get());
    return;
  }
  const auto* acceleration = ctx.scene().built_acceleration();
  assert(acceleration && "the executor builds the scene's acceleration structures for every plan with a ray-query pass");
  writer.structure("scene_tlas", acceleration->tlas()).buffer("TriangleBlock", acceleration->triangles());
}

void TracedScene::bind_textures(const graph::PassContext& ctx, const vk::Pipeline& pipeline) const {
  if (traced_) bind_scene_textures(ctx, ctx.cmd(), pipeline);
}

shader::Defines refraction_defines(const graph::PassSetup& setup, shader::Defines defines) {
  if (setup.bound("front_tint")) defines["REFRACTOR_TINT"] = "1";
  if (setup.bound("front_layers")) defines["REFRACTOR_LAYERS"] = "1";
  return defines;
}

void bind_front_texels(const graph::PassContext& ctx, vk::DescriptorWriter& writer) {
  if (ctx.bound("front_tint")) writer.image("front_tint_tex", ctx.view("front_tint"), ctx.nearest_sampler());
  if (ctx.bound("front_layers")) writer.image("front_layers_tex", ctx.view("front_layers"), ctx.nearest_sampler());
}

std::vector<graph::PortDecl> refraction_inputs() {
  using namespace graph;
  return {{"background", PortAccess::read, ResourceKind::image, PortUsage::sampled, {}, false, "frame", "radiance behind the refractors"},
          {"depth", PortAccess::read, ResourceKind::image, PortUsage::sampled, {Format::d32f}, false, "frame", "depth of the background"}};
}

vk::Pipeline make_copy_pipeline(graph::PassSetup& setup, VkFormat color) {
  vk::RasterState state;
  state.color_formats = {color};
  return setup.graphics_pipeline("copy_background", {"common/fullscreen.vert", {}}, {"common/copy.frag", {}}, state);
}

void record_copy(const graph::PassContext& ctx, const vk::Pipeline& copy, VkImageView source, VkImageView target, VkExtent2D extent) {
  VkCommandBuffer cmd = ctx.cmd();
  begin_rendering(cmd, extent, {{target, VK_ATTACHMENT_LOAD_OP_DONT_CARE}}, std::nullopt);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_GRAPHICS, copy.pipeline.get());
  vk::DescriptorWriter().image("source", source, ctx.nearest_sampler()).push(ctx.vk(), cmd, copy);
  vkCmdDraw(cmd, 3, 1, 0, 0);
  vkCmdEndRendering(cmd);
}

vk::DescriptorWriter refraction_descriptors(const graph::PassContext& ctx, const vk::Pipeline& pipeline, VkImageView background,
                                            VkImageView back, const TracedScene* exact) {
  vk::DescriptorWriter writer = scene_descriptors(ctx, pipeline);
  writer.image("background_tex", background, ctx.linear_sampler())
      .image("depth_tex", ctx.view("depth"), ctx.nearest_sampler())
      .image("back_tex", back, ctx.nearest_sampler())
      .buffer("CounterBlock", ctx.counter_buffer());
  if (exact) exact->bind(ctx, writer);
  bind_front_texels(ctx, writer);
  return writer;
}

VkRect2D screen_rect(const scene::Scene& scene, const glm::mat4& view_proj, const std::vector<uint32_t>& objects, VkExtent2D extent) {
  const VkRect2D full{{0, 0}, extent};
  glm::vec2 lo(1e30f), hi(-1e30f);
  for (uint32_t index : objects) {
    const auto& o = scene.objects[index];
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 p((corner & 1) ? o.bounds_max.x : o.bounds_min.x, (corner & 2) ? o.bounds_max.y : o.bounds_min.y,
                        (corner & 4) ? o.bounds_max.z : o.bounds_min.z);
      const glm::vec4 clip = view_proj * glm::vec4(p, 1.0f);
      if (clip.w <= 1e-6f) return full;
      const glm::vec2 pixel = (glm::vec2(clip) / clip.w * 0.5f + 0.5f) * glm::vec2(extent.width, extent.height);
      lo = glm::min(lo, pixel);
      hi = glm::max(hi, pixel);
    }
  }
  const auto clamp_to = [](float v, uint32_t size) { return static_cast<int32_t>(std::clamp(v, 0.0f, static_cast<float>(size))); };
  const int32_t x0 = clamp_to(std::floor(lo.x) - 1, extent.width), y0 = clamp_to(std::floor(lo.y) - 1, extent.height);
  const int32_t x1 = clamp_to(std::ceil(hi.x) + 1, extent.width), y1 = clamp_to(std::ceil(hi.y) + 1, extent.height);
  if (x1 <= x0 || y1 <= y0) return {{0, 0}, {0, 0}};
  return {{x0, y0}, {static_cast<uint32_t>(x1 - x0), static_cast<uint32_t>(y1 - y0)}};
}

namespace {
// shaders/refraction/deferred_refraction.comp's push block.
struct DeferredRefractionPush {
  RefractionPush refraction;
  int32_t rect[4];  // x0, y0, x1, y1
};
struct CopyPush {  // shaders/common/copy.comp's
  int32_t size[2];
};
}  // namespace

void DeferredRefractionShading::setup(graph::PassSetup& setup, graph::Format target, const TracedScene* exact) {
  exact_ = exact;
  const shader::Defines out_format{{"OUT_FORMAT", graph::format_info(target).glsl_qualifier}};
  refract_ = setup.compute_pipeline("deferred_refraction", {"refraction/deferred_refraction.comp",
                                                            refraction_defines(setup, exact ? exact->defines(out_format) : out_format)});
  std::vector<shader::MirroredMember> members = refraction_push_members(offsetof(DeferredRefractionPush, refraction));
  members.push_back(CAUSTICA_MIRRORED(DeferredRefractionPush, rect));
  refract_.interface->check_push("DeferredRefractionPush", sizeof(DeferredRefractionPush), members);
  copy_ = setup.compute_pipeline("copy_background", {"common/copy.comp", out_format});
  copy_.interface->check_push("CopyPush", sizeof(CopyPush), {CAUSTICA_MIRRORED(CopyPush, size)});
}

void DeferredRefractionShading::record(const graph::PassContext& ctx, const RefractionPush& push, VkImageView background, VkImageView front,
                                       VkImageView back, VkImageView target, VkExtent2D extent, VkRect2D rect) const {
  copy(ctx, background, target, extent);
  if (rect.extent.width == 0 || rect.extent.height == 0) return;
  VkCommandBuffer cmd = ctx.cmd();
  // The refracted pixels overwrite the copy's.
  vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT,
                     VK_PIPELINE_STAGE_2_COMPUTE_SHADER_BIT, VK_ACCESS_2_SHADER_STORAGE_WRITE_BIT);
  vkCmdBindPipeline(cmd, VK_PIPELINE_BIND_POINT_COMPUTE, refract_.pipeline.get());
  vk::DescriptorWriter writer = refraction_descriptors(ctx, refract_, background, back, exact_);
  writer.image("front_tex", front, ctx.nearest_sampler()).image("out_color", target).push(ctx.vk(), cmd, refract_);
  if (exact_) exact_->bind_textures(ctx, refract_);
  const DeferredRefractionPush shading{push,
                                       {rect.offset.x, rect.offset.y, rect.offset.x + static_cast<int32_t>(rect.extent.width),
                                        rect.offset.y + static_cast<int32_t>(rect.extent.height)}};
  vkCmdPushConstants(cmd, refract_.layout.get(), refract_.stages, 0, sizeof(shading), &shading);
  vkCmdDispatch(cmd, (rect.extent.width + 7) / 8, (rect.extent.height + 7) / 8, 1);
}

void DeferredRefractionShading::copy(const graph::PassContext& ctx, VkImageView source, VkImageView target, VkExtent2D extent) const {
  const CopyPush size{{static_cast<int32_t>(extent.width), static_cast<int32_t>(extent.height)}};
  vk::dispatch_over_image(ctx.vk(), ctx.cmd(), copy_,
                          vk::DescriptorWriter().image("source", source, ctx.nearest_sampler()).image("target", target), vk::bytes_of(size),
                          extent);
}

}  // namespace caustica::passes
