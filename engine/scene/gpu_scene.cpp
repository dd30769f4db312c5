#include "scene/gpu_scene.h"

#include <algorithm>
#include <array>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstring>
#include <functional>
#include <iterator>
#include <string_view>

#include "core/error.h"
#include "scene/bvh.h"
#include "scene/sheen_albedo.h"
#include "scene/translucent_samples.h"

namespace caustica::scene {
namespace {

gpu::TextureSlot texture_slot(const TextureRef& ref) {
  // glm is column-major: row r of the transform is (m[0][r], m[1][r], m[2][r]).
  const glm::mat3& m = ref.transform;
  return {glm::vec4(m[0][0], m[1][0], m[2][0], static_cast<float>(ref.texture)),
          glm::vec4(m[0][1], m[1][1], m[2][1], static_cast<float>(ref.texcoord))};
}

// Folds `count` plain structs (no padding: the gpu:: types are vec4-aligned) into `key`.
template <typename T>
uint64_t fold_bytes(uint64_t key, const T* data, size_t count) {
  const uint64_t bytes = std::hash<std::string_view>{}(std::string_view(reinterpret_cast<const char*>(data), count * sizeof(T)));
  return key ^ (bytes + 0x9e3779b97f4a7c15ull + (key << 6) + (key >> 2));
}

}  // namespace

GpuScene::GpuScene(vk::Context& vk, std::shared_ptr<const Scene> scene)
    : vk_(vk),
      scene_(std::move(scene)),
      camera_(scene_->camera),
      lights_(scene_->lights),
      views_(scene::caustic_views(lights_)),
      textures_(vk, *scene_) {
  std::vector<gpu::Vertex> vertices;
  std::vector<uint32_t> indices;
  std::vector<gpu::ObjectData> objects;
  ranges_.resize(scene_->objects.size());
  vertex_base_.resize(scene_->objects.size());
  // Opaque objects, solid refractors, thin-walled refractors: the refractor draws need another
  // culling mode for the thin ones.
  for (int kind = 0; kind < 3; ++kind) {
    DrawRange& group = kind == 0 ? opaque_ : kind == 1 ? refractors_ : thin_refractors_;
    group.first_index = static_cast<uint32_t>(indices.size());
    for (uint32_t o = 0; o < scene_->objects.size(); ++o) {
      const Object& object = scene_->objects[o];
      const int object_kind = !object.material.refractor ? 0 : object.material.thin ? 2 : 1;
      if (object_kind != kind) continue;
      const auto base = static_cast<uint32_t>(vertices.size());
      vertex_base_[o] = base;
      for (size_t v = 0; v < object.mesh.positions.size(); ++v) {
        const float dn = object.mesh.normal_distance.empty() ? 0.0f : object.mesh.normal_distance[v];
        const glm::vec4 uv = object.mesh.texcoords.empty() ? glm::vec4(0.0f) : object.mesh.texcoords[v];
        const glm::vec4 tangent = object.mesh.tangents.empty() ? glm::vec4(0.0f) : object.mesh.tangents[v];
        vertices.push_back(
            {glm::vec4(object.mesh.positions[v], dn), glm::vec4(object.mesh.normals[v], static_cast<float>(o)), uv, tangent});
      }
      ranges_[o].first_index = static_cast<uint32_t>(indices.size());
      ranges_[o].index_count = static_cast<uint32_t>(object.mesh.indices.size());
      for (uint32_t index : object.mesh.indices) indices.push_back(base + index);
    }
    group.index_count = static_cast<uint32_t>(indices.size()) - group.first_index;
  }
  refractors_.index_count += thin_refractors_.index_count;
  for (const Object& object : scene_->objects) {
    const Material& m = object.material;
    const LayerTextures& lt = m.layer_textures;
    const SurfaceTextures& st = m.surface_textures;
    const float refractor_kind = !m.refractor ? 0.0f : is_convex_refractor(object) ? 2.0f : 1.0f;  // scene_types.h
    objects.push_back(
        {glm::vec4(m.albedo, refractor_kind),
         glm::vec4(m.absorption, m.ior),
         glm::vec4(m.tint, m.transmission),
         glm::vec4(object.bounds_min, m.thin ? 1.0f : 0.0f),
         glm::vec4(object.bounds_max, m.ior_spread()),
         texture_slot(m.base_color_texture),
         glm::vec4(m.alpha,
                   m.alpha_mode == AlphaMode::mask ? m.alpha_cutoff
                   : m.coverage_transmits          ? -2.0f
                                                   : -1.0f,
                   m.double_sided ? 0.0f : 1.0f, m.occlusion_strength),
         texture_slot(m.metallic_roughness_texture),
         texture_slot(m.normal_texture),
         texture_slot(m.emissive_texture),
         glm::vec4(m.emissive, m.normal_scale),
         glm::vec4(m.metallic, m.roughness, m.metallic_roughness ? 1.0f : 0.0f, m.refractor ? m.transmission_roughness : 0.0f),
         texture_slot(m.occlusion_texture),
         texture_slot(m.transmission_texture),
         glm::vec4(m.tint_factor, m.transmission_factor),
         glm::vec4(m.specular_color, m.specular),
         glm::vec4(m.clearcoat, m.clearcoat_roughness, m.iridescence, m.film_ior),
         glm::vec4(m.film_thickness_nm, lt.thickness_min, lt.thickness_max, 0.0f),
         {texture_slot(lt.specular), texture_slot(lt.specular_color), texture_slot(lt.clearcoat), texture_slot(lt.clearcoat_roughness),
          texture_slot(lt.iridescence), texture_slot(lt.thickness)},
         glm::vec4(factor_or(lt.specular_color, lt.specular_color_factor, m.specular_color),
                   factor_or(lt.specular, lt.specular_factor, m.specular)),
         glm::vec4(factor_or(lt.clearcoat, lt.clearcoat_factor, m.clearcoat),
                   factor_or(lt.clearcoat_roughness, lt.clearcoat_roughness_factor, m.clearcoat_roughness),
                   factor_or(lt.iridescence, lt.iridescence_factor, m.iridescence), has_layer_textures(m) ? 1.0f : 0.0f),
         glm::vec4(m.sheen_color, m.sheen_roughness),
         {},
         glm::vec4(m.anisotropy, std::cos(m.anisotropy_rotation), std::sin(m.anisotropy_rotation), 0.0f),
         texture_slot(m.anisotropy_texture),
         glm::vec4(m.diffuse_transmission_color, m.diffuse_transmission),
         {texture_slot(st.sheen_color), texture_slot(st.sheen_roughness), texture_slot(st.diffuse_transmission),
          texture_slot(st.diffuse_transmission_color), texture_slot(st.clearcoat_normal)},
         glm::vec4(factor_or(st.sheen_color, st.sheen_color_factor, m.sheen_color),
                   factor_or(st.sheen_roughness, st.sheen_roughness_factor, m.sheen_roughness)),
         glm::vec4(factor_or(st.diffuse_transmission_color, st.diffuse_transmission_color_factor, m.diffuse_transmission_color),
                   factor_or(st.diffuse_transmission, st.diffuse_transmission_factor, m.diffuse_transmission)),
         glm::vec4(st.clearcoat_normal_scale, 0.0f, 0.0f, 0.0f)});
    // The sheen's albedo is an integral the lighting pass cannot afford per pixel: integrated here
    // once per object (scene/sheen_albedo.h; the reference integrates it at every point it shades).
    if (m.sheen_color != glm::vec3(0.0f)) {
      const std::array<float, 16> albedo = sheen_albedo_table(m.sheen_roughness);
      std::memcpy(objects.back().sheen_albedo, albedo.data(), sizeof(objects.back().sheen_albedo));
    }
  }
  // A sheen whose roughness a texture sets needs the albedo at every roughness: the table at
  // roughness j / 15 in row j, which the lighting pass interpolates between rows.
  const bool sheen_roughness_varies = std::any_of(scene_->objects.begin(), scene_->objects.end(), [](const Object& o) {
    return o.material.sheen_color != glm::vec3(0.0f) && o.material.surface_textures.sheen_roughness.used();
  });
  for (int row = 0; sheen_roughness_varies && row < 16; ++row) {
    const std::array<float, 16> albedo = sheen_albedo_table(static_cast<float>(row) / 15.0f);
    std::memcpy(&frame_data_.sheen_albedo_rows[4 * row], albedo.data(), sizeof(albedo));
  }
  vertices_ = vk::make_static_buffer(vk, vertices.data(), vertices.size() * sizeof(gpu::Vertex), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                     "scene vertices");
  indices_ =
      vk::make_static_buffer(vk, indices.data(), indices.size() * sizeof(uint32_t), VK_BUFFER_USAGE_INDEX_BUFFER_BIT, "scene indices");
  objects_ = vk::make_static_buffer(vk, objects.data(), objects.size() * sizeof(gpu::ObjectData), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                    "scene objects");
  // The translucent surfaces' patches, which the lighting pass gathers from (a zero one where there
  // are none: the binding needs a buffer). They follow from the geometry and materials, which the
  // content key holds.
  std::vector<gpu::TranslucentSample> patches = scene::translucent_samples(*scene_);
  frame_data_.translucent_samples = static_cast<uint32_t>(patches.size());
  if (patches.empty()) patches.emplace_back();
  translucent_ = vk::make_static_buffer(vk, patches.data(), patches.size() * sizeof(gpu::TranslucentSample),
                                        VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "translucent patches");
  content_key_ = fold_bytes(fold_bytes(fold_bytes(0, vertices.data(), vertices.size()), indices.data(), indices.size()), objects.data(),
                            objects.size());
  for (const Texture& texture : scene_->textures) content_key_ = fold_bytes(content_key_, texture.rgba.data(), texture.rgba.size());
  frame_ = vk::make_buffer(vk, sizeof(gpu::FrameData), VK_BUFFER_USAGE_UNIFORM_BUFFER_BIT,
                           VK_MEMORY_PROPERTY_HOST_VISIBLE_BIT | VK_MEMORY_PROPERTY_HOST_COHERENT_BIT, "scene frame data");
}

void GpuScene::replace_view(const View& camera, std::vector<Light> lights) {
  assert(lights.size() == scene_->lights.size() && "graph expressions counted the scene's lights (scene.lights)");
  camera_ = camera;
  // A moved light's caustic view is fitted again; a point light that then has none keeps its last
  // (the plan was compiled for the scene's lights as loaded: scene.lightK.view).
  for (size_t i = 0; i < lights.size(); ++i) {
    const View& was = lights_[i].view;
    Light& light = lights[i];
    if (light.view.position == was.position && light.view.target == was.target && light.view.fov_y_degrees == was.fov_y_degrees &&
        light.extent == lights_[i].extent)
      continue;
    const Light before = light;
    if (!fit_caustic_view(light, *scene_) && before.has_caustic_view) {
      light.caustic_view = before.caustic_view;
      light.has_caustic_view = true;
    }
  }
  lights_ = std::move(lights);
  views_ = scene::caustic_views(lights_);
}

const AccelerationStructures& GpuScene::acceleration() {
  if (!acceleration_) acceleration_ = std::make_unique<AccelerationStructures>(vk_, *scene_, vertex_base_);
  return *acceleration_;
}

const GpuScene::TracerBuffers& GpuScene::tracer_bvh() {
  if (tracer_bvh_) return *tracer_bvh_;
  const auto start = std::chrono::steady_clock::now();
  const TracerBvh built = build_scene_bvh(*scene_, vertex_base_);
  if (built.triangle_count == 0) throw InputError(scene_->path + ": no triangles to trace");
  auto buffers = std::make_unique<TracerBuffers>();
  buffers->bvh = vk::make_static_buffer(vk_, built.words.data(), built.words.size() * sizeof(glm::vec4), VK_BUFFER_USAGE_STORAGE_BUFFER_BIT,
                                        "tracer bvh");
  buffers->triangles = vk::make_static_buffer(vk_, built.triangle_vertices.data(), built.triangle_vertices.size() * sizeof(uint32_t),
                                              VK_BUFFER_USAGE_STORAGE_BUFFER_BIT, "tracer triangles");
  buffers->bytes = built.bytes();
  buffers->nodes = built.node_count;
  buffers->depth = built.depth;
  buffers->build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  tracer_bvh_ = std::move(buffers);
  return *tracer_bvh_;
}

std::pair<DrawRange, DrawRange> GpuScene::split_thin(DrawRange range) const {
  const uint32_t end = range.first_index + range.index_count;
  const uint32_t cut = std::clamp(thin_refractors_.first_index, range.first_index, end);
  return {{range.first_index, cut - range.first_index}, {cut, end - cut}};
}

std::vector<uint32_t> GpuScene::refractors_back_to_front(glm::vec3 eye) const {
  std::vector<uint32_t> order;
  for (uint32_t o = 0; o < scene_->objects.size(); ++o) {
    if (scene_->objects[o].material.refractor) order.push_back(o);
  }
  // Ties broken by index so the order never depends on the sort's stability.
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const float da = glm::length(scene_->objects[a].center() - eye), db = glm::length(scene_->objects[b].center() - eye);
    return da != db ? da > db : a < b;
  });
  return order;
}

