// A light's geometry: its views (the shadow map's, the caustic map's, a point light's cube faces),
// what it reaches, and the views fitted to the scene when it is loaded.
#include <algorithm>
#include <bit>
#include <cmath>
#include <glm/gtc/matrix_transform.hpp>
#include <limits>
#include <optional>
#include <tuple>
#include <vector>

#include "common/scene_types.h"
#include "scene/scene.h"

namespace caustica::scene {

const char* light_type_name(LightType type) {
  static const char* const kNames[] = {"spot", "point", "directional"};
  return kNames[static_cast<int>(type)];
}

glm::mat4 Light::view_projection() const {
  if (type != LightType::directional) return view.view_projection(1.0f);
  // Orthographic, Vulkan conventions as View::projection: depth 0..1 from near to far, y down.
  glm::mat4 p(1.0f);
  p[0][0] = 1.0f / extent;
  p[1][1] = -1.0f / extent;
  p[2][2] = 1.0f / (view.near_plane - view.far_plane);
  p[3][2] = view.near_plane / (view.near_plane - view.far_plane);
  return p * view.view_matrix();
}

glm::vec3 Light::face_axis(uint32_t face) {
  static const glm::vec3 axes[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  return axes[face % 6];
}

glm::mat4 Light::face_view_projection(uint32_t face) const {
  View face_view = view;
  face_view.target = view.position + face_axis(face);
  face_view.fov_y_degrees = glm::degrees(2.0f * std::atan(kCubeFaceTan));
  return face_view.view_projection(1.0f);
}

bool Light::reaches(glm::vec3 bounds_min, glm::vec3 bounds_max) const {
  if (type == LightType::point) return true;  // its caustic view is fitted to what it reaches
  const glm::vec3 center = 0.5f * (bounds_min + bounds_max);
  const float radius = 0.5f * glm::length(bounds_max - bounds_min);
  const glm::vec3 to_center = center - view.position;
  const float along = glm::dot(to_center, axis());
  if (along + radius < view.near_plane || along - radius > view.far_plane) return false;
  const float across = glm::length(to_center - along * axis());
  if (type == LightType::directional) return across - radius <= extent * std::sqrt(2.0f);
  // The sphere around the box against the cone through the square frustum's corners.
  const float distance = glm::length(to_center);
  if (distance <= radius) return true;
  const float corner = std::atan(std::sqrt(2.0f) * std::tan(glm::radians(view.fov_y_degrees) * 0.5f));
  const float off_axis = std::atan2(across, along);
  return off_axis - std::asin(std::min(1.0f, radius / distance)) <= corner;
}

namespace {

// A directional light's orthographic view is a prism along its direction: one that holds the first
// `fitted` objects (every bounding-box corner) shadows and throws caustics for all of them. Only
// lights whose extent the scene did not give are fitted; the far plane reaches past every object.
void fit_directional_light(Light& light, const Scene& scene, size_t fitted) {
  const glm::vec3 axis = light.axis();
  float radial = 0.0f, depth = 0.0f;
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    for (int corner = 0; corner < 8; ++corner) {
      const glm::vec3 c((corner & 1) ? o.bounds_max.x : o.bounds_min.x, (corner & 2) ? o.bounds_max.y : o.bounds_min.y,
                        (corner & 4) ? o.bounds_max.z : o.bounds_min.z);
      const glm::vec3 d = c - light.view.position;
      const float along = glm::dot(d, axis);
      depth = std::max(depth, along);
      if (i < fitted) radial = std::max(radial, glm::length(d - along * axis));
    }
  }
  if (light.extent <= 0.0f) light.extent = std::max(1.02f * radial, 1e-3f);
  light.view.far_plane = std::max(light.view.far_plane, 1.05f * depth + light.view.near_plane);
}

// The half angle of the narrowest cone about `axis` from the light that holds every sphere.
float cone_half_angle(glm::vec3 axis, const std::vector<std::pair<glm::vec3, float>>& spheres) {
  float half = 0.0f;
  for (const auto& [direction, angle] : spheres)
    half = std::max(half, std::acos(std::clamp(glm::dot(axis, direction), -1.0f, 1.0f)) + angle);
  return half;
}

// The refractors' bounding spheres (Object::bounding_radius) that light from it reaches.
std::vector<std::pair<glm::vec3, float>> reached_refractors(const Light& light, const Scene& scene) {
  std::vector<std::pair<glm::vec3, float>> spheres;
  for (const Object& o : scene.objects) {
    if (o.material.refractor && light.reaches(o.bounds_min, o.bounds_max)) spheres.emplace_back(o.center(), o.bounding_radius());
  }
  return spheres;
}

// A frustum from a point or spot light around the refractors it reaches, its tangent
// kCausticViewMargin times theirs, or nothing where the light is inside one or they spread over
// more than kMaxFittedViewHalfDegrees about it.
std::optional<View> fitted_frustum(const Light& light, const std::vector<std::pair<glm::vec3, float>>& refractors) {
  std::vector<std::pair<glm::vec3, float>> seen;  // direction and angular radius of each
  glm::vec3 sum(0.0f), lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& [center, radius] : refractors) {
    const glm::vec3 to_center = center - light.view.position;
    const float distance = glm::length(to_center);
    if (distance <= 1.001f * radius) return std::nullopt;
    seen.emplace_back(to_center / distance, std::asin(radius / distance));
    sum += to_center / distance;
    lo = glm::min(lo, center - radius);
    hi = glm::max(hi, center + radius);
  }
  if (seen.empty() || glm::length(sum) < 1e-6f) return std::nullopt;
  // Of two axes, towards the spheres' box and their mean direction, the one with the narrower cone.
  glm::vec3 axis = glm::normalize(sum);
  const glm::vec3 to_box = 0.5f * (lo + hi) - light.view.position;
  if (glm::length(to_box) > 1e-6f && cone_half_angle(glm::normalize(to_box), seen) < cone_half_angle(axis, seen))
    axis = glm::normalize(to_box);
  const float half = cone_half_angle(axis, seen);
  if (half > glm::radians(kMaxFittedViewHalfDegrees)) return std::nullopt;
  View view = light.view;
  view.target = view.position + axis;
  view.fov_y_degrees = glm::degrees(2.0f * std::atan(kCausticViewMargin * std::tan(half)));
  return view;
}

// A directional light's prism narrowed to the refractors it reaches: the same direction, its square
// about their bounding spheres' box across it, kCausticViewMargin times its half side; nothing
// where that square would reach outside the light's own (whose light is all there is).
std::optional<std::pair<View, float>> fitted_prism(const Light& light, const std::vector<std::pair<glm::vec3, float>>& refractors) {
  if (refractors.empty()) return std::nullopt;
  // The light's view across its direction: the rows of its view matrix.
  const glm::mat4 v = light.view.view_matrix();
  const glm::vec3 right(v[0][0], v[1][0], v[2][0]), up(v[0][1], v[1][1], v[2][1]);
  glm::vec2 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& [center, radius] : refractors) {
    const glm::vec3 d = center - light.view.position;
    const glm::vec2 across(glm::dot(d, right), glm::dot(d, up));
    lo = glm::min(lo, across - radius);
    hi = glm::max(hi, across + radius);
  }
  const glm::vec2 middle = 0.5f * (lo + hi);
  const float half_side = kCausticViewMargin * 0.5f * std::max(hi.x - lo.x, hi.y - lo.y);
  if (std::max(std::abs(middle.x), std::abs(middle.y)) + half_side > light.extent) return std::nullopt;
  View view = light.view;
  view.position += middle.x * right + middle.y * up;
  view.target = view.position + light.axis();
  return std::pair{view, half_side};
}

