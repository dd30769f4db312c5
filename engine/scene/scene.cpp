#include "scene/scene.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <glm/gtc/matrix_transform.hpp>
#include <tuple>

#include "common/scene_types.h"  // the bands' lines, which the shaders use too
#include "core/paths.h"
#include "io/json_reader.h"

namespace caustica::scene {

glm::vec3 Material::band_iors() const {
  // n(lambda) = n_d + (n_F - n_C) (1/lambda^2 - 1/lambda_d^2) / (1/lambda_F^2 - 1/lambda_C^2)
  constexpr double kC = CAUSTICA_LINE_C_NM, kD = CAUSTICA_LINE_D_NM, kF = CAUSTICA_LINE_F_NM;
  const auto inv2 = [](double nm) { return 1.0 / (nm * nm); };
  const double per_spread = 1.0 / (inv2(kF) - inv2(kC));
  const double spread = double(ior_spread());
  return glm::vec3(glm::dvec3(double(ior)) + spread * per_spread * (glm::dvec3(inv2(kC), inv2(kD), inv2(kF)) - inv2(kD)));
}

void View::orbit(float degrees) {
  const glm::vec3 offset = position - target;
  const float turn = glm::radians(degrees), c = std::cos(turn), s = std::sin(turn);
  position = target + glm::vec3(c * offset.x + s * offset.z, offset.y, -s * offset.x + c * offset.z);
}

glm::mat4 View::view_matrix() const {
  glm::vec3 forward = glm::normalize(target - position);
  // Looking straight up or down: any up vector not parallel to the view direction serves.
  const glm::vec3 up = std::abs(forward.y) > 0.999f ? glm::vec3(0, 0, -1) : glm::vec3(0, 1, 0);
  return glm::lookAt(position, target, up);
}

glm::mat4 View::projection(float aspect) const {
  // Vulkan: depth 0..1 and framebuffer y pointing down.
  const float f = 1.0f / std::tan(glm::radians(fov_y_degrees) * 0.5f);
  glm::mat4 p(0.0f);
  p[0][0] = f / aspect;
  p[1][1] = -f;
  p[2][2] = far_plane / (near_plane - far_plane);
  p[2][3] = -1.0f;
  p[3][2] = near_plane * far_plane / (near_plane - far_plane);
  return p;
}

bool Scene::disperses() const {
  return std::any_of(objects.begin(), objects.end(),
                     [](const Object& o) { return o.material.refractor && o.material.ior_spread() > 0.0f; });
}

bool has_surface_textures(const Material& m) {
  const SurfaceTextures& t = m.surface_textures;
  return !m.refractor && (t.sheen_color.used() || t.sheen_roughness.used() || t.diffuse_transmission.used() ||
                          t.diffuse_transmission_color.used() || (m.metallic_roughness && m.layer_textures.used()));
}

bool has_layer_textures(const Material& m) {
  return m.refractor && (m.layer_textures.used() || m.surface_textures.clearcoat_normal.used());
}

bool Scene::has_surface_layers() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) {
    const Material& m = o.material;
    const bool brdf_layers = m.metallic_roughness && (m.specular != 1.0f || m.specular_color != glm::vec3(1.0f) || m.clearcoat > 0.0f ||
                                                      m.iridescence > 0.0f || m.ior != 1.5f);
    return !m.refractor && (m.sheen_color != glm::vec3(0.0f) || m.anisotropy > 0.0f || m.diffuse_transmission > 0.0f || brdf_layers ||
                            scene::has_surface_textures(m));
  });
}

bool Scene::has_surface_textures() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return scene::has_surface_textures(o.material); });
}

bool Scene::has_layer_textures() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) { return scene::has_layer_textures(o.material); });
}

bool Scene::tints_per_texel() const {
  return std::any_of(objects.begin(), objects.end(), [](const Object& o) {
    return o.material.refractor && (o.material.base_color_texture.used() || o.material.transmission_texture.used());
  });
}

size_t Scene::refractor_count() const {
  return static_cast<size_t>(std::count_if(objects.begin(), objects.end(), [](const Object& o) { return o.material.refractor; }));
}

