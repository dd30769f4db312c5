#pragma once
// The resource inspector: any image of the graph (G-buffer normals, light-view buffers, the caustic
// map and its levels) with an exposure, fitted into its panel or in place of the output.
#include <vulkan/vulkan_core.h>

#include <optional>
#include <string>

#include "graph/plan.h"
#include "io/image_io.h"

namespace caustica::editor {

class Inspector {
 public:
  // Draws the panel (ImGui); returns the image the user chose when they chose another one. The
  // panel's image itself is copied into the window before the UI draws (ImGui 1.86's Vulkan
  // backend samples only its font), so the panel has no background where the image lies.
  std::optional<std::string> draw(const graph::Plan& plan, const io::ImageData& image, float window_width);
  // The exposure that shows the image's brightest texel (any colour channel) at white.
  void expose_to_fit(const io::ImageData& image);

  std::string inspected;  // empty: nothing chosen
  bool open = false, in_main_view = false;
  bool fit_exposure = false;  // once the next frame with the image is read back
  float exposure_stops = 0.0f;
  VkRect2D panel{};  // where the image goes this frame, in window pixels; empty: nowhere
};

// `image` resampled to width x height: each target texel averages the source texels it covers
// (the nearest one when enlarging), so a fine caustic is not lost between sampled texels.
io::ImageData fit_image(const io::ImageData& image, uint32_t width, uint32_t height);

}  // namespace caustica::editor
