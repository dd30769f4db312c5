#pragma once
// The scene's acceleration structures, for passes that trace exact paths with ray queries: one
// bottom-level structure per object, its triangles sorted first (scene/bvh_order.h), and a
// top-level structure with one instance per object. Meshes are already in world space, so every
// instance has the identity transform; its custom index is the object's first triangle in
// triangles(), whose entries index the GpuScene's vertex buffer (normals, object index).
#include <cstdint>
#include <vector>

#include "scene/scene.h"
#include "vk/buffer.h"

namespace caustica::scene {

// Owns a VkAccelerationStructureKHR; destroyed through the Context's deferred queue like every
// other Vulkan object (the destroy call is an extension entry point, so Owned<> cannot name it).
class OwnedAccelerationStructure {
 public:
  OwnedAccelerationStructure() = default;
  OwnedAccelerationStructure(vk::Context& vk, VkAccelerationStructureKHR handle) : vk_(&vk), handle_(handle) {}
  ~OwnedAccelerationStructure() { reset(); }
  OwnedAccelerationStructure(OwnedAccelerationStructure&& other) noexcept;
  OwnedAccelerationStructure& operator=(OwnedAccelerationStructure&& other) noexcept;
  OwnedAccelerationStructure(const OwnedAccelerationStructure&) = delete;
  OwnedAccelerationStructure& operator=(const OwnedAccelerationStructure&) = delete;
  VkAccelerationStructureKHR get() const { return handle_; }
  void reset();

 private:
  vk::Context* vk_ = nullptr;
  VkAccelerationStructureKHR handle_ = VK_NULL_HANDLE;
};

// What AccelerationStructures would hold for a scene, known without a device: the build inputs
// exactly, the structures at lavapipe 25's measured layout (104 bytes per triangle, 176 per
// instance). Other drivers size their structures differently; `--stats` reports the driver's own.
struct AccelerationEstimate {
  uint64_t triangles = 0, instances = 0;
  uint64_t input_bytes = 0;      // positions, sorted triangle list, instances
  uint64_t structure_bytes = 0;  // bottom and top levels
  uint64_t total() const { return input_bytes + structure_bytes; }
};
AccelerationEstimate estimate_acceleration(const Scene& scene);

class AccelerationStructures {
 public:
  // `vertex_base[o]`: where object o's vertices start in the GpuScene's vertex buffer. Throws
  // DeviceError when the device has no ray queries.
  AccelerationStructures(vk::Context& vk, const Scene& scene, const std::vector<uint32_t>& vertex_base);

  VkAccelerationStructureKHR tlas() const { return tlas_.structure.get(); }
  // Three uint32 per triangle: vertex indices into the GpuScene's vertex buffer, each object's
  // triangles in build order.
  VkBuffer triangles() const { return triangles_.get(); }
  // Device memory held: structures, their inputs and the triangle list (scratch is released).
  uint64_t bytes() const { return bytes_; }
  double sort_ms() const { return sort_ms_; }    // host: ordering triangles
  double build_ms() const { return build_ms_; }  // building on the device, waited for

 private:
  struct Level {
    vk::Buffer storage;
    OwnedAccelerationStructure structure;
  };
  std::vector<Level> blas_;
  Level tlas_;
  vk::Buffer positions_, triangles_, instances_;
  uint64_t bytes_ = 0;
  double sort_ms_ = 0, build_ms_ = 0;
};

}  // namespace caustica::scene