std::map<std::string, double> Scene::expression_values() const {
  std::map<std::string, double> values{
      {"scene.refractors", static_cast<double>(refractor_count())},   {"scene.lights", static_cast<double>(lights.size())},
      {"scene.objects", static_cast<double>(objects.size())},         {"scene.dispersive", disperses() ? 1.0 : 0.0},
      {"scene.surface_layers", has_surface_layers() ? 1.0 : 0.0},     {"scene.layer_textures", has_layer_textures() ? 1.0 : 0.0},
      {"scene.surface_textures", has_surface_textures() ? 1.0 : 0.0}, {"scene.diagonal", static_cast<double>(diagonal())},
      {"scene.ray_epsilon", static_cast<double>(ray_epsilon())}};
  for (size_t i = 0; i < lights.size(); ++i) {
    const Light& light = lights[i];
    const std::string prefix = "scene.light" + std::to_string(i) + ".";
    values[prefix + "view"] = light.has_caustic_view ? 1 : 0;
    values[prefix + "spot"] = light.type == LightType::spot ? 1 : 0;
    values[prefix + "point"] = light.type == LightType::point ? 1 : 0;
    values[prefix + "directional"] = light.type == LightType::directional ? 1 : 0;
    double objects_reached = 0, refractors_reached = 0;
    for (const Object& o : objects) {
      if (!light.reaches(o.bounds_min, o.bounds_max)) continue;
      objects_reached += 1;
      refractors_reached += o.material.refractor ? 1 : 0;
    }
    values[prefix + "objects"] = objects_reached;
    values[prefix + "refractors"] = refractors_reached;
  }
  // A view's other values are its light's: the graph compiler copies them (graph::compile_graph).
  const std::vector<CausticView> views = caustic_views(lights);
  values["scene.caustic_views"] = static_cast<double>(views.size());
  for (size_t k = 0; k < views.size(); ++k) {
    const std::string prefix = "scene.caustic" + std::to_string(k) + ".";
    values[prefix + "view"] = views[k].present ? 1 : 0;
    values[prefix + "light"] = views[k].light;
    values[prefix + "face"] = views[k].face;
  }
  return values;
}

float Scene::ray_epsilon() const {
  float extent = 1.0f;
  for (const auto& o : objects) extent = std::max(extent, glm::length(o.bounds_max - o.bounds_min));
  return 1e-4f * extent;
}

std::pair<glm::vec3, glm::vec3> Scene::bounds() const {
  if (objects.empty()) return {glm::vec3(0.0f), glm::vec3(0.0f)};
  glm::vec3 low = objects.front().bounds_min, high = objects.front().bounds_max;
  for (const auto& o : objects) {
    low = glm::min(low, o.bounds_min);
    high = glm::max(high, o.bounds_max);
  }
  return {low, high};
}

float Scene::diagonal() const {
  const auto [low, high] = bounds();
  return glm::length(high - low);
}

size_t Scene::triangle_count() const {
  size_t n = 0;
  for (const auto& o : objects) n += o.mesh.indices.size() / 3;
  return n;
}