namespace {

// `light` as the shaders see it through `seen`'s view (the light itself, or as_caustic_view()); the
// spot cone is the light's own either way.
gpu::LightData light_data(const Light& seen, const Light& light) {
  gpu::LightData l{};
  const bool directional = light.type == LightType::directional;
  l.view_proj = seen.view_projection();
  l.inv_view_proj = glm::inverse(l.view_proj);
  l.position_type = glm::vec4(seen.view.position, light.type == LightType::spot ? 0.0f : directional ? 2.0f : 1.0f);
  // A square frustum's inscribed cone: the half angle is half the field of view.
  l.direction_cos = glm::vec4(light.axis(), std::cos(glm::radians(light.view.fov_y_degrees) * 0.5f));
  l.radiant = glm::vec4(light.color * light.intensity, light.intensity);
  const float tan_half = std::tan(glm::radians(seen.view.fov_y_degrees) * 0.5f);
  l.clip = glm::vec4(seen.view.near_plane, seen.view.far_plane, directional ? seen.extent : tan_half, kCubeFaceTan);
  l.face = glm::vec4(-1.0f, static_cast<float>(light.inside), 0.0f, 0.0f);
  return l;
}

}  // namespace

void GpuScene::update_frame(uint32_t width, uint32_t height) {
  const Scene& s = *scene_;
  gpu::FrameData& f = frame_data_;
  const float aspect = static_cast<float>(width) / static_cast<float>(height);
  f.view_proj = camera_.view_projection(aspect);
  f.inv_view_proj = glm::inverse(f.view_proj);
  f.camera_position = glm::vec4(camera_.position, aspect);
  f.sky_ambient = glm::vec4(s.sky, s.ambient);
  f.sizes =
      glm::vec4(static_cast<float>(width), static_cast<float>(height), 1.0f / static_cast<float>(width), 1.0f / static_cast<float>(height));
  f.light_count = static_cast<uint32_t>(std::min<size_t>(lights_.size(), CAUSTICA_MAX_LIGHTS));
  for (uint32_t i = 0; i < f.light_count; ++i) {
    f.lights[i] = light_data(lights_[i], lights_[i]);
    if (lights_[i].type != LightType::point) continue;
    for (uint32_t face = 0; face < 6; ++face) f.light_faces[6 * i + face] = lights_[i].face_view_projection(face);
  }
  // Each caustic view as its passes see it: its view, with its light's own cone.
  f.caustic_view_count = static_cast<uint32_t>(std::min<size_t>(views_.size(), CAUSTICA_MAX_CAUSTIC_VIEWS));
  for (uint32_t v = 0; v < f.caustic_view_count; ++v) {
    f.caustic_lights[v] = light_data(views_[v].seen, lights_[views_[v].light]);
    f.caustic_lights[v].face.x = static_cast<float>(views_[v].face);
  }
  std::memcpy(frame_.mapped, &f, sizeof(f));
  lights_key_ = fold_bytes(fold_bytes(fold_bytes(0, &f.light_count, 1), f.lights, f.light_count), f.caustic_lights, f.caustic_view_count);
  // A light's key holds all its caustic views: its per-light and per-view passes follow it.
  light_keys_.assign(f.light_count, 0);
  for (uint32_t i = 0; i < f.light_count; ++i) light_keys_[i] = fold_bytes(0, &f.lights[i], 1);
  for (uint32_t v = 0; v < f.caustic_view_count; ++v) {
    if (views_[v].light < f.light_count) light_keys_[views_[v].light] = fold_bytes(light_keys_[views_[v].light], &f.caustic_lights[v], 1);
  }
  const glm::vec4 camera[] = {f.view_proj[0], f.view_proj[1], f.view_proj[2], f.view_proj[3], f.camera_position, f.sky_ambient, f.sizes};
  camera_key_ = fold_bytes(0, camera, std::size(camera));
}

glm::mat4 shifted_by_pixels(const glm::mat4& view_proj, glm::vec2 pixels, glm::vec2 size) {
  // A translation in clip space (times w): every point's image moves by the same pixels.
  glm::mat4 shift(1.0f);
  shift[3][0] = 2.0f * pixels.x / size.x;
  shift[3][1] = 2.0f * pixels.y / size.y;
  return shift * view_proj;
}

void GpuScene::jitter_camera(glm::vec2 pixels) {
  gpu::FrameData& f = frame_data_;
  f.view_proj = shifted_by_pixels(f.view_proj, pixels, glm::vec2(f.sizes));
  f.inv_view_proj = glm::inverse(f.view_proj);
  std::memcpy(frame_.mapped, &f, sizeof(f));
}

uint64_t GpuScene::parts_key(bool geometry, bool lights, bool camera) const {
  const uint64_t parts[] = {geometry ? content_key_ : 0, lights ? lights_key_ : 0, camera ? camera_key_ : 0};
  return fold_bytes(0, parts, std::size(parts));
}

}  // namespace caustica::scene
