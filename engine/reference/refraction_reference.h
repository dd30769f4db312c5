#pragma once
// The ground truth for image-space refraction: the camera image of a scene ray traced on its exact
// geometry with Embree, refracting at every interface (not two), following total internal
// reflection inside, with Fresnel transmittance and absorption. Everything else matches the
// engine's model so that the difference measures the image-space approximation only: the same
// direct lighting (exact shadow rays instead of a shadow map), the same sky, and reflection off a
// refractor's entry surface seeing the sky.
#include <cstdint>
#include <vector>

#include "io/image_io.h"
#include "scene/scene.h"

namespace caustica::reference {

struct RefractionImage {
  io::ImageData radiance;          // linear HDR, rgba32f-like floats
  std::vector<uint8_t> refractor;  // 1 where the primary ray hits a refractor first
};

// With `caustic_maps` (per caustic view, scene::caustic_views: light K's for K below the lights;
// flux per texel of the view's image plane, as the photon reference and the engine hold it; null
// or missing: none), opaque
// surfaces each such light sees past the refractors also receive its map's caustic irradiance,
// projected as the engine's lighting pass projects its own (bilinear, flux over the texel's solid
// angle at the receiver): the scene's picture with the reference's caustics of every light, seen
// directly and through the glass.
//
// Rough refractors draw random numbers keyed on (seed, the pixel's index in the whole image): with
// `rows` (a range [first, end) of the image's rows, end 0: to the last), the rows traced alone are
// those of the whole image, bit for bit, so shards of rows (camera_shard.h) make the one picture.
// The image returned holds the range's rows only.
struct ImageRows {
  uint32_t first = 0, end = 0;
};
using CausticMaps = std::vector<const io::ImageData*>;
RefractionImage render_refraction_reference(const scene::Scene& scene, uint32_t width, uint32_t height,
                                            const CausticMaps& caustic_maps = {}, uint64_t seed = 1, ImageRows rows = {});

// Error between an engine image and the reference, over the reference's refractor pixels:
// sum |engine - reference| / sum |reference|, on luminance.
double refraction_relative_l1(const io::ImageData& engine, const RefractionImage& reference);

}  // namespace caustica::reference
