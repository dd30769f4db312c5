#pragma once
// Drawing refractor front and back surfaces, shared by refractor_buffers (all refractors at once)
// and refraction_layers (one refractor per layer).
#include "scene_draw.h"

namespace caustica::passes {

class RefractorSurfaces {
 public:
  struct Targets {
    VkExtent2D extent;
    VkImageView front, back, front_depth, back_depth;
  };
  // `front` and `front_depth` name ports whose formats the pipelines are built for.
  void setup(graph::PassSetup& setup, const std::string& front, const std::string& front_depth);
  // Clears the targets and draws `range` into them from `view`.
  void record(graph::PassContext& ctx, const SceneView& view, scene::DrawRange range, const Targets& targets, bool back_only = false);

 private:
  vk::Pipeline pipelines_[2];  // front faces, back faces
};

}  // namespace caustica::passes
