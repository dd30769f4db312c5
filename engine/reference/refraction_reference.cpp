#include "reference/refraction_reference.h"

#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <thread>

#include "reference/exact_scene.h"
#include "reference/interface_physics.h"
#include "reference/translucent_light.h"

namespace caustica::reference {
namespace {

constexpr int kMaxInterfaces = 32;  // per refractor crossing; TIR can bounce a ray around inside
// A pixel whose ray meets a rough refractor averages this many paths (the engine takes 8: its
// pictures are noisier, their mean the same).
constexpr int kRoughSamples = 64;

float luminance(const float* rgb) {
  return 0.2126f * rgb[0] + 0.7152f * rgb[1] + 0.0722f * rgb[2];
}

class Tracer {
 public:
  Tracer(const scene::Scene& scene, const CausticMaps& caustic_maps)
      : exact_(scene),
        translucent_(exact_),
        scene_(scene),
        rays_(exact_.rays()),
        epsilon_(exact_.epsilon()),
        views_(scene::caustic_views(scene.lights)),
        caustic_maps_(caustic_maps) {
    caustic_maps_.resize(views_.size(), nullptr);
    for (size_t i = 0; i < views_.size(); ++i) {
      if (!views_[i].present) caustic_maps_[i] = nullptr;
      light_view_projs_.push_back(caustic_maps_[i] ? views_[i].seen.view_projection() : glm::mat4(1.0f));
    }
  }

  glm::vec3 smooth_normal(const RayHit& hit) const { return exact_.smooth_normal(hit); }

  // The engine's lighting model (scene/lighting.frag) with exact shadow rays, seen along `direction`,
  // with the light translucent surfaces pass on (translucent_light.h) where p lies on object
  // `receiver`: the model's receivers are opaque surfaces, so a refractor's diffuse share (-1) has none.
  glm::vec3 shade_opaque(glm::vec3 p, const SurfacePoint& surface, glm::vec3 direction, Random& random, int receiver) const {
    const glm::vec3 n = surface.normal, v = -direction;
    glm::vec3 radiance = surface.emitted + scene_.ambient * scene_.sky * surface.ambient_reflectance(v) * surface.occlusion;
    // The caustic's light arrives through the refractor from many directions: diffuse only.
    for (size_t view = 0; view < views_.size(); ++view) {
      if (caustic_maps_[view]) radiance += surface.diffuse_reflected() / glm::pi<float>() * caustic_irradiance(view, p, n);
    }
    // So does a translucent surface's, from all over its area.
    if (receiver >= 0 && !translucent_.empty()) {
      radiance += surface.diffuse_reflected() / glm::pi<float>() * translucent_.irradiance(p, n, uint32_t(receiver), random);
    }
    for (const scene::Light& light : scene_.lights) {
      auto [l, d2, reach, cone] = light_arrival(light, p, epsilon_);
      // A surface that transmits diffusely is lit from behind too, shadowed from its far side.
      const float n_l = glm::dot(n, l);
      if (n_l <= 0.0f && surface.layers.diffuse_transmission <= 0.0f) continue;
      const glm::vec3 lit_side = n_l > 0.0f ? n : -n;
      // The engine shadows every light (through its shadow map); the reference with an exact ray.
      if (cone > 0 && rays_.intersect(p + lit_side * epsilon_, l, 0.0f, reach)) cone = 0;
      radiance += surface.brdf(v, l) * light.color * light.intensity * std::abs(n_l) / d2 * cone;
    }
    return radiance;
  }

  // lighting.frag's caustic_irradiance on the exact geometry: only where the light sees p past
  // the refractors (the engine's receiver depth map), the map sampled bilinearly at p's place in
  // the image plane of caustic view `view`, its flux spread over the area the texel's solid angle covers at p.
  glm::vec3 caustic_irradiance(size_t view, glm::vec3 p, glm::vec3 n) const {
    const scene::Light& light = scene_.lights[views_[view].light];
    const scene::Light& seen = views_[view].seen;
    const glm::vec4 clip = light_view_projs_[view] * glm::vec4(p, 1.0f);
    if (clip.w <= 0.0f) return glm::vec3(0.0f);
    const glm::vec2 uv = glm::vec2(clip) / clip.w * 0.5f + 0.5f;
    if (uv.x < 0.0f || uv.y < 0.0f || uv.x > 1.0f || uv.y > 1.0f) return glm::vec3(0.0f);
    const bool directional = light.type == scene::LightType::directional;
    const glm::vec3 to_light = directional ? -light.axis() : light.view.position - p;
    const float r2 = directional ? 1.0f : std::max(glm::dot(to_light, to_light), 1e-8f), r = std::sqrt(r2);
    for (glm::vec3 origin = p + n * epsilon_;;) {  // refractors let the map's light through; nothing else does
      const float reach = directional ? std::numeric_limits<float>::infinity() : glm::distance(origin, light.view.position) - epsilon_;
      auto hit = rays_.intersect(origin, to_light / r, 0.0f, reach);
      if (!hit) break;
      if (!scene_.objects[hit->geometry].material.refractor) return glm::vec3(0.0f);
      origin += to_light / r * (hit->distance + epsilon_);
    }
    const auto& map = *caustic_maps_[view];
    const float cos_theta = std::max(glm::dot(n, to_light / r), 0.0f);
    if (directional) {  // the texel's flux over the area it covers across the light's direction
      const float texel = 2.0f * seen.extent / float(map.width);
      return light.color * sample_bilinear(map, uv) * cos_theta / (texel * texel);
    }
    const float half = std::tan(glm::radians(seen.view.fov_y_degrees) * 0.5f);
    const glm::vec2 plane = (uv * 2.0f - 1.0f) * half;
    const float cos_axis = 1.0f / std::sqrt(1.0f + glm::dot(plane, plane));
    const float texel_solid_angle = 4.0f * half * half / float(map.width * map.height) * cos_axis * cos_axis * cos_axis;
    return light.color * sample_bilinear(map, uv) * cos_theta / (texel_solid_angle * r2);
  }