namespace {

constexpr double kBig = 1e6;  // coordinates, sizes: anything larger is a mistake

glm::vec3 vec3(const JsonReader& read, const nlohmann::json& value, const std::string& pointer, const char* what, double lo = -kBig,
               double hi = kBig) {
  auto v = read.numbers(value, pointer, what, 3, lo, hi);
  return {static_cast<float>(v[0]), static_cast<float>(v[1]), static_cast<float>(v[2])};
}

View load_view(const JsonDocument& doc, const JsonReader& read, const nlohmann::json& value, const std::string& pointer, const char* what,
               std::vector<std::string> extra_keys) {
  read.object(value, pointer, what);
  std::vector<std::string> keys{"position", "target", "fov", "near", "far"};
  keys.insert(keys.end(), extra_keys.begin(), extra_keys.end());
  read.only_keys(value, pointer, keys, what);
  View v;
  if (!value.contains("position")) throw doc.error(pointer, std::string(what) + " needs a \"position\"");
  v.position = vec3(read, value["position"], pointer + "/position", "\"position\"");
  if (value.contains("target")) v.target = vec3(read, value["target"], pointer + "/target", "\"target\"");
  if (glm::length(v.target - v.position) < 1e-6f) throw doc.error(pointer + "/target", "\"target\" must differ from \"position\"");
  if (value.contains("fov")) v.fov_y_degrees = static_cast<float>(read.number(value["fov"], pointer + "/fov", "\"fov\"", 1.0, 170.0));
  if (value.contains("near")) v.near_plane = static_cast<float>(read.number(value["near"], pointer + "/near", "\"near\"", 1e-4, 1e4));
  if (value.contains("far")) v.far_plane = static_cast<float>(read.number(value["far"], pointer + "/far", "\"far\"", 1e-3, 1e6));
  if (v.far_plane <= v.near_plane) throw doc.error(pointer + "/far", "\"far\" must be greater than \"near\"");
  return v;
}

glm::mat4 load_transform(const JsonReader& read, const nlohmann::json& value, const std::string& pointer) {
  read.object(value, pointer, "a transform");
  read.only_keys(value, pointer, {"translate", "rotate", "scale"}, "a transform");
  glm::mat4 m(1.0f);
  if (value.contains("translate")) m = glm::translate(m, vec3(read, value["translate"], pointer + "/translate", "\"translate\""));
  if (value.contains("rotate")) {
    const glm::vec3 r = vec3(read, value["rotate"], pointer + "/rotate", "\"rotate\" (degrees about x, y, z)", -3600, 3600);
    m = glm::rotate(m, glm::radians(r.z), glm::vec3(0, 0, 1));
    m = glm::rotate(m, glm::radians(r.y), glm::vec3(0, 1, 0));
    m = glm::rotate(m, glm::radians(r.x), glm::vec3(1, 0, 0));
  }
  if (value.contains("scale")) {
    const auto& s = value["scale"];
    const glm::vec3 scale = s.is_number() ? glm::vec3(static_cast<float>(read.number(s, pointer + "/scale", "\"scale\"", -kBig, kBig)))
                                          : vec3(read, s, pointer + "/scale", "\"scale\"");
    // Negative factors mirror (winding is fixed when the transform is baked); zero flattens.
    if (glm::any(glm::lessThan(glm::abs(scale), glm::vec3(1e-6f)))) {
      throw read.error(pointer + "/scale", "\"scale\" must not be zero (or closer to zero than 1e-6) on any axis");
    }
    m = glm::scale(m, scale);
  }
  return m;
}

void apply_material(const JsonReader& read, const nlohmann::json& value, const std::string& pointer, Material& m) {
  read.object(value, pointer, "a material");
  read.only_keys(value, pointer, {"color", "refractor", "ior", "absorption", "transmission", "tint", "thin", "dispersion", "roughness"},
                 "a material");
  if (value.contains("color")) m.albedo = vec3(read, value["color"], pointer + "/color", "\"color\"", 0.0, 1.0);
  if (value.contains("refractor")) m.refractor = read.boolean(value["refractor"], pointer + "/refractor", "\"refractor\"");
  if (value.contains("ior"))
    m.ior = static_cast<float>(read.number(value["ior"], pointer + "/ior", "\"ior\" (index of refraction)", 1.0, 4.0));
  if (value.contains("absorption")) {
    m.absorption = vec3(read, value["absorption"], pointer + "/absorption", "\"absorption\" (per unit length)", 0.0, 1e4);
  }
  if (value.contains("transmission")) {
    m.transmission = static_cast<float>(read.number(value["transmission"], pointer + "/transmission", "\"transmission\"", 0.0, 1.0));
  }
  if (value.contains("tint")) m.tint = vec3(read, value["tint"], pointer + "/tint", "\"tint\"", 0.0, 1.0);
  if (value.contains("thin")) m.thin = read.boolean(value["thin"], pointer + "/thin", "\"thin\"");
  if (value.contains("roughness")) {
    m.transmission_roughness =
        static_cast<float>(read.number(value["roughness"], pointer + "/roughness", "\"roughness\" (of a refractor's surfaces)", 0.0, 1.0));
  }
  if (value.contains("dispersion")) {
    m.dispersion =
        static_cast<float>(read.number(value["dispersion"], pointer + "/dispersion", "\"dispersion\" (20 / Abbe number)", 0.0, 100.0));
  }
}

Mesh load_primitive(const JsonDocument& doc, const JsonReader& read, const nlohmann::json& value, const std::string& pointer) {
  static const std::vector<std::string> types{"sphere", "plane", "box", "torus", "slab"};
  read.object(value, pointer, "a primitive");
  read.only_keys(value, pointer, {"type", "radius", "size", "major_radius", "minor_radius", "detail"}, "a primitive");
  if (!value.contains("type")) throw doc.error(pointer, "a primitive needs a \"type\"" + did_you_mean("", types));
  const std::string type = read.string(value["type"], pointer + "/type", "a primitive type");
  const int detail =
      value.contains("detail") ? static_cast<int>(read.number(value["detail"], pointer + "/detail", "\"detail\"", 3, 1024)) : 64;
  auto number = [&](const char* key, double fallback, double lo, double hi) {
    return static_cast<float>(value.contains(key) ? read.number(value[key], pointer + "/" + key, key, lo, hi) : fallback);
  };
  if (type == "sphere") return make_sphere(number("radius", 1.0, 1e-6, kBig), detail, std::max(2, detail / 2));
  if (type == "plane") {
    auto size = value.contains("size") ? read.numbers(value["size"], pointer + "/size", "\"size\" (width, depth)", 2, 1e-6, kBig)
                                       : std::vector<double>{10, 10};
    return make_plane(static_cast<float>(size[0]), static_cast<float>(size[1]));
  }
  if (type == "box" || type == "slab") {
    glm::vec3 fallback = type == "box" ? glm::vec3(1.0f) : glm::vec3(2.0f, 0.2f, 2.0f);
    return make_box(value.contains("size") ? vec3(read, value["size"], pointer + "/size", "\"size\"", 1e-6, kBig) : fallback);
  }
  if (type == "torus") {
    const float major = number("major_radius", 1.0, 1e-6, kBig), minor = number("minor_radius", 0.3, 1e-6, kBig);
    if (minor >= major) throw doc.error(pointer + "/minor_radius", "\"minor_radius\" must be smaller than \"major_radius\"");
    return make_torus(major, minor, detail, std::max(3, detail / 2));
  }
  throw doc.error(pointer + "/type", "unknown primitive '" + type + "'" + did_you_mean(type, types));
}

// Mesh paths resolve against the scene file's folder; absolute paths are used as they are.
std::string resolve_mesh_path(const JsonDocument& doc, const std::string& text) {
  std::filesystem::path p(text);
  if (p.is_absolute()) return p.string();
  return (std::filesystem::path(doc.path()).parent_path() / p).lexically_normal().string();
}

// A mesh file's part as a scene object; its material's textures move from the file's list to the
// scene's, which already holds `texture_base` of them.
Object object_from_part(MeshPart&& part, size_t texture_base) {
  Object o;
  o.mesh = std::move(part.mesh);
  if (part.material) o.material = *part.material;
  for (TextureRef* ref : {&o.material.base_color_texture, &o.material.metallic_roughness_texture, &o.material.normal_texture,
                          &o.material.emissive_texture, &o.material.occlusion_texture}) {
    if (ref->used()) ref->texture += static_cast<int>(texture_base);
  }
  return o;
}

void finish_object(Object& o, const glm::mat4& transform) {
  const glm::mat3 normal_matrix = glm::transpose(glm::inverse(glm::mat3(transform)));
  for (auto& p : o.mesh.positions) p = glm::vec3(transform * glm::vec4(p, 1.0f));
  for (auto& n : o.mesh.normals) n = glm::normalize(normal_matrix * n);
  for (auto& t : o.mesh.tangents) t = carry_tangent(transform, t);
  if (glm::determinant(glm::mat3(transform)) < 0) {
    for (size_t t = 0; t + 2 < o.mesh.indices.size(); t += 3) std::swap(o.mesh.indices[t + 1], o.mesh.indices[t + 2]);
  }
  std::tie(o.bounds_min, o.bounds_max) = mesh_bounds(o.mesh);
  o.radius = 0.0f;
  for (const glm::vec3& p : o.mesh.positions) o.radius = std::max(o.radius, glm::length(p - o.center()));
  if (o.material.refractor) o.mesh.normal_distance = normal_distances(o.mesh);
}

}  // namespace

