#include "reference/photon_reference.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <thread>

#include "core/error.h"
#include "reference/exact_scene.h"
#include "reference/interface_physics.h"

namespace caustica::reference {
namespace {

constexpr uint64_t kChunk = 1u << 16;  // photons a thread takes at a time
constexpr int kMaxSegments = 64;       // interfaces one photon may cross, TIR bounces included
// Fixed point: the brightest photon is 2^24 units, so 10^11 of them still fit in 64 bits.
constexpr double kUnitsPerMaxPhoton = 16777216.0;

// A photon's power per colour channel; the totals count the channels' mean, as the engine's counters.
using Power = glm::dvec3;
double mean(const Power& power) {
  return (power.x + power.y + power.z) / 3.0;
}

struct Accumulator {
  std::vector<uint64_t> map, camera;  // three channels per texel
  PhotonTotals totals;                // per thread in double; summed in thread order (only the printout uses them)
};

// Half the side of a caustic view's image plane: at distance 1 (spot, point), or the orthographic
// view's square itself (directional).
float caustic_half_plane(const scene::CausticView& view) {
  const scene::Light& seen = view.seen;
  return seen.type == scene::LightType::directional ? seen.extent : std::tan(glm::radians(seen.view.fov_y_degrees) * 0.5f);
}

// A photon leaving through `ndc` of a light's caustic view: where it starts, where it goes, and its
// share of the power of the piece of image plane it stands for. A directional light's starts on the
// view's near plane and travels along the axis (irradiance times its part of the square); a spot's
// or point light's stands for a piece of the image plane at distance 1, whose solid angle is its
// area times cos^3 of its angle to the axis, within the spot's cone, and for a cube face's view
// within the face's own directions (so that a point light's faces share its photons out).
struct Emission {
  glm::vec3 eye, direction;
  double share;
};
Emission emission(const scene::Light& light, int face, const glm::mat4& inverse_view, float half_plane, glm::vec2 ndc) {
  const bool directional = light.type == scene::LightType::directional;
  const glm::vec4 far = inverse_view * glm::vec4(ndc, 0.5f, 1.0f);
  const glm::vec4 near = inverse_view * glm::vec4(ndc, 0.0f, 1.0f);
  Emission e;
  e.eye = directional ? glm::vec3(near) / near.w : light.view.position;
  e.direction = directional ? light.axis() : glm::normalize(glm::vec3(far) / far.w - e.eye);
  const glm::vec2 plane = ndc * half_plane;
  const double cos_axis = directional ? 1.0 : 1.0 / std::sqrt(1.0 + double(glm::dot(plane, plane)));
  e.share = cos_axis * cos_axis * cos_axis * double(spot_cone(light, e.direction));
  if (face >= 0 && !scene::leaves_through_face(e.direction, face)) e.share = 0.0;
  return e;
}

class PhotonTracer {
 public:
  PhotonTracer(const scene::Scene& scene, const PhotonOptions& options)
      : exact_(scene), options_(options), view_(scene::caustic_views(scene.lights).at(options.light)), light_(scene.lights[view_.light]) {
    // Its photons leave through the caustic view, the engine's caustic map's image plane.
    light_view_proj_ = view_.seen.view_projection();
    disperses_ = scene.disperses();
    inv_light_view_proj_ = glm::inverse(light_view_proj_);
    half_plane_ = caustic_half_plane(view_);
    photon_area_ = 4.0 * double(half_plane_) * double(half_plane_) / double(options.photons);
    max_power_ = double(light_.intensity) * photon_area_;
    unit_ = max_power_ / kUnitsPerMaxPhoton;
    for (const auto& object : scene.objects) band_iors_.push_back(object.material.band_iors());
    if (options.camera_width > 0) {
      camera_view_proj_ = scene.camera.view_projection(float(options.camera_width) / float(options.camera_height));
    }
  }

  double unit() const { return unit_; }

  void trace_photons(uint64_t first, uint64_t end, Accumulator& acc) const {
    for (uint64_t i = first; i < end; ++i) {
      Random random = Random::keyed(options_.seed, i);
      trace(random, acc);
    }
    acc.totals.photons += end - first;
  }