// The cube faces about a point light whose pyramid holds part of a refractor: each face's pyramid
// conservatively as the cone through its corners (half angle atan(sqrt 2)).
uint32_t faces_holding(const Light& light, const std::vector<std::pair<glm::vec3, float>>& refractors) {
  const float corner = std::atan(std::sqrt(2.0f));
  uint32_t faces = 0;
  for (const auto& [center, radius] : refractors) {
    const glm::vec3 to_center = center - light.view.position;
    const float distance = glm::length(to_center);
    if (distance <= radius) return 0x3fu;
    const float angular_radius = std::asin(radius / distance);
    for (uint32_t face = 0; face < 6; ++face) {
      const float off_axis = std::acos(std::clamp(glm::dot(Light::face_axis(face), to_center / distance), -1.0f, 1.0f));
      if (off_axis - angular_radius <= corner) faces |= 1u << face;
    }
  }
  return faces;
}

// Whether p lies inside the closed mesh: a ray from it crosses its triangles an odd number of
// times (Moller-Trumbore; the ray leans off every axis, so it meets no edge of an axis-aligned
// primitive's triangles exactly).
bool inside_mesh(const Mesh& mesh, glm::vec3 p) {
  const glm::vec3 d = glm::normalize(glm::vec3(1.0f, 0.000731f, 0.000417f));
  int crossings = 0;
  for (size_t i = 0; i + 2 < mesh.indices.size(); i += 3) {
    const glm::vec3 a = mesh.positions[mesh.indices[i]], e1 = mesh.positions[mesh.indices[i + 1]] - a,
                    e2 = mesh.positions[mesh.indices[i + 2]] - a;
    const glm::vec3 q = glm::cross(d, e2);
    const float det = glm::dot(e1, q);
    if (std::abs(det) < 1e-12f) continue;
    const glm::vec3 s = p - a;
    const float u = glm::dot(s, q) / det;
    const glm::vec3 r = glm::cross(s, e1);
    const float v = glm::dot(d, r) / det;
    if (u < 0.0f || v < 0.0f || u + v > 1.0f) continue;
    if (glm::dot(e2, r) / det > 0.0f) ++crossings;
  }
  return crossings % 2 == 1;
}