Scene load_scene(const JsonDocument& doc) {
  JsonReader read(doc);
  const auto& root = read.object(doc.root(), "", "a scene");
  // A graph given where a scene is wanted (--scene): say so, rather than name its first member.
  if (root.contains("passes") && !root.contains("objects")) {
    throw doc.error("", "this is a graph file (it has \"passes\"), not a scene: give it to --graph");
  }
  read.only_keys(root, "", {"$schema", "name", "description", "camera", "lights", "objects", "sky", "ambient"}, "a scene");
  Scene scene;
  scene.path = doc.path();
  scene.name =
      root.contains("name") ? read.name(root["name"], "/name", "the scene name") : std::filesystem::path(doc.path()).stem().string();
  if (root.contains("description")) read.string(root["description"], "/description", "\"description\"");
  if (!root.contains("camera")) throw doc.error("", "a scene needs a \"camera\"");
  scene.camera = load_view(doc, read, root["camera"], "/camera", "the camera", {});
  if (root.contains("sky")) scene.sky = vec3(read, root["sky"], "/sky", "\"sky\" (radiance)", 0.0, 1e4);
  if (root.contains("ambient")) scene.ambient = static_cast<float>(read.number(root["ambient"], "/ambient", "\"ambient\"", 0.0, 1.0));

  if (!root.contains("lights")) throw doc.error("", "a scene needs \"lights\" (an array, at least one light)");
  const auto& lights = root["lights"];
  if (!lights.is_array() || lights.empty()) throw doc.error("/lights", "\"lights\" must be a non-empty array");
  if (lights.size() > 8) throw doc.error("/lights", "at most 8 lights");
  for (size_t i = 0; i < lights.size(); ++i) {
    const std::string pointer = "/lights/" + std::to_string(i);
    const auto& value = lights[i];
    Light light;
    light.view = load_view(doc, read, value, pointer, "a light", {"type", "intensity", "color", "extent", "caustic_view"});
    static const std::vector<std::string> types{"spot", "point", "directional"};
    const std::string type = value.contains("type") ? read.string(value["type"], pointer + "/type", "a light type") : "spot";
    if (type == "spot")
      light.type = LightType::spot;
    else if (type == "point")
      light.type = LightType::point;
    else if (type == "directional")
      light.type = LightType::directional;
    else
      throw doc.error(pointer + "/type", "unknown light type '" + type + "' (known: spot, point, directional)" + did_you_mean(type, types));
    if (value.contains("extent")) {
      if (light.type != LightType::directional) throw doc.error(pointer + "/extent", "\"extent\" is for directional lights only");
      light.extent =
          static_cast<float>(read.number(value["extent"], pointer + "/extent", "\"extent\" (half the light view's side)", 1e-3, 1e5));
    }
    if (value.contains("caustic_view")) {
      const std::string view = read.string(value["caustic_view"], pointer + "/caustic_view", "\"caustic_view\"");
      if (view != "fitted" && view != "light")
        throw doc.error(pointer + "/caustic_view",
                        "\"caustic_view\" is \"fitted\" (to the refractors it reaches, the default) or \"light\" (its own view), not '" +
                            view + "'" + did_you_mean(view, {"fitted", "light"}));
      if (view == "light" && light.type == LightType::point)
        throw doc.error(pointer + "/caustic_view", "a point light has no view of its own: its caustic view is always fitted");
      light.own_caustic_view = view == "light";
    }
    if (light.type == LightType::spot && !value.contains("fov")) light.view.fov_y_degrees = 60.0f;
    if (value.contains("intensity"))
      light.intensity = static_cast<float>(read.number(value["intensity"], pointer + "/intensity", "\"intensity\"", 0.0, 1e9));
    if (value.contains("color")) light.color = vec3(read, value["color"], pointer + "/color", "\"color\"", 0.0, 1e4);
    scene.lights.push_back(light);
  }

  if (!root.contains("objects")) throw doc.error("", "a scene needs \"objects\" (an array)");
  const auto& objects = root["objects"];
  if (!objects.is_array()) throw doc.error("/objects", "\"objects\" must be an array");
  if (objects.size() > 256) throw doc.error("/objects", "at most 256 objects");
  for (size_t i = 0; i < objects.size(); ++i) {
    const std::string pointer = "/objects/" + std::to_string(i);
    const auto& value = read.object(objects[i], pointer, "an object");
    read.only_keys(value, pointer, {"name", "mesh", "primitive", "transform", "material"}, "an object");
    const std::string name =
        value.contains("name") ? read.name(value["name"], pointer + "/name", "an object name") : "object" + std::to_string(i);
    for (const auto& o : scene.objects) {
      if (o.name == name || o.name.rfind(name + ".", 0) == 0) throw doc.error(pointer + "/name", "two objects are named '" + name + "'");
    }
    if (value.contains("mesh") == value.contains("primitive"))
      throw doc.error(pointer, "an object needs exactly one of \"mesh\" and \"primitive\"");
    const glm::mat4 transform =
        value.contains("transform") ? load_transform(read, value["transform"], pointer + "/transform") : glm::mat4(1.0f);
    std::vector<Object> parts;
    if (value.contains("primitive")) {
      Object o;
      o.mesh = load_primitive(doc, read, value["primitive"], pointer + "/primitive");
      parts.push_back(std::move(o));
    } else {
      const std::string path = resolve_mesh_path(doc, read.string(value["mesh"], pointer + "/mesh", "\"mesh\""));
      ModelFile model;
      try {
        model = load_model_file(path);
      } catch (const InputError& e) {
        throw doc.error(pointer + "/mesh", e.what());
      }
      for (auto& part : model.parts) parts.push_back(object_from_part(std::move(part), scene.textures.size()));
      std::move(model.textures.begin(), model.textures.end(), std::back_inserter(scene.textures));
      scene.file_images += model.images;
      std::move(model.warnings.begin(), model.warnings.end(), std::back_inserter(scene.warnings));
    }
    for (size_t p = 0; p < parts.size(); ++p) {
      Object& o = parts[p];
      o.name = parts.size() == 1 ? name : name + "." + std::to_string(p);
      o.pointer = pointer;
      if (value.contains("material")) apply_material(read, value["material"], pointer + "/material", o.material);
      finish_object(o, transform);
      scene.objects.push_back(std::move(o));
    }
  }
  if (scene.objects.empty()) throw doc.error("/objects", "a scene needs at least one object");
  fit_light_views(scene, scene.objects.size());
  return scene;
}

