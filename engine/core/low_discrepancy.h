#pragma once
// Points that cover a square evenly however many of them are taken: where a frame's photons start
// in their grid cells (caustic_map's jitter) and where in its pixel a still camera's frame looks
// (graph::FrameInfo::camera_jitter).
#include <cmath>
#include <cstdint>
#include <glm/vec2.hpp>

namespace caustica {

// The R2 sequence's point n in [0, 1)^2 (Roberts 2018: the generalised golden ratio's reciprocal
// powers), (0.5, 0.5) at n = 0; in double so that it stays exact over millions of frames.
inline glm::vec2 r2_point(uint64_t n) {
  constexpr double kAlpha1 = 0.7548776662466927, kAlpha2 = 0.5698402909980532;
  const double x = 0.5 + kAlpha1 * static_cast<double>(n), y = 0.5 + kAlpha2 * static_cast<double>(n);
  return {static_cast<float>(x - std::floor(x)), static_cast<float>(y - std::floor(y))};
}

}  // namespace caustica