// The solid refractor that p lies in (the smallest by its box, where they nest), or -1.
int enclosing_refractor(const Scene& scene, glm::vec3 p) {
  int found = -1;
  float smallest = std::numeric_limits<float>::max();
  for (size_t i = 0; i < scene.objects.size(); ++i) {
    const Object& o = scene.objects[i];
    if (!o.material.refractor || o.material.thin || glm::any(glm::lessThan(p, o.bounds_min)) || glm::any(glm::greaterThan(p, o.bounds_max)))
      continue;
    const glm::vec3 size = o.bounds_max - o.bounds_min;
    if (size.x * size.y * size.z < smallest && inside_mesh(o.mesh, p)) {
      smallest = size.x * size.y * size.z;
      found = static_cast<int>(i);
    }
  }
  return found;
}

// The far plane of a view from the light beyond every object: where the caustic lands.
float far_beyond_objects(const Light& light, const Scene& scene) {
  float farthest = 0.0f;
  for (const Object& o : scene.objects) farthest = std::max(farthest, glm::length(o.center() - light.view.position) + o.bounding_radius());
  return std::max(light.view.far_plane, 1.05f * farthest + light.view.near_plane);
}

}  // namespace

uint32_t Light::caustic_view_count() const {
  if (!has_caustic_view) return 0;
  return caustic_faces != 0 ? static_cast<uint32_t>(std::popcount(caustic_faces)) : 1u;
}

View Light::caustic_face_view(uint32_t face) const {
  View face_view = caustic_faces != 0 ? caustic_view : view;  // caustic_view holds the far plane fitted to the scene
  face_view.position = view.position;
  face_view.target = view.position + face_axis(face);
  face_view.fov_y_degrees = glm::degrees(2.0f * std::atan(kCubeFaceCausticTan));
  return face_view;
}

bool leaves_through_face(glm::vec3 d, int face) {
  const glm::vec3 a = glm::abs(d);
  const int axis = a.x >= a.y && a.x >= a.z ? 0 : a.y >= a.z ? 1 : 2;
  return face == 2 * axis + (d[axis] > 0.0f ? 0 : 1);
}

std::vector<CausticView> caustic_views(const std::vector<Light>& lights) {
  std::vector<CausticView> views(lights.size());
  std::vector<CausticView> further;
  for (uint32_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    views[i].light = i;
    views[i].present = light.has_caustic_view;
    views[i].seen = light.as_caustic_view();
    bool first = true;
    for (uint32_t face = 0; face < 6; ++face) {
      if (!(light.caustic_faces & (1u << face))) continue;
      // The device holds CAUSTICA_MAX_CAUSTIC_VIEWS (eight point lights each inside glass would need 48).
      if (!first && views.size() + further.size() >= CAUSTICA_MAX_CAUSTIC_VIEWS) break;
      CausticView& view = first ? views[i] : further.emplace_back();
      view.light = i;
      view.face = static_cast<int>(face);
      view.present = true;
      view.seen = light;
      view.seen.view = light.caustic_face_view(face);
      first = false;
    }
  }
  views.insert(views.end(), further.begin(), further.end());
  return views;
}

glm::mat4 Light::caustic_view_projection() const {
  return as_caustic_view().view_projection();
}

Light Light::as_caustic_view() const {
  Light seen = *this;
  seen.view = caustic_view;
  seen.extent = caustic_extent;
  return seen;
}

bool fit_caustic_view(Light& light, const Scene& scene) {
  light.inside = light.type == LightType::directional ? -1 : enclosing_refractor(scene, light.view.position);
  light.caustic_view = light.view;
  light.caustic_extent = light.extent;
  light.has_caustic_view = light.type != LightType::point;
  if (light.type != LightType::point && light.own_caustic_view) return true;
  const auto refractors = reached_refractors(light, scene);
  if (light.type == LightType::directional) {
    if (const auto prism = fitted_prism(light, refractors)) std::tie(light.caustic_view, light.caustic_extent) = *prism;
    return true;
  }
  // A point light that no frustum fits throws through cube faces; one that did keeps them as it
  // moves (the graph's instances were made for them).
  const auto fitted = light.caustic_faces != 0 ? std::nullopt : fitted_frustum(light, refractors);
  if (light.type == LightType::point && !fitted) {
    if (light.caustic_faces == 0) light.caustic_faces = faces_holding(light, refractors);
    if (light.caustic_faces == 0) return false;
    light.caustic_view.far_plane = far_beyond_objects(light, scene);
    light.caustic_view = light.caustic_face_view(static_cast<uint32_t>(std::countr_zero(light.caustic_faces)));
    light.has_caustic_view = true;
    return true;
  }
  // A spot light keeps its own view where that is the narrower.
  if (!fitted || (light.type == LightType::spot && fitted->fov_y_degrees >= light.view.fov_y_degrees)) return light.has_caustic_view;
  light.caustic_view = *fitted;
  light.caustic_view.far_plane = far_beyond_objects(light, scene);
  light.has_caustic_view = true;
  return true;
}

void move_light(Scene& scene, size_t index, glm::vec3 offset) {
  Light& light = scene.lights.at(index);
  light.view.position += offset;
  fit_caustic_view(light, scene);
}

void fit_light_views(Scene& scene, size_t fitted) {
  for (Light& light : scene.lights) {
    if (light.type == LightType::directional) fit_directional_light(light, scene, fitted);
    fit_caustic_view(light, scene);
  }
}

}  // namespace caustica::scene
