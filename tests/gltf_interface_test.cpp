// The glTF interface extensions as the loader reads them (KHR_materials_specular, _clearcoat,
// _iridescence), and the warnings for what a file uses and caustica does not read.
#include <gtest/gtest.h>

#include <filesystem>

#include "scene/scene.h"

namespace caustica::scene {
namespace {

const std::filesystem::path kData = std::filesystem::path(CAUSTICA_SOURCE_DIR) / "tests/data";
const std::filesystem::path kModels = std::filesystem::path(CAUSTICA_SOURCE_DIR) / "scenes/materials";

Material ball_material(const char* file) {
  const auto parts = load_mesh_file((kModels / file).string());
  EXPECT_EQ(parts.size(), 1u);
  EXPECT_TRUE(parts.at(0).material.has_value());
  return *parts.at(0).material;
}

// The values scenes/materials/make_layered_balls.py writes, and the defaults of what it leaves out.
TEST(GltfInterface, EachExtensionsValuesAreRead) {
  const Material coat = ball_material("clearcoat_ball.gltf");
  EXPECT_TRUE(coat.refractor);
  EXPECT_FLOAT_EQ(coat.clearcoat, 1.0f);
  EXPECT_FLOAT_EQ(coat.clearcoat_roughness, 0.0f);
  EXPECT_FLOAT_EQ(coat.specular, 1.0f);  // no specular extension: the plain dielectric
  EXPECT_EQ(coat.specular_color, glm::vec3(1.0f));
  EXPECT_FLOAT_EQ(coat.iridescence, 0.0f);

  const Material specular = ball_material("specular_ball.gltf");
  EXPECT_FLOAT_EQ(specular.specular, 1.0f);
  EXPECT_EQ(specular.specular_color, glm::vec3(2.5f, 1.0f, 0.4f));  // above 1 is allowed: it scales F0
  EXPECT_FLOAT_EQ(specular.clearcoat, 0.0f);

  const Material film = ball_material("iridescent_ball.gltf");
  EXPECT_FLOAT_EQ(film.iridescence, 1.0f);
  EXPECT_FLOAT_EQ(film.film_ior, 2.0f);
  EXPECT_FLOAT_EQ(film.film_thickness_nm, 380.0f);  // without a thickness texture: the maximum

  const Material rough = ball_material("coated_rough_ball.gltf");
  EXPECT_FLOAT_EQ(rough.clearcoat, 1.0f);
  EXPECT_FLOAT_EQ(rough.transmission_roughness, 0.4f);  // the base is rough, the coat smooth
  EXPECT_FLOAT_EQ(rough.clearcoat_roughness, 0.0f);
}

// A file that uses an extension caustica does not read renders, with a warning that names the
// extension, what is lost and where it is used; through a scene file too. One that requires it is
// refused (tests/data/bad_commands.txt has both from the command line).
TEST(GltfInterface, AnUnreadExtensionIsAWarningNamingIt) {
  const Scene model = load_model_scene((kData / "gltf/uses_unlit.gltf").string());
  ASSERT_EQ(model.warnings.size(), 1u);
  const std::string& warning = model.warnings[0];
  EXPECT_NE(warning.find("uses_unlit.gltf: uses KHR_materials_unlit, which caustica does not read"), std::string::npos) << warning;
  EXPECT_NE(warning.find("unlit shading (lit as the metallic-roughness model) is ignored (/materials/0)"), std::string::npos) << warning;
  EXPECT_TRUE(load_model_scene((kModels / "clearcoat_ball.gltf").string()).warnings.empty());  // every extension read
  const Scene through_scene = load_scene_file((kData / "warnings/unlit_scene.json").string());
  ASSERT_EQ(through_scene.warnings.size(), 1u);
  EXPECT_NE(through_scene.warnings[0].find("uses_unlit.gltf: uses KHR_materials_unlit"), std::string::npos) << through_scene.warnings[0];
  EXPECT_THROW(load_model_scene((kData / "gltf/requires_basisu.gltf").string()), InputError);
}

// An opaque surface's layer on a transmissive material is read and not drawn, and says so.
TEST(GltfInterface, SheenOnATransmissiveSurfaceWarnsThatItIsNotDrawn) {
  const Scene model = load_model_scene((kData / "gltf/uses_sheen.gltf").string());
  ASSERT_EQ(model.warnings.size(), 1u);
  EXPECT_NE(model.warnings[0].find("/materials/0 uses KHR_materials_sheen, which caustica draws on opaque surfaces only"),
            std::string::npos)
      << model.warnings[0];
  ASSERT_FALSE(model.objects.empty());
  EXPECT_EQ(model.objects[0].material.sheen_color, glm::vec3(1.0f, 0.5f, 0.5f));
  EXPECT_FLOAT_EQ(model.objects[0].material.sheen_roughness, 0.5f);
}

// The extensions' textures on opaque surfaces are kept with their factors, which the G-buffer reads
// per texel, and the material's values hold each factor times its texture's mean
// (tests/data/gltf/textured_extensions.gltf, whose checker is half (255, 160, 60, 255) and half
// (60, 140, 255, 70): in linear light its rgb mean is (0.522593, 0.306892, 0.522593) by the sRGB
// curve, its alpha mean 0.637255). A clear coat's own normal map is kept on opaque surfaces and on
// a transmissive one (tests/data/gltf/coat_normal_glass.gltf), without a warning.
TEST(GltfInterface, OpaqueSurfacesKeepTheirExtensionsTexturesAndFactors) {
  const Scene model = load_model_scene((kData / "gltf/textured_extensions.gltf").string());
  EXPECT_TRUE(model.warnings.empty()) << model.warnings.front();
  ASSERT_GE(model.objects.size(), 5u);
  const Material& sheen = model.objects[0].material;
  EXPECT_TRUE(sheen.surface_textures.sheen_color.used() && sheen.surface_textures.sheen_roughness.used());
  EXPECT_EQ(sheen.surface_textures.sheen_color_factor, glm::vec3(1.0f, 0.9f, 0.8f));
  EXPECT_FLOAT_EQ(sheen.surface_textures.sheen_roughness_factor, 0.9f);
  EXPECT_NEAR(sheen.sheen_color.r, 0.522593f, 2e-3f);
  EXPECT_NEAR(sheen.sheen_color.g, 0.9f * 0.306892f, 2e-3f);
  EXPECT_NEAR(sheen.sheen_color.b, 0.8f * 0.522593f, 2e-3f);
  EXPECT_NEAR(sheen.sheen_roughness, 0.9f * 0.637255f, 2e-3f);
  const Material& coat = model.objects[1].material;
  EXPECT_TRUE(coat.surface_textures.clearcoat_normal.used());
  EXPECT_FLOAT_EQ(coat.surface_textures.clearcoat_normal_scale, 0.8f);
  const Material& panel = model.objects[4].material;
  EXPECT_TRUE(panel.surface_textures.diffuse_transmission.used() && panel.surface_textures.diffuse_transmission_color.used());
  EXPECT_FLOAT_EQ(panel.surface_textures.diffuse_transmission_factor, 0.8f);
  EXPECT_NEAR(panel.diffuse_transmission, 0.8f * 0.637255f, 2e-3f);
  EXPECT_TRUE(model.has_surface_textures());

  // A refractor's coat normal map is read where the exact paths meet it (trace.glsl's coat_normal_at).
  const Scene glass = load_model_scene((kData / "gltf/coat_normal_glass.gltf").string());
  EXPECT_TRUE(glass.warnings.empty()) << glass.warnings[0];
  EXPECT_FALSE(glass.has_surface_textures());
  EXPECT_TRUE(glass.has_layer_textures());
  EXPECT_TRUE(glass.objects[1].material.surface_textures.clearcoat_normal.used());
}

}  // namespace
}  // namespace caustica::scene