 private:
  void trace(Random& random, Accumulator& acc) const {
    const glm::vec2 uv(random.uniform(), random.uniform());
    const Emission leaving = emission(light_, view_.face, inv_light_view_proj_, half_plane_, uv * 2.0f - 1.0f);
    const glm::vec3 eye = leaving.eye, direction = leaving.direction;
    const double emitted = max_power_ * leaving.share;  // photon_area_ of the image plane
    if (emitted <= 0) return;
    acc.totals.emitted += emitted;
    if (!disperses_) {
      trace_band(random, acc, eye, direction, Power(emitted), -1);
      return;
    }
    for (int band = 0; band < 3; ++band) {  // as the engine: each band its own path, its power in its channel
      Power power(0.0);
      power[band] = emitted;
      trace_band(random, acc, eye, direction, power, band);
    }
  }

  // One photon's path; `band` is -1 for white light (every channel, the index n_d) or the colour
  // band whose index it refracts with.
  void trace_band(Random& random, Accumulator& acc, glm::vec3 eye, glm::vec3 direction, Power power, int band) const {
    const auto& objects = exact_.scene().objects;
    const float epsilon = exact_.epsilon();
    glm::vec3 origin = eye;
    int inside = light_.inside;  // the refractor the photon travels in (a light inside a glass globe starts in it)
    bool refracted = false;
    for (int segment = 0; segment < kMaxSegments; ++segment) {
      const auto hit = exact_.rays().intersect(origin, direction, segment == 0 ? 0.0f : epsilon, std::numeric_limits<float>::infinity());
      if (!hit) {
        (refracted ? acc.totals.escaped : acc.totals.direct) += mean(power);
        return;
      }
      const auto& object = objects[hit->geometry];
      const glm::vec3 p = origin + direction * hit->distance;
      if (inside >= 0) {
        const Power kept = power * glm::exp(-Power(objects[static_cast<size_t>(inside)].material.absorption) * double(hit->distance));
        acc.totals.absorbed += mean(power - kept);
        power = kept;
      }
      if (!object.material.refractor) {
        if (refracted)
          land(p, power, acc);
        else
          acc.totals.direct += mean(power);
        return;
      }
      const bool entering = inside < 0;
      if (!refracted) acc.totals.entering += mean(power);
      glm::vec3 n = exact_.smooth_normal(*hit);
      if (glm::dot(n, direction) > 0) n = -n;
      const float ior = band < 0 ? object.material.ior : band_iors_[hit->geometry][band];
      const glm::vec3 m = microfacet_normal(n, direction, exact_.transmission_roughness(*hit), random);
      // Past the surface's Fresnel reflection only the transmitted share of the power goes on, tinted;
      // the rest is reflected diffusely (not a caustic) and counted with the absorbed.
      auto transmit = [&] {
        const ExactScene::Transmittance passing = exact_.transmittance(*hit);
        const Power kept = power * Power(passing.transmission * passing.tint);
        acc.totals.absorbed += mean(power - kept);
        power = kept;
      };
      // A thin wall is always entered: reflected, or through it (unbent where smooth).
      scene::Material textured;
      const scene::Material& material = exact_.interface_material(*hit, textured);
      const InterfaceCrossing crossing = cross_interface(material, direction, m, n, exact_.coat_normal(*hit, n), entering ? 1.0f : ior,
                                                         entering ? ior : 1.0f, options_.fresnel);
      origin = p;
      const bool first_refractor = !refracted;
      refracted = true;
      if (reflects(crossing, material, n, band, direction, power, random)) {
        // Reflected off the outside too: followed, since it lands on the receivers like any other
        // specular path (3.8% of the ball lens's floor flux); only the exact tracers model it.
        if (entering && first_refractor) acc.totals.reflected += mean(power);
        continue;
      }
      if (entering) transmit();
      if (object.material.thin) {
        direction = through_thin(direction, m, n);
      } else {
        direction = crossing.transmitted;
        inside = entering ? static_cast<int>(hit->geometry) : -1;
      }
    }
    acc.totals.trapped += mean(power);
  }

