#pragma once
// A thin film's reflectance (KHR_materials_iridescence): the Airy sum of its two interfaces at each
// colour channel's wavelength, for the references' refractor interfaces (reference/
// interface_physics.h) and opaque surfaces (reference/surface_physics.h) alike.
#include <algorithm>
#include <cmath>
#include <glm/gtc/constants.hpp>

namespace caustica::reference {

// Each channel's wavelength in nm: the Fraunhofer lines C (red), d (green) and F (blue), the ones
// the dispersion bands' indices are given at, so that a film and dispersion agree on a channel.
inline constexpr float kChannelWavelengthsNm[3] = {656.27f, 587.56f, 486.13f};

// The cosine, in a layer of index n_k, of a ray at cosine cos_j in index n_j (Snell's law). 0 where
// the ray cannot enter the layer: its amplitude coefficients then become +-1 (total reflection; the
// tunnelling of an evanescent wave through a thin layer is not modelled).
inline float snell_cos(float cos_j, float n_j, float n_k) {
  const float sin_k = n_j / n_k * std::sqrt(std::max(0.0f, 1.0f - cos_j * cos_j));
  return sin_k >= 1.0f ? 0.0f : std::sqrt(1.0f - sin_k * sin_k);
}

// (a - b) / (a + b): both polarisations' amplitude coefficients have this form. a = b = 0 (grazing
// on both sides) is the grazing limit, total reflection.
inline float amplitude_ratio(float a, float b) {
  return a + b > 0.0f ? (a - b) / (a + b) : 1.0f;
}

// The Airy sum of a layer's two interfaces for one polarisation, |r12 + r23 e^{i delta}|^2 /
// |1 + r12 r23 e^{i delta}|^2. The denominator reaches 0 only with |r12 r23| = 1, both interfaces
// reflecting everything, whose limit is 1.
inline float airy_reflectance(float r12, float r23, float cos_delta) {
  const float cross = 2.0f * r12 * r23 * cos_delta;
  const float den = 1.0f + r12 * r12 * r23 * r23 + cross;
  if (den <= 1e-12f) return 1.0f;
  return std::clamp((r12 * r12 + r23 * r23 + cross) / den, 0.0f, 1.0f);
}

// Unpolarised reflectance at `wavelength_nm` of the stack incident medium (eta_i) | film (film_ior,
// thickness_nm) | substrate (eta_t), met at cosine cos_i: the mean of the s and p Airy reflectances.
inline float thin_film_reflectance(float cos_i, float eta_i, float film_ior, float thickness_nm, float eta_t, float wavelength_nm) {
  const float c1 = cos_i, c2 = snell_cos(cos_i, eta_i, film_ior), c3 = snell_cos(cos_i, eta_i, eta_t);
  const float n1 = eta_i, n2 = film_ior, n3 = eta_t;
  // The phase one round trip through the film adds over the light reflected at its top.
  const float delta = 4.0f * glm::pi<float>() * n2 * thickness_nm * c2 / wavelength_nm;
  const float cos_delta = std::cos(delta);
  const float s = airy_reflectance(amplitude_ratio(n1 * c1, n2 * c2), amplitude_ratio(n2 * c2, n3 * c3), cos_delta);
  const float p = airy_reflectance(amplitude_ratio(n2 * c1, n1 * c2), amplitude_ratio(n3 * c2, n2 * c3), cos_delta);
  return 0.5f * (s + p);
}

}  // namespace caustica::reference