  // The colour at uv, as a linear sampler with clamp-to-edge reads it (texel centres at
  // (i + 0.5) / size).
  static glm::vec3 sample_bilinear(const io::ImageData& map, glm::vec2 uv) {
    const glm::vec2 c = uv * glm::vec2(float(map.width), float(map.height)) - 0.5f;
    const glm::vec2 base = glm::floor(c), f = c - base;
    auto at = [&](int x, int y) {
      x = std::clamp(x, 0, int(map.width) - 1);
      y = std::clamp(y, 0, int(map.height) - 1);
      return glm::make_vec3(&map.rgba[(size_t(y) * map.width + size_t(x)) * 4]);
    };
    const int x = int(base.x), y = int(base.y);
    return glm::mix(glm::mix(at(x, y), at(x + 1, y), f.x), glm::mix(at(x, y + 1), at(x + 1, y + 1), f.x), f.y);
  }

  // In colour band `band` (-1: white light, every refractor with its index n_d; 0, 1, 2: red, green,
  // blue with their indices, scene::Material::band_iors). Rough refractors scatter the ray about
  // microfacets drawn from `random` and set `rough`.
  glm::vec3 trace(glm::vec3 origin, glm::vec3 direction, Random& random, bool& rough, bool* hit_refractor, int band = -1) const {
    glm::vec3 throughput(1.0f), radiance(0.0f);
    for (int segment = 0; segment < 16; ++segment) {
      auto hit = rays_.intersect(origin, direction, epsilon_, std::numeric_limits<float>::infinity());
      if (!hit) return radiance + throughput * scene_.sky;
      const auto& object = scene_.objects[hit->geometry];
      glm::vec3 p = origin + direction * hit->distance;
      glm::vec3 n = smooth_normal(*hit);
      if (!object.material.refractor && !object.material.double_sided && glm::dot(hit->geometric_normal, direction) > 0.0f) {
        origin = p;  // the back of a single-sided surface: culled, as in the engine's camera view
        continue;
      }
      if (!object.material.refractor)
        return radiance + throughput * shade_opaque(p, exact_.surface(*hit, direction), direction, random, int(hit->geometry));
      if (segment == 0 && hit_refractor) *hit_refractor = true;
      // Entry: reflection sees the sky (as in the engine); of the rest, the share `transmission`
      // passes tinted, the remainder is reflected diffusely with the tint as albedo.
      if (glm::dot(n, direction) > 0) n = -n;
      const scene::Material& m = object.material;
      const float ior = band < 0 || m.thin ? m.ior : m.band_iors()[band];
      const float roughness = exact_.transmission_roughness(*hit);
      rough = rough || roughness > 0.0f;
      const glm::vec3 facet = microfacet_normal(n, direction, roughness, random);
      scene::Material textured;
      const InterfaceCrossing entry =
          cross_interface(exact_.interface_material(*hit, textured), direction, facet, n, exact_.coat_normal(*hit, n), 1.0f, ior);
      radiance += throughput * entry.reflectance * scene_.sky;
      throughput *= 1.0f - entry.reflectance;
      const auto [tint, transmission] = exact_.transmittance(*hit);
      if (transmission < 1.0f) {  // the engine shades a refractor's diffuse share as a Lambertian surface of its tint
        SurfacePoint diffuse;
        diffuse.normal = n;
        diffuse.base = tint;
        radiance += throughput * (1.0f - transmission) * shade_opaque(p, diffuse, direction, random, -1);
      }
      throughput *= transmission * tint;
      origin = p;
      if (m.thin) {  // a thin wall: the ray goes on, unbent where it is smooth
        direction = through_thin(direction, facet, n);
        continue;
      }
      direction = entry.transmitted;
      bool left = false;
      for (int bounce = 0; bounce < kMaxInterfaces && !left; ++bounce) {
        auto inner = rays_.intersect(origin, direction, epsilon_, std::numeric_limits<float>::infinity());
        if (!inner) return radiance;  // an open mesh: the ray is lost inside
        throughput *= glm::exp(-object.material.absorption * inner->distance);
        p = origin + direction * inner->distance;
        glm::vec3 inward = smooth_normal(*inner);
        if (glm::dot(inward, direction) > 0) inward = -inward;
        const float exit_roughness = exact_.transmission_roughness(*inner);
        rough = rough || exit_roughness > 0.0f;
        const InterfaceCrossing exit = cross_interface(exact_.interface_material(*inner, textured), direction,
                                                       microfacet_normal(inward, direction, exit_roughness, random), inward,
                                                       exact_.coat_normal(*inner, inward), ior, 1.0f);
        origin = p;
        if (exit.total_internal()) {
          direction = exit.reflected;
        } else {
          throughput *= 1.0f - exit.reflectance;
          direction = exit.transmitted;
          left = true;
        }
      }
      if (!left) return radiance;  // trapped: its energy stays inside
    }
    return radiance;
  }

