#version 460
// The device's opaque-surface model (scene/surface.glsl) at chosen materials and angles: texel i of
// `values` holds case i's value per channel, which tests/surface_layers_test.cpp compares with values
// worked by hand from glTF's extensions (sheen, anisotropy, diffuse transmission; specular, index,
// thin film and clear coat on the metallic-roughness BRDF).
#extension GL_GOOGLE_include_directive : require
#define SURFACE_LAYERS 1
#include "scene/surface.glsl"

layout(set = 0, binding = 0, rgba32f) uniform writeonly image2D values;

layout(local_size_x = 18, local_size_y = 1) in;

void main() {
  int i = int(gl_GlobalInvocationID.x);
  if (i >= imageSize(values).x) return;
  const vec3 n = vec3(0.0, 0.0, 1.0), tilted = vec3(0.6, 0.0, 0.8), behind = vec3(0.0, 0.6, -0.8);
  // View and light at 60 degrees from n on either side of it: the half vector is n, v.h = 0.5.
  const vec3 view60 = vec3(0.8660254, 0.0, 0.5), light60 = vec3(-0.8660254, 0.0, 0.5);
  Surface s = plain_surface(n, vec3(0.8, 0.6, 0.4), 0.0, 0.5);
  vec3 value = vec3(0.0);
  if (i == 0) {  // KHR_materials_sheen's lobe, roughness 1, view and light both at n.h = 0.6
    s.sheen_color = vec3(1.0, 0.5, 0.25);
    s.sheen_roughness = 1.0;
    value = sheen_lobe(s, 0.6, 0.6, 0.6);
  } else if (i == 1) {  // the same at roughness 0.5
    s.sheen_color = vec3(1.0, 0.5, 0.25);
    s.sheen_roughness = 0.5;
    value = sheen_lobe(s, 0.6, 0.6, 0.6);
  } else if (i == 2) {  // the albedo table (E_k = (k / 15)^2 here, at cosines (k / 15)^2) between samples, and the scaling it gives
    for (int k = 0; k < 16; ++k) s.sheen_albedo[k / 4][k % 4] = float(k * k) / 225.0;
    s.sheen_color = vec3(0.5, 0.2, 0.1);
    value = vec3(sheen_albedo(s, 0.25), sheen_scaling(s, 0.09, 0.49), sheen_scaling(s, 1.0, 0.04));
  } else if (i == 3) {  // KHR_materials_anisotropy: strength 1 along x, view = light = n
    s.anisotropy = 1.0;
    s.anisotropy_t = vec3(1.0, 0.0, 0.0);
    value = vec3(specular_lobe(s, n, n, n, 1.0, 1.0));
  } else if (i == 4) {  // the same, view = light tilted toward the direction it stretches along
    s.anisotropy = 1.0;
    s.anisotropy_t = vec3(1.0, 0.0, 0.0);
    value = vec3(specular_lobe(s, tilted, tilted, tilted, 0.8, 0.8));
  } else if (i == 5) {  // the direction turned a quarter: tilted across it
    s.anisotropy = 1.0;
    s.anisotropy_t = vec3(0.0, 1.0, 0.0);
    value = vec3(specular_lobe(s, tilted, tilted, tilted, 0.8, 0.8));
  } else if (i == 6) {  // no anisotropy: GGX's round lobe, view = light = n
    value = vec3(specular_lobe(s, n, n, n, 1.0, 1.0));
  } else if (i == 7) {  // KHR_materials_diffuse_transmission: light from behind, metallic 0.25
    s.metallic = 0.25;
    s.transmission = 0.5;
    s.transmission_color = vec3(1.0, 0.5, 0.2);
    value = brdf(s, n, behind);
  } else if (i == 8) {  // a Lambertian surface lit in front keeps what it does not pass
    s = plain_surface(n, vec3(0.8, 0.6, 0.4), 0.0, -1.0);
    s.transmission = 0.25;
    value = brdf(s, n, tilted);
  } else if (i == 9) {  // and under the sky, the light passed from behind
    s = plain_surface(n, vec3(0.8, 0.6, 0.4), 0.0, -1.0);
    s.transmission = 0.25;
    s.transmission_color = vec3(1.0, 0.5, 0.0);
    value = ambient_reflectance(s, n);
  } else if (i == 10 || i == 11) {  // KHR_materials_specular: colour (2, 1, 0.5), weight 0.8; v = l = n, then at 60 degrees
    s.specular = vec4(2.0, 1.0, 0.5, 0.8);
    value = i == 10 ? brdf(s, n, n) : brdf(s, view60, light60);
  } else if (i == 12) {  // KHR_materials_ior: index 2 on an opaque surface, v = l = n
    s.dielectric_f0 = 1.0 / 9.0;
    value = brdf(s, n, n);
  } else if (i == 13 || i == 14) {  // KHR_materials_clearcoat: a full coat of roughness 0.3; v = l = n, then at 60 degrees
    s.coat = 1.0;
    s.coat_roughness = 0.3;
    value = i == 13 ? brdf(s, n, n) : brdf(s, view60, light60);
  } else if (i == 15) {  // the same coat under the sky, seen along n
    s.coat = 1.0;
    s.coat_roughness = 0.3;
    value = ambient_reflectance(s, n);
  } else if (i == 16) {  // KHR_materials_iridescence: a film of 1.3, a quarter wave at 587.56 nm, v = l = n
    s.film = 1.0;
    s.film_ior = 1.3;
    s.film_thickness = 587.56 / (4.0 * 1.3);
    value = brdf(s, n, n);
  } else if (i == 17) {  // a film of no thickness on metal, v = l = n
    s.metallic = 1.0;
    s.film = 1.0;
    s.film_ior = 1.3;
    value = brdf(s, n, n);
  }
  imageStore(values, ivec2(i, 0), vec4(value, 0.0));
}
