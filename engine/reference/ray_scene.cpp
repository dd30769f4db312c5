#include "reference/ray_scene.h"

#include <embree3/rtcore.h>

#include <cstring>
#include <limits>

#include "core/error.h"

namespace caustica::reference {

struct RayScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  uint32_t geometries = 0;
};

RayScene::RayScene() : impl_(std::make_unique<Impl>()) {
  impl_->device = rtcNewDevice(nullptr);
  if (!impl_->device) throw DeviceError("Embree could not start (rtcNewDevice failed)");
  impl_->scene = rtcNewScene(impl_->device);
  // Watertight: a ray through a shared vertex or edge (a sphere's vertex towards its antipode) must
  // not slip between the triangles.
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_ROBUST);
}

RayScene::~RayScene() {
  rtcReleaseScene(impl_->scene);
  rtcReleaseDevice(impl_->device);
}

namespace {

// Rejects the candidate hits that land where the geometry's CutOut says there is no surface.
void filter_cut_outs(const RTCFilterFunctionNArguments* args) {
  const auto& cut_out = *static_cast<const RayScene::CutOut*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const uint32_t triangle = RTCHitN_primID(args->hit, args->N, i);
    if (cut_out(triangle, RTCHitN_u(args->hit, args->N, i), RTCHitN_v(args->hit, args->N, i))) args->valid[i] = 0;
  }
}

}  // namespace

uint32_t RayScene::add_mesh(const std::vector<glm::vec3>& positions, const std::vector<uint32_t>& indices, CutOut cut_out) {
  RTCGeometry geometry = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  if (cut_out) {
    cut_outs_.push_back(std::make_unique<CutOut>(std::move(cut_out)));
    rtcSetGeometryUserData(geometry, cut_outs_.back().get());
    rtcSetGeometryIntersectFilterFunction(geometry, filter_cut_outs);
  }
  // Embree may read 16 bytes at the last vertex: the buffers it allocates are padded for that.
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
  std::memcpy(vertices, positions.data(), positions.size() * sizeof(glm::vec3));
  auto* triangles = static_cast<uint32_t*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), indices.size() / 3));
  std::memcpy(triangles, indices.data(), indices.size() / 3 * 3 * sizeof(uint32_t));
  rtcCommitGeometry(geometry);
  const uint32_t id = rtcAttachGeometry(impl_->scene, geometry);
  rtcReleaseGeometry(geometry);
  ++impl_->geometries;
  return id;
}

void RayScene::commit() {
  rtcCommitScene(impl_->scene);
}

std::optional<RayHit> RayScene::intersect(glm::vec3 origin, glm::vec3 direction, float near, float far) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit query{};
  query.ray.org_x = origin.x;
  query.ray.org_y = origin.y;
  query.ray.org_z = origin.z;
  query.ray.dir_x = direction.x;
  query.ray.dir_y = direction.y;
  query.ray.dir_z = direction.z;
  query.ray.tnear = near;
  query.ray.tfar = far;
  query.ray.mask = ~0u;
  query.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  query.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(impl_->scene, &context, &query);
  if (query.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  glm::vec3 n(query.hit.Ng_x, query.hit.Ng_y, query.hit.Ng_z);
  const float len = glm::length(n);
  return RayHit{query.ray.tfar, query.hit.geomID, query.hit.primID, len > 0 ? n / len : glm::vec3(0, 1, 0), query.hit.u, query.hit.v};
}

}  // namespace caustica::reference
