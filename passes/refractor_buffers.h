#pragma once
// Drawing refractor front and back surfaces, shared by refractor_buffers (all refractors at once)
// and refraction_layers (one refractor per layer).
#include <array>

#include "scene_draw.h"

namespace caustica::passes {

class RefractorSurfaces {
 public:
  struct Targets {
    VkExtent2D extent;
    VkImageView front, back, front_depth;
    VkImage front_depth_image;
    VkImageView back_depth;    // VK_NULL_HANDLE: the back draw clears and reuses front_depth
    VkImageView front_tint;    // VK_NULL_HANDLE: not drawn (the optional front_tint port unbound)
    VkImageView front_layers;  // likewise for front_layers
  };
  // The pass's ports front, back, front_depth and (optional) back_depth, front_tint and front_layers.
  static Targets targets(graph::PassContext& ctx);
  // The optional back_depth port: without it the two draws share one depth image.
  static graph::PortDecl back_depth_port(const char* extent_group);
  // The optional front_tint port: the front surface's tint (rgb) and transmission (a) per texel,
  // from the material's textures, for the image-space methods to read (without it they take each
  // material's means).
  static graph::PortDecl front_tint_port(graph::PortAccess access, graph::PortUsage usage, const char* extent_group);
  // The optional front_layers port: the front surface's interface layers per texel (the texels of
  // KHR_materials_specular's, _clearcoat's and _iridescence's textures), likewise.
  static graph::PortDecl front_layers_port(graph::PortAccess access, graph::PortUsage usage, const char* extent_group);
  // The optional ports that carry the front surface's texels, in the order the pipelines write them.
  static constexpr std::array<const char*, 2> kTexelPorts{"front_tint", "front_layers"};
  // `front` and `front_depth` name ports whose formats the pipelines are built for.
  void setup(graph::PassSetup& setup, const std::string& front, const std::string& front_depth);
  // Clears the targets and draws `range` into them from `view`.
  void record(graph::PassContext& ctx, const SceneView& view, scene::DrawRange range, const Targets& targets, bool back_only = false);

 private:
  vk::Pipeline pipelines_[3];  // front faces, back faces, thin-walled refractors' front (no culling)
  // With front_tint or front_layers bound: the front and thin pipelines that also draw what is
  // bound of them, used where the scene has a refractor whose tint or interface layers vary (the
  // others never read them: at_front_texel).
  vk::Pipeline per_texel_[2];
};

}  // namespace caustica::passes
