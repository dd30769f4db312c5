#pragma once
// KHR_materials_sheen's "Charlie" lobe (Estevez & Kulla 2017, with Ashikhmin's visibility, which the
// extension allows) and its directional albedo E, which the specification's albedo scaling of the
// layers beneath needs. The scene integrates E once per sheen material into a table that the device
// interpolates (ObjectData::sheen_albedo, scene/surface.glsl); the reference (reference/
// surface_physics.h) integrates E at every point it shades. Written from the extension's text, apart
// from the device's lobe.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

namespace caustica::scene {

// The sheen's alpha, kept at 1e-3 or more so that its exponent 1 / alpha stays finite.
inline float sheen_alpha(float roughness) {
  return std::max(roughness * roughness, 1e-3f);
}

// The Charlie distribution, (2 + 1/alpha) sin(theta_h)^(1/alpha) / (2 pi), with the sine's power
// taken from its square (sin^2 = 1 - (n.h)^2) so that no square root is needed.
inline float sheen_distribution(float roughness, float n_h) {
  const float alpha = sheen_alpha(roughness);
  const float sin2 = std::max(1.0f - n_h * n_h, 0.0f);
  return (2.0f + 1.0f / alpha) * std::pow(sin2, 0.5f / alpha) / (2.0f * glm::pi<float>());
}

// Ashikhmin's visibility, 1 / (4 (n.l + n.v - n.l n.v)). Both cosines grazing (0) is a direction
// pair that sees nothing of the surface: 0 rather than a division by zero.
inline float sheen_visibility(float n_l, float n_v) {
  n_l = std::clamp(n_l, 0.0f, 1.0f);
  n_v = std::clamp(n_v, 0.0f, 1.0f);
  const float den = 4.0f * (n_l + n_v - n_l * n_v);
  return den > 0.0f ? 1.0f / den : 0.0f;
}

// The sheen lobe's directional albedo E(mu): the integral of D V (n.l) over the hemisphere of l,
// for a white sheen seen at n.v = mu. Midpoint rule on 64 x 64 cells of (s, phi_l), phi_l over
// [0, pi] only: the lobe is mirror-symmetric about the plane of n and v, so that half counts twice
// (the density of 64 x 128 over the whole circle). theta_l = (pi/2) s (2 - s) crowds the cells
// toward the horizon, where the integrand changes on the scale of mu (V's n.l / (n.l + mu)) and
// where a smooth sheen's D peaks, yet stays linear in s at the pole, where D at roughness 1 has a
// kink in theta. Uniform in theta, 64 x 128 cells erred by up to 1.5e-3 at roughness 0.3 and 9e-3
// at 0.1; this grid is within 1.6e-4 relative for mu >= 0.01 (surface_physics_test.cpp measures it).
inline float sheen_albedo(float mu, float roughness) {
  constexpr int kS = 64, kPhi = 64;
  const float pi = glm::pi<float>();
  mu = std::clamp(mu, 0.0f, 1.0f);
  const glm::vec3 v(std::sqrt(1.0f - mu * mu), 0.0f, mu);
  const float d_s = 1.0f / kS, d_phi = pi / kPhi;
  double sum = 0.0;
  for (int i = 0; i < kS; ++i) {
    const float s = (static_cast<float>(i) + 0.5f) * d_s;
    const float theta = 0.5f * pi * s * (2.0f - s);
    const float sin_t = std::sin(theta), cos_t = std::cos(theta);
    double ring = 0.0;
    for (int j = 0; j < kPhi; ++j) {
      const float phi = (static_cast<float>(j) + 0.5f) * d_phi;
      const glm::vec3 l(sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t);
      const float n_h = glm::normalize(v + l).z;
      ring += static_cast<double>(sheen_distribution(roughness, n_h) * sheen_visibility(cos_t, mu));
    }
    // The cosine n.l, times dω = sin(theta) dtheta dphi with dtheta = pi (1 - s) ds.
    sum += ring * static_cast<double>(cos_t * sin_t * pi * (1.0f - s));
  }
  return static_cast<float>(2.0 * sum * static_cast<double>(d_s * d_phi));
}

// E at mu_k = (k / 15)^2 for the device, which interpolates it linearly in sqrt(mu) as
// sheen_albedo_from_table does: E falls steeply near grazing, where the samples crowd (the worst
// error over mu at roughness 0.1, 0.3, 0.5, 1: 0.075, 0.012, 0.0056, 0.0027, against 0.53, 0.068,
// 0.030, 0.015 with samples even in mu). mu = 0 stands for the grazing limit: sampled at 1e-4, where
// the view still has a direction.
inline std::array<float, 16> sheen_albedo_table(float roughness) {
  std::array<float, 16> table{};
  for (std::size_t k = 0; k < table.size(); ++k) {
    const float s = static_cast<float>(k) / 15.0f;
    table[k] = sheen_albedo(std::max(s * s, 1e-4f), roughness);
  }
  return table;
}

inline float sheen_albedo_from_table(const std::array<float, 16>& table, float mu) {
  const float x = std::sqrt(std::clamp(mu, 0.0f, 1.0f)) * 15.0f;
  // mu = 1 falls on the last sample: its cell is the last one, at its far end.
  const std::size_t k = std::min(static_cast<std::size_t>(x), std::size_t{14});
  return glm::mix(table[k], table[k + 1], x - static_cast<float>(k));
}

}  // namespace caustica::scene
