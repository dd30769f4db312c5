#pragma once
// Points over the scene's translucent surfaces (opaque objects with KHR_materials_diffuse_transmission)
// from which the lighting pass gathers the light they pass on to what lies behind them: each a small
// patch of a surface, its share of the area, its geometric normal, its object and what it passes
// (its textures' texels where it lies; docs/gltf.md, "Diffuse transmission").
#include <cstdint>
#include <vector>

#include "common/scene_types.h"  // shaders/ is on the include path: the layout GLSL sees
#include "scene/scene.h"

namespace caustica::scene {

// The patches over every translucent surface together: the lighting pass gathers from each at
// every pixel, so their count is its cost (docs/gltf.md measures it).
inline constexpr uint32_t kTranslucentSamples = 64;

// Stratified over the translucent surfaces' area: patch k of K lies in the triangle that holds the
// area fraction (k + 0.5) / K, at a point of it from the R2 sequence folded onto the triangle, and
// stands for a K-th of the area. None without a translucent surface.
std::vector<gpu::TranslucentSample> translucent_samples(const Scene& scene);

}  // namespace caustica::scene
