#pragma once
// A scene on the device: one vertex buffer and one index buffer for every object (opaque objects
// first, then solid refractors, then thin-walled ones, each object a contiguous index range), object materials, and per-frame
// data (camera, lights) that run_frame() refreshes before recording.
#include <memory>
#include <utility>
#include <vector>

#include "common/scene_types.h"  // shaders/ is on the include path: the layouts GLSL sees
#include "scene/acceleration.h"
#include "scene/gpu_textures.h"
#include "scene/scene.h"
#include "vk/buffer.h"

namespace caustica::scene {

struct DrawRange {
  uint32_t first_index = 0;
  uint32_t index_count = 0;
};

// `view_proj` with its image moved by `pixels` on a `size` (in pixels) target.
glm::mat4 shifted_by_pixels(const glm::mat4& view_proj, glm::vec2 pixels, glm::vec2 size);

class GpuScene {
 public:
  GpuScene(vk::Context& vk, std::shared_ptr<const Scene> scene);

  // Its objects and textures; its camera and lights as loaded (camera() and lights() are those in use).
  const Scene& scene() const { return *scene_; }
  const View& camera() const { return camera_; }
  const std::vector<Light>& lights() const { return lights_; }
  // The caustic views of lights() (scene::caustic_views): FrameData::caustic_lights.
  const std::vector<CausticView>& caustic_views() const { return views_; }
  // The same objects and textures seen with another camera or other lights (a viewer's move, as
  // many lights as the scene has): nothing is uploaded again, nothing of the scene copied.
  void replace_view(const View& camera, std::vector<Light> lights);
  VkBuffer vertices() const { return vertices_.get(); }
  VkBuffer indices() const { return indices_.get(); }
  VkBuffer objects() const { return objects_.get(); }
  // The translucent surfaces' patches (scene/translucent_samples.h; FrameData::translucent_samples of them).
  VkBuffer translucent_samples() const { return translucent_.get(); }
  VkBuffer frame() const { return frame_.get(); }
  // Set 1 of pipelines made with PipelineDesc::texture_array = CAUSTICA_MAX_TEXTURES.
  VkDescriptorSet textures() const { return textures_.set(); }
  uint64_t texture_bytes() const { return textures_.bytes(); }

  DrawRange opaque() const { return opaque_; }
  DrawRange refractors() const { return refractors_; }  // solid ones first, then thin_refractors()
  DrawRange thin_refractors() const { return thin_refractors_; }
  // `range` (within the refractors) cut into its solid part and its thin-walled part.
  std::pair<DrawRange, DrawRange> split_thin(DrawRange range) const;
  DrawRange object(uint32_t index) const { return ranges_[index]; }
  // Indices into scene().objects of the refractors, farthest from `eye` first (by bounding-box centre).
  std::vector<uint32_t> refractors_back_to_front(glm::vec3 eye) const;

  // The scene's acceleration structures, built on first request (the executor asks when a plan has a
  // pass that traces with ray queries), so that a graph without one never pays for them.
  const AccelerationStructures& acceleration();
  const AccelerationStructures* built_acceleration() const { return acceleration_.get(); }
  // The compute tracer's BVH (scene/bvh.h) on the device, built on first request likewise.
  struct TracerBuffers {
    vk::Buffer bvh, triangles;  // the shaders' BvhBlock and TriangleBlock
    uint64_t bytes = 0;
    double build_ms = 0;  // on the host, with the upload
    uint32_t nodes = 0, depth = 0;
  };
  const TracerBuffers& tracer_bvh();
  const TracerBuffers* built_tracer_bvh() const { return tracer_bvh_.get(); }

  // Writes camera and light data for an output of this size; call before recording a frame.
  void update_frame(uint32_t width, uint32_t height);
  // Moves the camera's image by `pixels` (each axis within half a pixel) for the frame that
  // update_frame() set up, as a still camera's frames are moved within their pixels to be averaged
  // (temporal_mean); passes that draw from the camera move their own projection alike
  // (shifted_by_pixels with graph::FrameInfo::camera_jitter). The camera's key (parts_key) stays the
  // unmoved camera's.
  void jitter_camera(glm::vec2 pixels);
  // A hash of the chosen parts as of the last update_frame(): geometry (with materials and
  // textures), lights, camera (with the sky and the output size). What a pass that depends on just
  // those parts is skipped by while it does not change, and what restarts its history.
  uint64_t parts_key(bool geometry, bool lights, bool camera) const;
  // Each light's key alone, as of the last update_frame(): what a per-light pass follows.
  const std::vector<uint64_t>& light_keys() const { return light_keys_; }
  const gpu::FrameData& frame_data() const { return frame_data_; }

 private:
  vk::Context& vk_;
  std::shared_ptr<const Scene> scene_;
  View camera_;
  std::vector<Light> lights_;
  std::vector<CausticView> views_;
  GpuTextures textures_;
  std::vector<uint32_t> vertex_base_;  // per object: its first vertex in vertices_
  std::unique_ptr<AccelerationStructures> acceleration_;
  std::unique_ptr<TracerBuffers> tracer_bvh_;
  vk::Buffer vertices_, indices_, objects_, translucent_, frame_;
  DrawRange opaque_, refractors_, thin_refractors_;
  std::vector<DrawRange> ranges_;
  gpu::FrameData frame_data_{};
  uint64_t content_key_ = 0;  // geometry, materials and textures, as uploaded
  uint64_t lights_key_ = 0, camera_key_ = 0;
  std::vector<uint64_t> light_keys_;
};

}  // namespace caustica::scene