bool is_model_file(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".gltf" || extension == ".glb" || extension == ".obj" || extension == ".off";
}

Scene load_model_scene(const std::string& path, bool stage) {
  ModelFile model = load_model_file(path);
  const size_t model_objects = model.parts.size();
  Scene scene;
  scene.path = path;
  scene.name = std::filesystem::path(path).stem().string();
  // The default picture's fill: a sky and ambient light, so that no shadow is black.
  scene.sky = glm::vec3(0.55f, 0.65f, 0.8f);
  scene.ambient = 0.25f;
  scene.textures = std::move(model.textures);
  scene.file_images = model.images;
  scene.warnings = std::move(model.warnings);
  for (size_t p = 0; p < model.parts.size(); ++p) {
    Object o = object_from_part(std::move(model.parts[p]), 0);
    o.name = (model.parts[p].name.empty() ? scene.name : model.parts[p].name) + "." + std::to_string(p);
    finish_object(o, glm::mat4(1.0f));
    scene.objects.push_back(std::move(o));
  }
  const auto [low, high] = scene.bounds();
  const glm::vec3 center = 0.5f * (low + high);
  const float radius = std::max(0.5f * glm::length(high - low), 1e-4f);
  if (stage) {
    Object floor;
    floor.name = "stage_floor";
    floor.mesh = make_plane(8.0f * radius, 8.0f * radius);
    floor.material.albedo = glm::vec3(0.78f, 0.76f, 0.72f);
    // A hair below the model, so that its base does not fight the floor for depth; well above the
    // exact tracers' ray epsilon (1e-4 of the largest object, the floor: about 1.1e-3 radii), so
    // that light leaving the model's base lands on the floor instead of stepping through it.
    finish_object(floor, glm::translate(glm::mat4(1.0f), glm::vec3(center.x, low.y - 1e-2f * radius, center.z)));
    scene.objects.push_back(std::move(floor));
  }
  if (model.camera && !model.camera_is_orthographic) {
    scene.camera = *model.camera;
    // Aim at the model along the file's direction, so that the orbit camera turns around it.
    scene.camera.target =
        scene.camera.position + (scene.camera.target - scene.camera.position) * glm::length(center - scene.camera.position);
  } else {
    // Framed: the model's bounding sphere fills the view, seen from in front and above.
    scene.camera.fov_y_degrees = 45.0f;
    const float distance = 1.15f * radius / std::sin(glm::radians(0.5f * scene.camera.fov_y_degrees));
    scene.camera.target = center;
    scene.camera.position = center + distance * glm::normalize(glm::vec3(0.0f, 0.45f, 1.0f));
    // Its planes from the model's size, like the lights': a large model seen through the default
    // 0.05 near plane got depth steps of a third of a unit on its floor, which streaked its lighting.
    scene.camera.near_plane = 0.01f * radius;
  }
  scene.camera.near_plane = std::min(scene.camera.near_plane, 0.01f * radius);
  scene.camera.far_plane = std::max(scene.camera.far_plane, 50.0f * radius);
  for (const auto& l : model.lights) {
    Light light;
    light.color = l.color;
    light.view.near_plane = 0.01f * radius;
    light.view.far_plane = 50.0f * radius;
    if (l.type == "directional") {
      // Its orthographic view starts two model radii before the model and is fitted to the model
      // (not the stage floor: the model's shadow and caustic on it lie inside the prism anyway).
      light.type = LightType::directional;
      light.view.position = center - 2.0f * radius * l.direction;
      light.view.target = center;
      light.intensity = l.intensity;  // lux as W/m^2, as candela as W/sr for the others
    } else {
      light.type = l.type == "point" ? LightType::point : LightType::spot;
      light.view.position = l.position;
      light.view.target = l.position + l.direction;
      light.view.fov_y_degrees = light.type == LightType::spot ? std::clamp(l.cone_degrees, 1.0f, 170.0f) : 90.0f;
      light.intensity = l.intensity;
    }
    if (scene.lights.size() < 8) scene.lights.push_back(light);
  }
  if (scene.lights.empty()) {
    // As in the default scene: a spot light above and behind the model, so that its caustic falls
    // on the floor in front of it, in view; irradiance at the model about the default scene's.
    Light light;
    light.view.position = center + radius * glm::vec3(-0.4f, 3.5f, -1.6f);
    light.view.target = glm::vec3(center.x, low.y, center.z + 0.4f * radius);
    const float distance = glm::length(light.view.position - center);
    light.view.fov_y_degrees = glm::degrees(2.0f * std::atan(1.3f * radius / distance));
    light.view.near_plane = 0.01f * radius;
    light.view.far_plane = 50.0f * radius;
    light.intensity = 1.8f * distance * distance;
    scene.lights.push_back(light);
  }
  fit_light_views(scene, model_objects);
  return scene;
}

Scene load_scene_file(const std::string& path, bool stage) {
  if (is_model_file(path)) return load_model_scene(path, stage);
  return load_scene(JsonDocument::load(path));
}

}  // namespace caustica::scene
