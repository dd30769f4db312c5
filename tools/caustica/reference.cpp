// caustica reference and caustica merge: the ground truth with Embree, whole or as shards for a
// cluster, and the shards joined into what one process writes (docs/cluster.md).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "bench_common.h"
#include "cli.h"
#include "core/error.h"
#include "core/paths.h"
#include "flags.h"
#include "io/files.h"
#include "io/image_io.h"
#include "reference/camera_shard.h"
#include "reference/photon_reference.h"
#include "reference/photon_shard.h"
#include "reference/refraction_reference.h"
#include "scene/scene.h"

namespace caustica::cli {
namespace {

struct Shard {
  uint64_t index = 0, count = 0;  // count 0: the whole reference
};

// --shard I/K, I from 0; auto/K: I is the array index that Slurm or Kubernetes gives the process.
Shard parse_shard(const std::string& text) {
  const std::string usage = "--shard " + text + ": expected INDEX/COUNT, INDEX from 0 to COUNT - 1 or auto, e.g. 3/64 or auto/64";
  const size_t slash = text.find('/');
  if (slash == std::string::npos) throw UsageError(usage + (text == "auto" ? " (auto gives the index; the count is yours to give)" : ""));
  Shard shard;
  try {
    shard.count = parse_uint("--shard", text.substr(slash + 1), 1, 1'000'000);
  } catch (const UsageError&) {
    throw UsageError(usage + " (the count '" + text.substr(slash + 1) + "' is not a whole number from 1 to 1000000)");
  }
  std::string index = text.substr(0, slash), from = "--shard";
  if (index == "auto") {
    std::tie(index, from) = bench::scheduler_index();
    if (from.empty()) {
      throw UsageError("--shard " + text + ": neither SLURM_ARRAY_TASK_ID (a Slurm job array) nor JOB_COMPLETION_INDEX (a Kubernetes " +
                       "Indexed Job) is set; outside a scheduler give the index: --shard I/" + std::to_string(shard.count));
    }
  }
  try {
    shard.index = parse_uint(from, index, 0, shard.count - 1);
  } catch (const UsageError&) {
    const std::string what = from == "--shard" ? "the index '" + index + "'" : "the index that " + from + " gives, '" + index + "',";
    throw UsageError(usage + " (" + what + " is not a whole number from 0 to " + std::to_string(shard.count - 1) + ")");
  }
  return shard;
}

void print_photon_flux(const reference::PhotonTotals& t) {
  std::printf("flux emitted %.6g: direct %.6g, entering a refractor %.6g\n", t.emitted, t.direct, t.entering);
  std::printf(
      "of the entering flux: landed in the map %.6g (%.2f%%), off the map %.6g, escaped %.6g, trapped %.6g, absorbed %.6g; "
      "reflected off the outside first %.6g (followed)\n",
      t.landed, t.entering > 0 ? 100.0 * t.landed / t.entering : 0.0, t.off_map, t.escaped, t.trapped, t.absorbed, t.reflected);
}

// One shard of the photon reference: its range's sums, exactly, with what it is a part of.
int trace_photon_shard(const scene::Scene& scene, reference::PhotonOptions photons, const Shard& shard, const std::string& out) {
  const auto start = std::chrono::steady_clock::now();
  const auto [first, end] = reference::shard_range(photons.photons, shard.index, shard.count);
  ProgressLine progress("photons", end - first);
  if (end - first >= 10'000'000 || ::isatty(STDERR_FILENO)) photons.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
  const reference::TracedShard traced = reference::trace_photon_shard(scene, photons, shard.index, shard.count);
  const reference::PhotonShard& header = traced.shard;
  reference::write_photon_shard(out, header, traced.map_units);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("shard %llu/%llu: photons %llu to %llu of %llu in %.2f s (%.1f M/s), seed %llu\n",
              static_cast<unsigned long long>(shard.index), static_cast<unsigned long long>(shard.count),
              static_cast<unsigned long long>(header.first), static_cast<unsigned long long>(header.end - 1),
              static_cast<unsigned long long>(header.total), seconds, double(end - first) / seconds * 1e-6,
              static_cast<unsigned long long>(header.seed));
  print_photon_flux(header.totals);
  std::fprintf(stderr, "reference: %s shard %llu/%llu -> %s\n", scene.name.c_str(), static_cast<unsigned long long>(shard.index),
               static_cast<unsigned long long>(shard.count), out.c_str());
  return 0;
}

// One shard of the ray-traced camera reference: its range of rows, exactly, with what it is a part of.
int trace_camera_shard(const scene::Scene& scene, uint32_t width, uint32_t height, const reference::CausticMaps& caustic_maps,
                       uint64_t seed, const Shard& shard, const std::string& out) {
  const auto start = std::chrono::steady_clock::now();
  const reference::TracedCameraShard traced =
      reference::trace_camera_shard(scene, width, height, caustic_maps, seed, shard.index, shard.count);
  const reference::CameraShard& header = traced.shard;
  reference::write_camera_shard(out, header, traced.rows);
  std::printf("shard %llu/%llu: rows %llu to %llu of %ux%u in %.2f s, seed %llu\n", static_cast<unsigned long long>(shard.index),
              static_cast<unsigned long long>(shard.count), static_cast<unsigned long long>(header.first),
              static_cast<unsigned long long>(header.end - 1), width, height,
              std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), static_cast<unsigned long long>(seed));
  std::fprintf(stderr, "reference: %s shard %llu/%llu -> %s\n", scene.name.c_str(), static_cast<unsigned long long>(shard.index),
               static_cast<unsigned long long>(shard.count), out.c_str());
  return 0;
}

// What reference is told.
struct ReferenceOptions {
  std::string scene = (data_dir() / kDefaultScene).string(), out, camera_out, picture_out;
  std::vector<std::pair<uint32_t, std::string>> caustics_files;  // --caustics [LIGHT=]MAP.exr: the light's map
  uint32_t width = 1280, height = 720;
  double exposure = 1.0;
  bool exposure_given = false;
  bool stage = true;
  reference::PhotonOptions photons;
  Shard shard;
  ReferenceOptions() { photons.photons = 0; }
};

// --caustics [I=]MAP.exr: light I's map (a bare file is light 0's; a file may start with digits
// and '=' only as I=).
std::pair<uint32_t, std::string> parse_caustics_file(const std::string& value, const std::vector<std::pair<uint32_t, std::string>>& given) {
  const size_t eq = value.find('=');
  uint32_t light = 0;
  std::string file = value;
  if (eq != std::string::npos && eq > 0 && value.find_first_not_of("0123456789") == eq) {
    light = static_cast<uint32_t>(parse_uint("--caustics", value.substr(0, eq), 0, 1023));
    file = value.substr(eq + 1);
  }
  if (file.empty()) throw UsageError("--caustics " + value + ": expected [LIGHT=]MAP.exr");
  for (const auto& [other, other_file] : given) {
    if (other == light)
      throw UsageError("--caustics " + value + ": light " + std::to_string(light) + " has a map already (" + other_file + ")");
  }
  return {light, file};
}

FlagTable reference_flags(ReferenceOptions& o) {
  return {
      scene_flag(o.scene, nullptr, "the scene (default: scenes/glass_bunny.json), or a model file (as for render)"),
      no_stage_flag(o.stage),
      text_flag("--out", "FILE", "the image (required)", o.out),
      size_flag(o.width, o.height, "camera image size (default 1280x720)"),
      uint_flag("--photons", "N", "photons to trace, e.g. 1e8", o.photons.photons, 1, 100'000'000'000ull),
      uint_flag("--seed", "K", "random seed (default 1): the photons', or the rough refractors' paths", o.photons.seed, 0, ~0ull),
      uint32_flag("--light", "I",
                  "with --photons: the caustic view whose photons are traced: light I's (default 0, the first); a point light\n"
                  "among its refractors has one per cube face, the faces after the first numbered after the lights",
                  o.photons.light, 0, 1023),
      text_flag("--picture", "FILE.exr|.png",
                "with --photons: every light's photons (N shared by the flux each sends through its\n"
                "caustic view), then the camera picture lit by all their maps (--size, --exposure)",
                o.picture_out),
      uint32_flag("--map-size", "N", "side of the light-space map (default 512, the graphs' caustic_size)", o.photons.map_size, 1, 8192),
      text_flag("--camera", "FILE.exr", "also write the caustic irradiance seen by the camera", o.camera_out),
      switch_flag("--no-fresnel", "transmit every photon unless total internal reflection (the graphs' fresnel=false)", o.photons.fresnel,
                  false),
      {"--shard", "I/K",
       "trace the I-th of K parts of the photons, or without --photons of the image's\n"
       "rows (I from 0; auto/K: from the scheduler)",
       [&o](const std::string& v) { o.shard = parse_shard(v); }},
      {"--caustics", "[I=]MAP.exr",
       "without --photons: light the picture with caustic view I's map too (light I's;\n"
       "I default 0; repeatable, one map a view)",
       [&o](const std::string& v) { o.caustics_files.push_back(parse_caustics_file(v, o.caustics_files)); }, true},
      {"--exposure", "E", "a PNG picture's exposure (default 1, as the graphs')", [&o](const std::string& v) {
         o.exposure = parse_number("--exposure", v, 0.0, 100.0);
         o.exposure_given = true;
       }}};
}

// The combinations of flags that cannot go together, refused before any work; returns --out's extension.
std::string check_reference(const ReferenceOptions& o) {
  const uint64_t photons = o.photons.photons;
  const bool picture = !o.picture_out.empty();
  if (picture) {
    if (photons == 0) throw UsageError("--picture goes with --photons N: the photons of every light, then the picture they light");
    if (!o.out.empty() || !o.camera_out.empty() || o.shard.count > 0 || o.photons.light != 0)
      throw UsageError(
          "--picture writes the picture alone: a light's map is --light I --out MAP.exr, and on a cluster its shards, "
          "merged, light the picture through --caustics I=MAP.exr (docs/cluster.md)");
    return io::check_image_output(o.picture_out);
  }
  if (o.out.empty()) throw UsageError("reference needs --out FILE.exr (or, with --photons, --picture FILE)");
  if (photons == 0 && (!o.camera_out.empty() || !o.photons.fresnel || o.photons.light != 0))
    throw UsageError("--camera, --light and --no-fresnel go with --photons");
  if (photons > 0 && (!o.caustics_files.empty() || o.exposure_given))
    throw UsageError("--caustics and --exposure go without --photons (or with --picture)");
  const std::string out_extension = io::check_image_output(o.out);
  if (!o.camera_out.empty()) io::check_image_output(o.camera_out);
  const std::string shard = "--shard " + std::to_string(o.shard.index) + "/" + std::to_string(o.shard.count);
  if (o.shard.count > 0 && photons == 0) {
    if (out_extension != ".exr") throw UsageError(o.out + ": a shard is an EXR of the image's rows: --out must end in .exr");
    if (o.exposure_given) throw UsageError("--exposure goes without --shard: a shard holds linear radiance");
    if (o.shard.count > o.height) throw UsageError(shard + ": more shards than the " + std::to_string(o.height) + " rows of the image");
  } else if (o.shard.count > 0) {
    if (!o.camera_out.empty()) throw UsageError("--camera goes without --shard: a shard holds the light-space map's sums only");
    if (out_extension != ".exr") throw UsageError(o.out + ": a shard is an EXR of sums: --out must end in .exr");
    if (o.shard.count > photons) throw UsageError(shard + ": more shards than the " + std::to_string(photons) + " photons");
  }
  return out_extension;
}

// The whole photon reference: the caustic map and, with --camera, what the camera sees of it.
int trace_photons(const scene::Scene& scene, ReferenceOptions o) {
  const auto start = std::chrono::steady_clock::now();
  reference::PhotonOptions& photons = o.photons;
  if (!o.camera_out.empty()) {
    photons.camera_width = o.width;
    photons.camera_height = o.height;
  }
  const bool show_progress = photons.photons >= 10'000'000 || ::isatty(STDERR_FILENO);
  ProgressLine progress("photons", photons.photons);
  if (show_progress) photons.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
  const auto result = reference::trace_photon_reference(scene, photons);
  io::write_image(o.out, result.caustic_map);
  if (!o.camera_out.empty()) io::write_image(o.camera_out, result.camera);
  const auto& t = result.totals;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("photons %llu in %.2f s (%.1f M/s), seed %llu\n", static_cast<unsigned long long>(t.photons), seconds,
              double(t.photons) / seconds * 1e-6, static_cast<unsigned long long>(photons.seed));
  print_photon_flux(t);
  std::fprintf(stderr, "reference: %s -> %s%s%s\n", scene.name.c_str(), o.out.c_str(), o.camera_out.empty() ? "" : ", ",
               o.camera_out.c_str());
  return 0;
}

// Linear radiance as EXR, or tone mapped to a PNG as the engine's tonemap pass does.
void write_radiance(const std::string& path, io::ImageData image, const std::string& extension, double exposure) {
  if (extension == ".png") {
    for (size_t i = 0; i < image.rgba.size(); ++i) {
      if (i % 4 != 3) image.rgba[i] = 1.0f - std::exp(-static_cast<float>(exposure) * image.rgba[i]);
    }
  }
  io::write_image(path, image);
}

// How the printout names caustic view `index`: "light K", or "light K's -y face" for a point light's.
std::string view_name(const scene::CausticView& view, uint32_t index) {
  static const char* const kFaces[] = {"+x", "-x", "+y", "-y", "+z", "-z"};
  const std::string light = "light " + std::to_string(view.light);
  if (view.face < 0) return light;
  return "view " + std::to_string(index) + " (" + light + "'s " + kFaces[view.face] + " face)";
}

// Each caustic view's map, where it has one, and the pointers to them that the camera reference
// projects (null: a view without a map).
struct LightMaps {
  explicit LightMaps(size_t lights) : maps(lights), lit(lights, nullptr) {}
  void set(uint32_t light, io::ImageData map) {
    maps[light] = std::move(map);
    lit[light] = &maps[light];
  }
  std::vector<io::ImageData> maps;
  reference::CausticMaps lit;
};

// The camera picture lit by `maps`, written to `out`.
int write_camera_picture(const scene::Scene& scene, const ReferenceOptions& o, const LightMaps& maps, const std::string& out,
                         const std::string& extension, std::chrono::steady_clock::time_point start) {
  const auto image = reference::render_refraction_reference(scene, o.width, o.height, maps.lit, o.photons.seed);
  write_radiance(out, image.radiance, extension, o.exposure);
  std::fprintf(stderr, "reference: %s picture %ux%u in %.2f s -> %s\n", scene.name.c_str(), o.width, o.height,
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), out.c_str());
  return 0;
}

// The scene's whole reference picture: every caustic view's photons, --photons shared among them
// by the flux each sends, then the camera picture lit by all their maps.
int trace_picture(const scene::Scene& scene, const ReferenceOptions& o, const std::string& extension) {
  const auto start = std::chrono::steady_clock::now();
  const std::vector<uint64_t> shares = reference::photons_per_view(scene, o.photons.photons);
  const std::vector<scene::CausticView> views = scene::caustic_views(scene.lights);
  LightMaps maps(views.size());
  for (uint32_t i = 0; i < views.size(); ++i) {
    const std::string name = view_name(views[i], i);
    if (shares[i] == 0) {
      std::printf("%s: no photons (%s)\n", name.c_str(),
                  views[i].present ? "its share of the flux rounds to none" : "no caustic view: it reaches no refractor");
      continue;
    }
    reference::PhotonOptions photons = o.photons;
    photons.light = i;
    photons.photons = shares[i];
    ProgressLine progress(name + " photons", shares[i]);
    if (shares[i] >= 10'000'000 || ::isatty(STDERR_FILENO)) photons.progress = [&](uint64_t done, uint64_t) { progress.update(done); };
    reference::PhotonReference traced = reference::trace_photon_reference(scene, photons);
    std::printf("%s: photons %llu (--light %u --photons %llu), flux through its caustic view %.6g\n", name.c_str(),
                static_cast<unsigned long long>(shares[i]), i, static_cast<unsigned long long>(shares[i]),
                reference::caustic_view_flux(scene.lights[views[i].light], views[i]));
    print_photon_flux(traced.totals);
    maps.set(i, std::move(traced.caustic_map));
  }
  return write_camera_picture(scene, o, maps, o.picture_out, extension, start);
}

}  // namespace

