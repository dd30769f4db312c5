#include "scene/acceleration.h"

#include <chrono>
#include <cstring>
#include <utility>

#include "common/scene_types.h"  // the instance masks the shaders ask for
#include "core/error.h"
#include "scene/bvh_order.h"

namespace caustica::scene {

OwnedAccelerationStructure::OwnedAccelerationStructure(OwnedAccelerationStructure&& other) noexcept
    : vk_(other.vk_), handle_(std::exchange(other.handle_, VK_NULL_HANDLE)) {}

OwnedAccelerationStructure& OwnedAccelerationStructure::operator=(OwnedAccelerationStructure&& other) noexcept {
  if (this != &other) {
    reset();
    vk_ = other.vk_;
    handle_ = std::exchange(other.handle_, VK_NULL_HANDLE);
  }
  return *this;
}

void OwnedAccelerationStructure::reset() {
  if (handle_ == VK_NULL_HANDLE) return;
  const auto destroy = vk_->rt.destroy;
  vk_->defer([destroy, handle = handle_](VkDevice device) { destroy(device, handle, nullptr); });
  handle_ = VK_NULL_HANDLE;
}

namespace {

constexpr VkBufferUsageFlags kBuildInput =
    VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_BUILD_INPUT_READ_ONLY_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT;

double ms_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

VkDeviceSize align_up(VkDeviceSize v, VkDeviceSize alignment) {
  return (v + alignment - 1) / alignment * alignment;
}

// One object's triangles: where they start in the sorted triangle list, and how many.
struct ObjectTriangles {
  uint32_t object, first_triangle, triangle_count;
};

// The build inputs: positions in the vertex buffer's order, triangles sorted per object (see bvh_order.h).
struct BuildInput {
  std::vector<glm::vec3> positions;
  std::vector<uint32_t> triangles;
  std::vector<ObjectTriangles> objects;
};

BuildInput sorted_build_input(const Scene& scene, const std::vector<uint32_t>& vertex_base) {
  BuildInput in;
  uint32_t vertex_count = 0;
  for (uint32_t o = 0; o < scene.objects.size(); ++o) vertex_count += static_cast<uint32_t>(scene.objects[o].mesh.positions.size());
  in.positions.resize(vertex_count);
  for (uint32_t o = 0; o < scene.objects.size(); ++o) {
    const Mesh& mesh = scene.objects[o].mesh;
    std::copy(mesh.positions.begin(), mesh.positions.end(), in.positions.begin() + vertex_base[o]);
    if (mesh.indices.empty()) continue;
    in.objects.push_back({o, static_cast<uint32_t>(in.triangles.size() / 3), static_cast<uint32_t>(mesh.indices.size() / 3)});
    for (uint32_t index : bvh_triangle_order(mesh.positions, mesh.indices)) in.triangles.push_back(vertex_base[o] + index);
  }
  return in;
}

VkDeviceSize scratch_alignment_of(vk::Context& vk) {
  VkPhysicalDeviceAccelerationStructurePropertiesKHR as_properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_ACCELERATION_STRUCTURE_PROPERTIES_KHR};
  VkPhysicalDeviceProperties2 properties{VK_STRUCTURE_TYPE_PHYSICAL_DEVICE_PROPERTIES_2};
  properties.pNext = &as_properties;
  vkGetPhysicalDeviceProperties2(vk.physical_device(), &properties);
  return std::max<VkDeviceSize>(as_properties.minAccelerationStructureScratchOffsetAlignment, 256);
}

// A build of one level from one geometry, for the fastest tracing.
VkAccelerationStructureBuildGeometryInfoKHR build_of(VkAccelerationStructureTypeKHR type,
                                                     const VkAccelerationStructureGeometryKHR* geometry) {
  VkAccelerationStructureBuildGeometryInfoKHR build{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_GEOMETRY_INFO_KHR};
  build.type = type;
  build.flags = VK_BUILD_ACCELERATION_STRUCTURE_PREFER_FAST_TRACE_BIT_KHR;
  build.mode = VK_BUILD_ACCELERATION_STRUCTURE_MODE_BUILD_KHR;
  build.geometryCount = 1;
  build.pGeometries = geometry;
  return build;
}

// An object's triangles as a bottom level's geometry. A MASK material's geometry is tested by the
// shaders (ray_query.glsl's confirm_if_covered), so it is not opaque.
VkAccelerationStructureGeometryKHR triangle_geometry(const ObjectTriangles& object, bool masked, VkDeviceAddress positions,
                                                     VkDeviceAddress triangles, uint32_t vertex_count) {
  VkAccelerationStructureGeometryKHR geometry{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  geometry.geometryType = VK_GEOMETRY_TYPE_TRIANGLES_KHR;
  geometry.flags = masked ? VK_GEOMETRY_NO_DUPLICATE_ANY_HIT_INVOCATION_BIT_KHR : VK_GEOMETRY_OPAQUE_BIT_KHR;
  auto& tris = geometry.geometry.triangles;
  tris = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_TRIANGLES_DATA_KHR};
  tris.vertexFormat = VK_FORMAT_R32G32B32_SFLOAT;
  tris.vertexData.deviceAddress = positions;
  tris.vertexStride = sizeof(glm::vec3);
  tris.maxVertex = vertex_count - 1;
  tris.indexType = VK_INDEX_TYPE_UINT32;
  tris.indexData.deviceAddress = triangles + VkDeviceSize{object.first_triangle} * 3 * sizeof(uint32_t);
  return geometry;
}

// The top level's instance of a bottom level: identity transform, custom index = its first triangle.
VkAccelerationStructureInstanceKHR instance_of(vk::Context& vk, VkAccelerationStructureKHR blas, uint32_t first_triangle, bool refractor) {
  VkAccelerationStructureDeviceAddressInfoKHR address{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_DEVICE_ADDRESS_INFO_KHR};
  address.accelerationStructure = blas;
  VkAccelerationStructureInstanceKHR instance = {};
  instance.transform.matrix[0][0] = instance.transform.matrix[1][1] = instance.transform.matrix[2][2] = 1.0f;
  instance.instanceCustomIndex = first_triangle;
  instance.mask = refractor ? CAUSTICA_REFRACTOR_INSTANCES : CAUSTICA_RECEIVER_INSTANCES;
  instance.flags = VK_GEOMETRY_INSTANCE_TRIANGLE_FACING_CULL_DISABLE_BIT_KHR;
  instance.accelerationStructureReference = vk.rt.address(vk.device(), &address);
  return instance;
}

// The bottom levels in one call, then (after a barrier) the top level; waited for.
void record_builds(vk::Context& vk, const std::vector<VkAccelerationStructureBuildGeometryInfoKHR>& blas_builds,
                   const std::vector<VkAccelerationStructureBuildRangeInfoKHR>& blas_ranges,
                   const VkAccelerationStructureBuildGeometryInfoKHR& tlas_build, uint32_t instance_count) {
  vk.submit_and_wait([&](VkCommandBuffer cmd) {
    std::vector<const VkAccelerationStructureBuildRangeInfoKHR*> range_pointers;
    for (const auto& range : blas_ranges) range_pointers.push_back(&range);
    vk.rt.cmd_build(cmd, static_cast<uint32_t>(blas_builds.size()), blas_builds.data(), range_pointers.data());
    vk::memory_barrier(cmd, VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_WRITE_BIT_KHR,
                       VK_PIPELINE_STAGE_2_ACCELERATION_STRUCTURE_BUILD_BIT_KHR, VK_ACCESS_2_ACCELERATION_STRUCTURE_READ_BIT_KHR);
    const VkAccelerationStructureBuildRangeInfoKHR tlas_range{instance_count, 0, 0, 0};
    const VkAccelerationStructureBuildRangeInfoKHR* tlas_range_pointer = &tlas_range;
    vk.rt.cmd_build(cmd, 1, &tlas_build, &tlas_range_pointer);
  });
}

}  // namespace

