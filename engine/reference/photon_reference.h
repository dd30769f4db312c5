#pragma once
// The ground truth for caustics: photons from one of the scene's lights, through its caustic view
// (scene::Light::caustic_view: a spot or directional light's own view, a point light's frustum
// about its refractors), traced on the exact geometry with Embree through every interface, with exact Fresnel and total internal reflection
// (reflect or transmit chosen at random by the reflectance), until they land on an opaque
// receiver. What lands is accumulated as the engine's caustic map holds it (flux per texel of the
// light's image plane) and, optionally, as the caustic irradiance the camera sees.
//
// Deterministic for a seed: each photon's random numbers are keyed on (seed, its index among all
// the photons) and what lands is summed in fixed point, so neither the thread count, the scheduling
// nor a split into shards (processes that each trace a range of the photons) changes a single bit.
#include <cstdint>
#include <functional>
#include <vector>

#include "io/image_io.h"
#include "scene/scene.h"

namespace caustica::reference {

struct PhotonOptions {
  // The caustic view whose photons are traced (scene::caustic_views): light K's for K below the
  // scene's lights, a point light's further cube faces after them.
  uint32_t light = 0;
  uint64_t photons = 10'000'000;
  uint64_t seed = 1;
  // The range of the `photons` traced here, [first_photon, end_photon); end 0: to the last. Each
  // photon still carries 1 / `photons` of the light, so shards' sums add up to the whole map.
  uint64_t first_photon = 0, end_photon = 0;
  uint32_t map_size = 512;                       // the light-space map's side, as the graphs' caustic_size
  uint32_t camera_width = 0, camera_height = 0;  // 0: no camera image
  bool fresnel = true;   // false: every photon transmits unless total internal reflection (docs/oracles.md's "no Fresnel")
  unsigned threads = 0;  // 0: every core
  std::function<void(uint64_t done, uint64_t total)> progress;  // called from the calling thread
};

// Flux (the light's units) by what became of it. emitted = direct + entering; entering =
// landed + off_map + escaped + trapped + absorbed, up to float rounding. Photons that reflect off a
// refractor's outside are followed like every other path (they land, escape, ...); `reflected` is
// how much of the entering flux did so at the first refractor it met.
struct PhotonTotals {
  uint64_t photons = 0;
  uint64_t landed_photons = 0;  // how many photons make up `landed`: its sampling error is about 1 / sqrt of it
  double emitted = 0;           // everything the light sent into its view
  double direct = 0;            // met an opaque surface or nothing before any refractor: not a caustic
  double entering = 0;          // met a refractor first
  double landed = 0;            // reached an opaque receiver inside the light's view: in the map
  double off_map = 0;           // reached a receiver outside the light's view
  double reflected = 0;         // reflected off a refractor's outside at its first meeting (Fresnel), then followed
  double escaped = 0;           // left the scene after refracting
  double trapped = 0;           // still bouncing inside after the interface limit
  double absorbed = 0;          // by the refractors' absorption
};

struct PhotonReference {
  io::ImageData caustic_map;  // map_size^2, flux per texel and colour channel (the totals are the channels' mean)
  io::ImageData camera;       // caustic irradiance (flux per receiver area) per camera pixel, if asked
  PhotonTotals totals;
};

// What the photons of a range left, before it becomes a map: flux in fixed-point units (three
// channels per texel) that add exactly, whatever order shards are added in.
struct PhotonSums {
  std::vector<uint64_t> map, camera;
  double unit = 1;  // flux per unit: depends on the scene's light and the photon count alone
  PhotonTotals totals;
};

// Throws InputError when options.light is not one of the scene's lights, or has no caustic view.
PhotonReference trace_photon_reference(const scene::Scene& scene, const PhotonOptions& options);
// The photons of options' range only, as sums (a shard of the reference).
PhotonSums trace_photon_sums(const scene::Scene& scene, const PhotonOptions& options);
// The caustic map (flux per texel) of sums of a map_size^2 map.
io::ImageData caustic_map_from_sums(const std::vector<uint64_t>& units, uint32_t map_size, double unit);
void add_totals(PhotonTotals& to, const PhotonTotals& from);

// The flux a light sends through a caustic view of its own (its photons' emitted total, the light's
// units): a directional light's irradiance over the view's square, a spot or point light's
// intensity over the solid angle of the view (within a spot's cone, a cube face's own directions).
// 0 for a view that is not present.
double caustic_view_flux(const scene::Light& light, const scene::CausticView& view);
// Through every caustic view it has (a point light's cube faces together: 4 pi times its intensity
// where they cover every direction).
double caustic_view_flux(const scene::Light& light);
// `photons` shared among the scene's caustic views (scene::caustic_views) in proportion to
// caustic_view_flux, so that every photon carries about the same flux whichever light sent it: per
// view (0 where it sends none, or its share rounds to none); they add up to `photons`.
std::vector<uint64_t> photons_per_view(const scene::Scene& scene, uint64_t photons);

}  // namespace caustica::reference