int cmd_reference(Args& args) {
  ReferenceOptions o;
  if (args.wants_help()) {
    std::cout << "usage: caustica reference --scene FILE --out FILE.exr|.png [--size WxH] [--caustics [I=]MAP.exr]...\n"
                 "                          [--exposure E] [--seed K] [--shard I/K]\n"
                 "       caustica reference --scene FILE --photons N --out MAP.exr [--light I] [--seed K] [--map-size N]\n"
                 "                          [--camera IMAGE.exr [--size WxH]] [--no-fresnel] [--shard I/K]\n"
                 "       caustica reference --scene FILE --photons N --picture FILE.exr|.png [--size WxH] [--map-size N]\n"
                 "                          [--exposure E] [--seed K] [--no-fresnel]\n\n"
                 "Without --photons: ray traces the scene's camera image on its exact geometry with Embree (every\n"
                 "core): refraction at every interface, total internal reflection followed inside, Fresnel\n"
                 "transmittance and absorption, and otherwise the engine's own lighting model. It is the ground truth\n"
                 "that image-space refraction is measured against (docs/refraction.md). Writes linear radiance (EXR)\n"
                 "or an 8-bit PNG tone mapped as the engine's tonemap pass does (1 - exp(-E L), sRGB). With --caustics\n"
                 "I=MAP.exr (caustic view I's map from --photons; one per view, I default 0), surfaces its light sees past the\n"
                 "refractors also receive that map's caustic, projected as the engine's lighting pass projects its own:\n"
                 "the scene's reference picture with caustics, seen directly and through the glass. A pixel whose ray\n"
                 "meets a rough refractor averages paths drawn from random numbers keyed on the seed and the pixel's\n"
                 "place in the image.\n\n"
                 "With --photons: traces N photons through caustic view I (--light, default 0: light I's own, a spot or\n"
                 "directional light's view or a frustum fitted to its refractors; a point light among its refractors\n"
                 "has one per cube face, the faces after its first numbered after the lights) and every interface,\n"
                 "Fresnel and total internal reflection exact, to the receivers, and writes the caustic map as the\n"
                 "engine holds it (flux per texel of the view's image plane, --map-size texels a side) and, with\n"
                 "--camera, the caustic irradiance the camera sees. Deterministic for a seed on any number of cores\n"
                 "(docs/accuracy.md).\n\n"
                 "With --photons and --picture: the scene's whole reference picture. The N photons are shared among the\n"
                 "caustic views by the flux each sends (each view's share is printed: --light I --photons SHARE\n"
                 "traces the same map alone), each view's map is traced, and the camera picture is traced lit by all\n"
                 "of them: every light's direct light and exact shadows and its caustic, seen directly and through\n"
                 "the glass; the ground truth a multi-light render is compared with.\n\n"
                 "With --shard I/K: traces only the I-th of K contiguous ranges of the N photons (each photon's random\n"
                 "numbers depend on the seed and its index alone) and writes their sums, exactly, to --out (an EXR whose\n"
                 "header holds the range, the photon count, the seed and the scene's and the engine's identity, written\n"
                 "under a temporary name and renamed); 'caustica merge' adds the K files into the map that one process\n"
                 "writes, bit for bit. 'auto/K' takes I from SLURM_ARRAY_TASK_ID (a Slurm job array, --array=0-K-1) or\n"
                 "JOB_COMPLETION_INDEX (a Kubernetes Indexed Job); docs/cluster.md.\n\n"
                 "Without --photons, --shard I/K traces the I-th of K contiguous ranges of the image's rows (each\n"
                 "pixel as the whole image's run traces it) and writes them to --out: an EXR of those rows (32-bit\n"
                 "floats, its data window the rows, its display window the image) whose header holds the rows, the\n"
                 "image's size, the seed, the --caustics map's identity and the scene's and the engine's identity,\n"
                 "written under a temporary name and renamed; 'caustica merge' joins the K files into the EXR that one\n"
                 "process writes, bit for bit.\n\n"
                 "options:\n"
              << reference_flags(o).help();
    return 0;
  }
  reference_flags(o).parse(args);
  const std::string out_extension = check_reference(o);
  const scene::Scene scene = load_scene_and_warn(o.scene, o.stage);
  if (!o.picture_out.empty()) return trace_picture(scene, o, out_extension);
  if (o.shard.count > 0 && o.photons.photons > 0) return trace_photon_shard(scene, o.photons, o.shard, o.out);
  if (o.photons.photons > 0) return trace_photons(scene, o);
  const auto start = std::chrono::steady_clock::now();
  const std::vector<scene::CausticView> views = scene::caustic_views(scene.lights);
  LightMaps maps(views.size());
  for (const auto& [view, file] : o.caustics_files) {
    if (view >= views.size())
      throw UsageError("--caustics " + std::to_string(view) + "=" + file + ": the scene has " + std::to_string(views.size()) +
                       (views.size() == 1 ? " caustic view" : " caustic views") +
                       " (from 0; one per light, then a point light's further cube faces)");
    if (!views[view].present)
      throw InputError(file + ": light " + std::to_string(view) +
                       " has no caustic view (a point light that reaches no refractor) to project it through");
    maps.set(view, io::read_image(file));
  }
  if (o.shard.count > 0) return trace_camera_shard(scene, o.width, o.height, maps.lit, o.photons.seed, o.shard, o.out);
  return write_camera_picture(scene, o, maps, o.out, out_extension, start);
}