 private:
  ExactScene exact_;
  TranslucentLight translucent_;  // over exact_'s scene: built after it
  const scene::Scene& scene_;
  const RayScene& rays_;
  float epsilon_;
  std::vector<scene::CausticView> views_;
  CausticMaps caustic_maps_;                 // per caustic view
  std::vector<glm::mat4> light_view_projs_;  // per caustic view with a map: its view's
};

}  // namespace

RefractionImage render_refraction_reference(const scene::Scene& scene, uint32_t width, uint32_t height, const CausticMaps& caustic_maps,
                                            uint64_t seed, ImageRows range) {
  if (range.end == 0) range.end = height;
  Tracer tracer(scene, caustic_maps);
  const bool disperses = scene.disperses();
  RefractionImage out;
  const uint32_t rows_traced = range.end - range.first;
  out.radiance.width = width;
  out.radiance.height = rows_traced;
  out.radiance.rgba.assign(size_t{width} * rows_traced * 4, 1.0f);
  out.refractor.assign(size_t{width} * rows_traced, 0);
  const glm::mat4 inv = glm::inverse(scene.camera.view_projection(static_cast<float>(width) / static_cast<float>(height)));
  auto rows = [&](uint32_t first, uint32_t step) {
    for (uint32_t y = range.first + first; y < range.end; y += step) {
      for (uint32_t x = 0; x < width; ++x) {
        // Pixel centres, as the engine's gl_FragCoord.
        const glm::vec2 ndc((static_cast<float>(x) + 0.5f) / static_cast<float>(width) * 2 - 1,
                            (static_cast<float>(y) + 0.5f) / static_cast<float>(height) * 2 - 1);
        const glm::vec4 far = inv * glm::vec4(ndc, 1.0f, 1.0f);
        const glm::vec3 direction = glm::normalize(glm::vec3(far) / far.w - scene.camera.position);
        bool refractor = false, rough = false;
        Random random(uint64_t{y} * width + x, seed - 1);  // seed 1: the numbers drawn before the reference had a seed
        glm::vec3 c(0.0f);
        int samples = 0;
        do {
          glm::vec3 sample = tracer.trace(scene.camera.position, direction, random, rough, &refractor);
          if (disperses) {  // each colour band along its own path, as the engine
            for (int band = 0; band < 3; ++band)
              sample[band] = tracer.trace(scene.camera.position, direction, random, rough, nullptr, band)[band];
          }
          c += sample;
        } while (rough && ++samples < kRoughSamples);
        if (rough) c /= float(kRoughSamples);
        const size_t pixel = size_t{y - range.first} * width + x;
        float* px = &out.radiance.rgba[pixel * 4];
        px[0] = c.r;
        px[1] = c.g;
        px[2] = c.b;
        out.refractor[pixel] = refractor ? 1 : 0;
      }
    }
  };
  const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (uint32_t t = 0; t < threads; ++t) pool.emplace_back(rows, t, threads);
  for (auto& t : pool) t.join();
  return out;
}

double refraction_relative_l1(const io::ImageData& engine, const RefractionImage& reference) {
  double difference = 0, total = 0;
  const size_t pixels = reference.refractor.size();
  for (size_t i = 0; i < pixels && i * 4 < engine.rgba.size(); ++i) {
    if (!reference.refractor[i]) continue;
    const double e = static_cast<double>(luminance(&engine.rgba[i * 4])),
                 r = static_cast<double>(luminance(&reference.radiance.rgba[i * 4]));
    difference += std::abs(e - r);
    total += std::abs(r);
  }
  return total > 0 ? difference / total : 0.0;
}

}  // namespace caustica::reference
