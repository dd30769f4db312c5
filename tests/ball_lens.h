#pragma once
// docs/oracles.md's ball lens, computed analytically for the bundled sphere_plane scene: a spot light
// above a glass sphere (R = 1, n = 1.5) over the floor y = 0.
#include <cmath>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <vector>

#include "io/image_io.h"
#include "scene/scene.h"

namespace caustica::test {

// The exact flux a spot light sends into the sphere (the scene's last object): intensity times the
// sphere's solid angle seen from the light, 2 pi (1 - sqrt(1 - R^2 / D^2)).
inline double flux_into_ball(const scene::Scene& scene) {
  const auto& light = scene.lights[0];
  const auto& ball = scene.objects.back();
  const double distance = static_cast<double>(glm::length(ball.center() - light.view.position));
  const double radius = 0.5 * static_cast<double>(ball.bounds_max.y - ball.bounds_min.y);
  return static_cast<double>(light.intensity) * glm::two_pi<double>() * (1.0 - std::sqrt(1.0 - radius * radius / (distance * distance)));
}

// The fraction of the entering flux that lands on the floor within each radius of the axis, and in
// all (`landed`), for a perfect sphere without Fresnel: rays stratified uniformly in solid angle
// over the cone the sphere subtends, both refractions exact (no ray that enters a sphere can meet
// total internal reflection).
struct ExactLens {
  std::vector<double> inside;
  double landed = 0;
};

inline ExactLens exact_ball_lens(const scene::Scene& scene, const std::vector<double>& radii, double ior = 1.5) {
  const glm::dvec3 light(scene.lights[0].view.position), centre(scene.objects.back().center());
  const double radius = 1.0;
  const glm::dvec3 axis = glm::normalize(centre - light);
  const double cos_max = std::sqrt(1.0 - radius * radius / glm::dot(centre - light, centre - light));
  const glm::dvec3 u = glm::normalize(glm::cross(axis, glm::dvec3(1, 0, 0))), v = glm::cross(axis, u);
  ExactLens exact{std::vector<double>(radii.size(), 0.0), 0.0};
  const int rings = 1000, sectors = 200;
  for (int i = 0; i < rings; ++i) {
    const double cos_t = 1.0 - (1.0 - cos_max) * (i + 0.5) / rings, sin_t = std::sqrt(1.0 - cos_t * cos_t);
    for (int j = 0; j < sectors; ++j) {
      const double phi = glm::two_pi<double>() * (j + 0.5) / sectors;
      const glm::dvec3 d = cos_t * axis + sin_t * (std::cos(phi) * u + std::sin(phi) * v);
      const glm::dvec3 oc = light - centre;
      const double b = glm::dot(oc, d), c = glm::dot(oc, oc) - radius * radius, disc = b * b - c;
      if (disc < 0) continue;  // grazing samples past the rim
      const glm::dvec3 entry = light + (-b - std::sqrt(disc)) * d;
      const glm::dvec3 t1 = glm::refract(d, (entry - centre) / radius, 1.0 / ior);
      const glm::dvec3 exit = entry - 2.0 * glm::dot(t1, entry - centre) * t1;
      const glm::dvec3 t2 = glm::refract(t1, -(exit - centre) / radius, ior);
      if (t2.y >= 0) continue;
      const glm::dvec3 floor = exit + (-exit.y / t2.y) * t2;
      const double r = std::hypot(floor.x, floor.z);
      exact.landed += 1.0 / (rings * sectors);
      for (size_t k = 0; k < radii.size(); ++k) exact.inside[k] += r <= radii[k] ? 1.0 / (rings * sectors) : 0.0;
    }
  }
  return exact;
}

// Visits every lit texel of a light-space caustic map (flux per texel and channel of the image plane
// of the first light's caustic view) with the point where its centre sees the floor y = 0.
template <typename Visit>
void for_each_floor_point(const scene::Scene& scene, const io::ImageData& map, Visit&& visit) {
  const glm::dvec3 light(scene.lights[0].view.position);
  const glm::dmat4 inverse = glm::inverse(glm::dmat4(scene.lights[0].caustic_view_projection()));
  for (uint32_t y = 0; y < map.height; ++y) {
    for (uint32_t x = 0; x < map.width; ++x) {
      const float* rgb = &map.rgba[(size_t{y} * map.width + x) * 4];
      if (rgb[0] == 0 && rgb[1] == 0 && rgb[2] == 0) continue;
      const glm::dvec4 far = inverse * glm::dvec4((x + 0.5) / map.width * 2 - 1, (y + 0.5) / map.height * 2 - 1, 1, 1);
      const glm::dvec3 d = glm::normalize(glm::dvec3(far) / far.w - light);
      visit(light + (-light.y / d.y) * d, glm::dvec3(rgb[0], rgb[1], rgb[2]));
    }
  }
}

// The same with the floor point's distance from the axis.
template <typename Visit>
void for_each_floor_texel(const scene::Scene& scene, const io::ImageData& map, Visit&& visit) {
  for_each_floor_point(scene, map, [&](const glm::dvec3& floor, const glm::dvec3& rgb) { visit(std::hypot(floor.x, floor.z), rgb); });
}

// The flux of a caustic map (the channels' mean, as the flux counters count it) inside each radius
// of the axis on the floor.
inline std::vector<double> map_flux_inside(const scene::Scene& scene, const io::ImageData& map, const std::vector<double>& radii) {
  std::vector<double> inside(radii.size(), 0.0);
  for_each_floor_texel(scene, map, [&](double r, const glm::dvec3& rgb) {
    for (size_t k = 0; k < radii.size(); ++k) inside[k] += r <= radii[k] ? (rgb.x + rgb.y + rgb.z) / 3.0 : 0.0;
  });
  return inside;
}

}  // namespace caustica::test