int cmd_merge(Args& args) {
  std::string out;
  const FlagTable flags{
      text_flag("--out", "OUT.exr", "the merged map or image (required; written under a temporary name and renamed)", out)};
  if (args.wants_help()) {
    std::cout << "usage: caustica merge SHARD.exr... --out OUT.exr\n\n"
                 "Joins the shards of a reference (one file per index) into what one process writes, bit for bit:\n"
                 "- photon shards ('caustica reference --photons N --shard I/K'): adds them, in the order of their\n"
                 "  photon ranges, one file at a time, into the caustic map of 'caustica reference --photons N'. They\n"
                 "  must tile the N photons exactly, from one scene, seed, photon count, map size, Fresnel setting and\n"
                 "  engine build.\n"
                 "- camera shards ('caustica reference --size WxH --shard I/K', without --photons): places their rows,\n"
                 "  one file at a time, into the EXR image of 'caustica reference --size WxH'. They must tile the image's\n"
                 "  rows exactly, from one scene (with its camera), seed, image size, --caustics map and engine build.\n"
                 "The first file's kind decides. Otherwise nothing is written and every problem is named: the missing\n"
                 "photons or rows with the shard indices that trace them (resubmit those), an overlap, a duplicate, a\n"
                 "shard of another run or of the other kind. Exit 0, 1 for such shards, 2 for a usage error\n"
                 "(docs/cluster.md).\n\n"
                 "options:\n"
              << flags.help();
    return 0;
  }
  std::vector<std::string> files;
  flags.parse(args, [&files](const std::string& file) { files.push_back(file); });
  if (files.empty()) throw UsageError("merge needs the shard files: caustica merge SHARD.exr... --out OUT.exr");
  if (out.empty()) throw UsageError("merge needs --out OUT.exr");
  if (io::check_image_output(out) != ".exr") throw UsageError(out + ": the merged map or image is linear: --out must end in .exr");
  for (const auto& file : files) {
    if (std::filesystem::weakly_canonical(std::filesystem::absolute(file)) ==
        std::filesystem::weakly_canonical(std::filesystem::absolute(out))) {
      throw UsageError("--out " + out + " is one of the shards: merging would replace it");
    }
  }
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (reference::shard_file_kind(files.front()) == "caustica camera shard") {
    const auto merged = reference::merge_camera_shards(files);
    io::write_image(out, merged.image);
    const auto& whole = merged.whole;
    std::printf("merged %zu shards: image %ux%llu, seed %llu, scene %s, in %.2f s\n", files.size(), whole.width,
                static_cast<unsigned long long>(whole.total), static_cast<unsigned long long>(whole.seed), whole.scene_name.c_str(),
                seconds());
  } else {
    const auto merged = reference::merge_photon_shards(files);
    io::write_image(out, merged.caustic_map);
    const auto& whole = merged.whole;
    std::printf("merged %zu shards: photons %llu, seed %llu, scene %s, in %.2f s\n", files.size(),
                static_cast<unsigned long long>(whole.total), static_cast<unsigned long long>(whole.seed), whole.scene_name.c_str(),
                seconds());
    print_photon_flux(whole.totals);
  }
  std::fprintf(stderr, "merge: %s\n", out.c_str());
  return 0;
}

}  // namespace caustica::cli