  // Whether a photon reflects off an interface: off the clear coat first (about a facet of the
  // coat's roughness around the coat's normal), else off the base with its probability (choice_probability), its power
  // weighted so that its expectation is what each side of the interface takes. Sets `direction`
  // where it reflects.
  static bool reflects(const InterfaceCrossing& crossing, const scene::Material& material, glm::vec3 n, int band, glm::vec3& direction,
                       Power& power, Random& random) {
    if (crossing.coat > 0.0f && random.uniform() < crossing.coat) {
      const glm::vec3 facet = microfacet_normal(crossing.coat_normal, direction, material.clearcoat_roughness, random);
      direction = on_side(glm::reflect(direction, facet), n, true);
      return true;
    }
    const glm::vec3 base = crossing.base();
    const float p = choice_probability(base, band);
    const bool reflected = p > 0.0f && random.uniform() < p;
    power *= Power(reflected ? choice_weight(base, p) : choice_weight(1.0f - base, 1.0f - p));
    if (reflected) direction = crossing.reflected;
    return reflected;
  }

  void land(glm::vec3 p, const Power& power, Accumulator& acc) const {
    const glm::vec4 clip = light_view_proj_ * glm::vec4(p, 1.0f);
    const glm::vec2 uv = clip.w > 0 ? glm::vec2(clip) / clip.w * 0.5f + 0.5f : glm::vec2(-1.0f);
    if (uv.x < 0 || uv.y < 0 || uv.x >= 1 || uv.y >= 1) {
      acc.totals.off_map += mean(power);
      return;
    }
    acc.totals.landed += mean(power);
    ++acc.totals.landed_photons;
    const glm::u64vec3 units(glm::round(power / unit_));
    const uint32_t size = options_.map_size;
    const uint32_t x = std::min(size - 1, static_cast<uint32_t>(uv.x * float(size)));
    const uint32_t y = std::min(size - 1, static_cast<uint32_t>(uv.y * float(size)));
    for (int c = 0; c < 3; ++c) acc.map[(size_t{y} * size + x) * 3 + static_cast<size_t>(c)] += units[c];
    if (options_.camera_width == 0) return;
    const glm::vec4 cam = camera_view_proj_ * glm::vec4(p, 1.0f);
    if (cam.w <= 0) return;
    const glm::vec2 cam_uv = glm::vec2(cam) / cam.w * 0.5f + 0.5f;
    if (cam_uv.x < 0 || cam_uv.y < 0 || cam_uv.x >= 1 || cam_uv.y >= 1) return;
    const glm::vec3 to_p = p - exact_.scene().camera.position;
    const float distance = glm::length(to_p);
    if (exact_.rays().intersect(exact_.scene().camera.position, to_p / distance, 0.0f, distance - 2 * exact_.epsilon())) return;  // hidden
    const uint32_t cx = std::min(options_.camera_width - 1, static_cast<uint32_t>(cam_uv.x * float(options_.camera_width)));
    const uint32_t cy = std::min(options_.camera_height - 1, static_cast<uint32_t>(cam_uv.y * float(options_.camera_height)));
    for (int c = 0; c < 3; ++c) acc.camera[(size_t{cy} * options_.camera_width + cx) * 3 + static_cast<size_t>(c)] += units[c];
  }