AccelerationEstimate estimate_acceleration(const Scene& scene) {
  constexpr uint64_t kBytesPerTriangle = 104, kBytesPerInstance = 176;
  AccelerationEstimate estimate;
  uint64_t vertices = 0;
  for (const auto& object : scene.objects) {
    vertices += object.mesh.positions.size();
    const uint64_t triangles = object.mesh.indices.size() / 3;
    estimate.triangles += triangles;
    estimate.instances += triangles > 0 ? 1 : 0;
  }
  estimate.input_bytes = vertices * sizeof(glm::vec3) + estimate.triangles * 3 * sizeof(uint32_t) +
                         estimate.instances * sizeof(VkAccelerationStructureInstanceKHR);
  estimate.structure_bytes = estimate.triangles * kBytesPerTriangle + estimate.instances * kBytesPerInstance;
  return estimate;
}

AccelerationStructures::AccelerationStructures(vk::Context& vk, const Scene& scene, const std::vector<uint32_t>& vertex_base) {
  if (!vk.ray_queries().available) {
    throw DeviceError(vk.device_name() + " cannot build acceleration structures: it lacks " + vk.ray_queries().missing);
  }
  const auto sort_start = std::chrono::steady_clock::now();
  const BuildInput in = sorted_build_input(scene, vertex_base);
  sort_ms_ = ms_since(sort_start);
  if (in.objects.empty()) throw InputError(scene.path + ": no triangles to build acceleration structures from");

  positions_ =
      vk::make_static_buffer(vk, in.positions.data(), in.positions.size() * sizeof(glm::vec3), kBuildInput, "acceleration positions");
  triangles_ = vk::make_static_buffer(vk, in.triangles.data(), in.triangles.size() * sizeof(uint32_t),
                                      kBuildInput | VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "acceleration triangles");
  const VkDeviceAddress positions_address = vk::device_address(vk, positions_.get());
  const VkDeviceAddress triangles_address = vk::device_address(vk, triangles_.get());
  const VkDeviceSize scratch_alignment = scratch_alignment_of(vk);

  // Creates the structure's buffer and handle for the sizes of `build`; returns the scratch it needs.
  auto create_level = [&](Level& level, VkAccelerationStructureBuildGeometryInfoKHR& build, uint32_t primitives, const std::string& name) {
    VkAccelerationStructureBuildSizesInfoKHR sizes{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_BUILD_SIZES_INFO_KHR};
    vk.rt.build_sizes(vk.device(), VK_ACCELERATION_STRUCTURE_BUILD_TYPE_DEVICE_KHR, &build, &primitives, &sizes);
    level.storage =
        vk::make_buffer(vk, sizes.accelerationStructureSize,
                        VK_BUFFER_USAGE_ACCELERATION_STRUCTURE_STORAGE_BIT_KHR | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT, 0, name);
    VkAccelerationStructureCreateInfoKHR create{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_CREATE_INFO_KHR};
    create.buffer = level.storage.get();
    create.size = sizes.accelerationStructureSize;
    create.type = build.type;
    VkAccelerationStructureKHR handle = VK_NULL_HANDLE;
    vk::check(vk.rt.create(vk.device(), &create, nullptr, &handle), "vkCreateAccelerationStructureKHR");
    level.structure = OwnedAccelerationStructure(vk, handle);
    vk.set_name(VK_OBJECT_TYPE_ACCELERATION_STRUCTURE_KHR, reinterpret_cast<uint64_t>(handle), name);
    build.dstAccelerationStructure = handle;
    bytes_ += sizes.accelerationStructureSize;
    return align_up(sizes.buildScratchSize, scratch_alignment);
  };

  // Bottom level: one per object, all built in one call with their own scratch ranges.
  const size_t count = in.objects.size();
  std::vector<VkAccelerationStructureGeometryKHR> blas_geometry(count);
  std::vector<VkAccelerationStructureBuildGeometryInfoKHR> blas_builds(count);
  std::vector<VkAccelerationStructureBuildRangeInfoKHR> blas_ranges(count);
  std::vector<VkDeviceSize> scratch_offsets(count);
  VkDeviceSize scratch_bytes = 0;
  blas_.resize(count);
  for (size_t g = 0; g < count; ++g) {
    const ObjectTriangles& object = in.objects[g];
    const bool masked = scene.objects[object.object].material.alpha_mode == AlphaMode::mask;
    blas_geometry[g] = triangle_geometry(object, masked, positions_address, triangles_address, static_cast<uint32_t>(in.positions.size()));
    blas_builds[g] = build_of(VK_ACCELERATION_STRUCTURE_TYPE_BOTTOM_LEVEL_KHR, &blas_geometry[g]);
    scratch_offsets[g] = scratch_bytes;
    scratch_bytes += create_level(blas_[g], blas_builds[g], object.triangle_count, "blas " + scene.objects[object.object].name);
    blas_ranges[g] = {object.triangle_count, 0, 0, 0};
  }

  std::vector<VkAccelerationStructureInstanceKHR> instances(count);
  for (size_t g = 0; g < count; ++g) {
    const ObjectTriangles& object = in.objects[g];
    instances[g] = instance_of(vk, blas_[g].structure.get(), object.first_triangle, scene.objects[object.object].material.refractor);
  }
  if (in.triangles.size() / 3 >= (1u << 24))
    throw InputError(scene.path + ": more than 2^24 triangles; an instance's custom index cannot reach them");
  instances_ = vk::make_static_buffer(vk, instances.data(), instances.size() * sizeof(VkAccelerationStructureInstanceKHR), kBuildInput,
                                      "acceleration instances");
  VkAccelerationStructureGeometryKHR tlas_geometry{VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_KHR};
  tlas_geometry.geometryType = VK_GEOMETRY_TYPE_INSTANCES_KHR;
  tlas_geometry.geometry.instances = {VK_STRUCTURE_TYPE_ACCELERATION_STRUCTURE_GEOMETRY_INSTANCES_DATA_KHR};
  tlas_geometry.geometry.instances.data.deviceAddress = vk::device_address(vk, instances_.get());
  VkAccelerationStructureBuildGeometryInfoKHR tlas_build = build_of(VK_ACCELERATION_STRUCTURE_TYPE_TOP_LEVEL_KHR, &tlas_geometry);
  const VkDeviceSize tlas_scratch_offset = scratch_bytes;
  scratch_bytes += create_level(tlas_, tlas_build, static_cast<uint32_t>(instances.size()), "tlas");
  bytes_ += positions_.size + triangles_.size + instances_.size;

  vk::Buffer scratch =
      vk::make_buffer(vk, scratch_bytes + scratch_alignment, VK_BUFFER_USAGE_STORAGE_BUFFER_BIT | VK_BUFFER_USAGE_SHADER_DEVICE_ADDRESS_BIT,
                      0, "acceleration scratch");
  const VkDeviceAddress scratch_address = align_up(vk::device_address(vk, scratch.get()), scratch_alignment);
  for (size_t g = 0; g < blas_builds.size(); ++g) blas_builds[g].scratchData.deviceAddress = scratch_address + scratch_offsets[g];
  tlas_build.scratchData.deviceAddress = scratch_address + tlas_scratch_offset;

  const auto build_start = std::chrono::steady_clock::now();
  record_builds(vk, blas_builds, blas_ranges, tlas_build, static_cast<uint32_t>(instances.size()));
  build_ms_ = ms_since(build_start);
}

}  // namespace caustica::scene