  ExactScene exact_;
  const PhotonOptions& options_;
  const scene::CausticView view_;
  const scene::Light& light_;
  glm::mat4 light_view_proj_{1.0f}, inv_light_view_proj_{1.0f}, camera_view_proj_{1.0f};
  float half_plane_ = 1.0f;
  bool disperses_ = false;  // Scene::disperses: every photon is traced once per colour band
  std::vector<glm::vec3> band_iors_;
  double photon_area_ = 0, max_power_ = 0, unit_ = 1;
};

io::ImageData grey_image(uint32_t width, uint32_t height) {
  io::ImageData image;
  image.width = width;
  image.height = height;
  image.rgba.assign(size_t{width} * height * 4, 1.0f);
  return image;
}

// Units to flux, each texel scaled by scale(texel index).
template <typename Scale>
void resolve_units(const std::vector<uint64_t>& units, double unit, io::ImageData& image, Scale&& scale) {
  const size_t texels = size_t{image.width} * image.height;
  for (size_t i = 0; i < texels; ++i) {
    const double texel_scale = scale(i);
    for (size_t c = 0; c < 3; ++c) image.rgba[i * 4 + c] = static_cast<float>(double(units[i * 3 + c]) * unit * texel_scale);
  }
}

}  // namespace

void add_totals(PhotonTotals& to, const PhotonTotals& from) {
  to.photons += from.photons;
  to.landed_photons += from.landed_photons;
  to.emitted += from.emitted;
  to.direct += from.direct;
  to.entering += from.entering;
  to.landed += from.landed;
  to.off_map += from.off_map;
  to.reflected += from.reflected;
  to.escaped += from.escaped;
  to.trapped += from.trapped;
  to.absorbed += from.absorbed;
}

double caustic_view_flux(const scene::Light& light, const scene::CausticView& view) {
  if (!view.present) return 0.0;
  // The tracer's emission integrated on a grid of the image plane (midpoints).
  constexpr int kSide = 512;
  const glm::mat4 inverse_view = glm::inverse(view.seen.view_projection());
  const float half = caustic_half_plane(view);
  double sum = 0;
  for (int y = 0; y < kSide; ++y) {
    for (int x = 0; x < kSide; ++x) {
      const glm::vec2 ndc((float(x) + 0.5f) / kSide * 2.0f - 1.0f, (float(y) + 0.5f) / kSide * 2.0f - 1.0f);
      sum += emission(light, view.face, inverse_view, half, ndc).share;
    }
  }
  return double(light.intensity) * 4.0 * double(half) * double(half) * sum / double(kSide * kSide);
}

double caustic_view_flux(const scene::Light& light) {
  double flux = 0;
  for (const scene::CausticView& view : scene::caustic_views({light})) flux += caustic_view_flux(light, view);
  return flux;
}

std::vector<uint64_t> photons_per_view(const scene::Scene& scene, uint64_t photons) {
  std::vector<double> flux;
  for (const auto& view : scene::caustic_views(scene.lights)) flux.push_back(caustic_view_flux(scene.lights[view.light], view));
  double total = 0;
  for (double f : flux) total += f;
  std::vector<uint64_t> share(flux.size(), 0);
  if (total <= 0) return share;
  // Each its floor, then what rounding left to the largest remainders: they add up to `photons`.
  uint64_t given = 0;
  std::vector<std::pair<double, size_t>> remainders;
  for (size_t i = 0; i < flux.size(); ++i) {
    const double exact = double(photons) * flux[i] / total;
    share[i] = static_cast<uint64_t>(exact);
    given += share[i];
    if (flux[i] > 0) remainders.emplace_back(exact - std::floor(exact), i);
  }
  std::stable_sort(remainders.begin(), remainders.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  for (size_t k = 0; given < photons && k < remainders.size(); ++k, ++given) ++share[remainders[k].second];
  return share;
}

PhotonSums trace_photon_sums(const scene::Scene& scene, const PhotonOptions& options) {
  const std::vector<scene::CausticView> views = scene::caustic_views(scene.lights);
  if (options.light >= views.size()) {
    throw InputError(scene.path + ": the photon reference traces through caustic view " + std::to_string(options.light) +
                     ", and the scene has " + std::to_string(views.size()) +
                     " (one per light, and a point light among its refractors one per cube face that holds one)");
  }
  if (!views[options.light].present) {
    throw InputError(scene.path + ": light " + std::to_string(options.light) +
                     " is a point light that reaches no refractor: it has no caustic view to trace photons through, and throws "
                     "no caustic in the engine either");
  }
  if (options.photons == 0 || options.map_size == 0) throw InputError("the photon reference needs at least one photon and texel");
  const uint64_t first = options.first_photon, end = options.end_photon > 0 ? options.end_photon : options.photons;
  if (first >= end || end > options.photons) {
    throw InputError("photons " + std::to_string(first) + " to " + std::to_string(end) + " are not a range of the " +
                     std::to_string(options.photons) + " photons");
  }
  const PhotonTracer tracer(scene, options);
  const unsigned threads = options.threads > 0 ? options.threads : std::max(1u, std::thread::hardware_concurrency());
  const uint64_t count = end - first, chunks = (count + kChunk - 1) / kChunk;
  std::vector<Accumulator> accumulators(threads);
  std::atomic<uint64_t> next_chunk{0}, photons_done{0};
  auto work = [&](Accumulator& acc) {
    acc.map.assign(size_t{options.map_size} * options.map_size * 3, 0);
    acc.camera.assign(size_t{options.camera_width} * options.camera_height * 3, 0);
    for (uint64_t chunk; (chunk = next_chunk.fetch_add(1)) < chunks;) {
      const uint64_t chunk_first = first + chunk * kChunk, chunk_end = std::min(end, chunk_first + kChunk);
      tracer.trace_photons(chunk_first, chunk_end, acc);
      photons_done.fetch_add(chunk_end - chunk_first);
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 0; t < threads; ++t) pool.emplace_back(work, std::ref(accumulators[t]));
  while (options.progress && photons_done.load() < count) {
    options.progress(photons_done.load(), count);
    std::this_thread::sleep_for(std::chrono::milliseconds(250));
  }
  for (auto& t : pool) t.join();
  if (options.progress) options.progress(count, count);

  PhotonSums sums;
  sums.unit = tracer.unit();
  sums.map.assign(accumulators.front().map.size(), 0);
  sums.camera.assign(accumulators.front().camera.size(), 0);
  for (const auto& acc : accumulators) {
    add_totals(sums.totals, acc.totals);
    for (size_t i = 0; i < sums.map.size(); ++i) sums.map[i] += acc.map[i];
    for (size_t i = 0; i < sums.camera.size(); ++i) sums.camera[i] += acc.camera[i];
  }
  return sums;
}

io::ImageData caustic_map_from_sums(const std::vector<uint64_t>& units, uint32_t map_size, double unit) {
  io::ImageData map = grey_image(map_size, map_size);
  resolve_units(units, unit, map, [](size_t) { return 1.0; });
  return map;
}

PhotonReference trace_photon_reference(const scene::Scene& scene, const PhotonOptions& options) {
  const PhotonSums sums = trace_photon_sums(scene, options);
  PhotonReference out;
  out.caustic_map = caustic_map_from_sums(sums.map, options.map_size, sums.unit);
  out.camera = grey_image(options.camera_width, options.camera_height);
  out.totals = sums.totals;
  if (options.camera_width > 0) {
    // Flux per pixel over the receiver area the pixel covers, from a ray through its centre.
    const ExactScene exact(scene);
    const float aspect = float(options.camera_width) / float(options.camera_height);
    const glm::mat4 inv = glm::inverse(scene.camera.view_projection(aspect));
    const double side = 2.0 * std::tan(double(glm::radians(scene.camera.fov_y_degrees)) * 0.5) / double(options.camera_height);
    const glm::vec3 axis = glm::normalize(scene.camera.target - scene.camera.position);
    resolve_units(sums.camera, sums.unit, out.camera, [&](size_t i) {
      const uint32_t x = static_cast<uint32_t>(i % options.camera_width), y = static_cast<uint32_t>(i / options.camera_width);
      const glm::vec2 ndc((float(x) + 0.5f) / float(options.camera_width) * 2 - 1,
                          (float(y) + 0.5f) / float(options.camera_height) * 2 - 1);
      const glm::vec4 far = inv * glm::vec4(ndc, 1.0f, 1.0f);
      const glm::vec3 d = glm::normalize(glm::vec3(far) / far.w - scene.camera.position);
      const auto hit = exact.rays().intersect(scene.camera.position, d, 0.0f, std::numeric_limits<float>::infinity());
      if (!hit) return 0.0;
      const double cos_view = std::abs(double(glm::dot(hit->geometric_normal, d)));
      const double cos_axis = double(glm::dot(d, axis));
      const double area =
          side * side * cos_axis * cos_axis * cos_axis * double(hit->distance) * double(hit->distance) / std::max(cos_view, 1e-6);
      return 1.0 / area;
    });
  }
  return out;
}

}  // namespace caustica::reference
