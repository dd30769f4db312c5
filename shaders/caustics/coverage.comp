#version 460
// The coverage pyramid of the hierarchical caustic map and of coverage seeding: level 0 marks the
// blocks of light-view texels where a photon of the effective grid sees a refractor; each next
// level is the max of 2 x 2 texels of the one before.
#extension GL_GOOGLE_include_directive : require
#include "caustics/adaptive_common.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

void main() {
  uvec2 p = gl_GlobalInvocationID.xy;
  uint level = params.level;  // the pyramid level being written
  uint side = 1u << (params.light_size_log2 - level);
  if (any(greaterThanEqual(p, uvec2(side)))) return;
  uint offset = 0u;
  for (uint l = 0u; l < level; ++l) offset += 1u << (2u * (params.light_size_log2 - l));
  if (level == 0u) {
    // Each texel of the finest level stands for a block of light-view texels (see the pass) and
    // marks whether a photon of the effective grid inside it sees a refractor: the photons'
    // own sample texels, where this frame's jitter puts them, when the grid is coarser than the
    // light view, every texel otherwise.
    // That is what the regular map of the same grid sees, no more, and it saves reading the
    // whole light view for small grids. A light inside a glass globe sees only the inside of it
    // (its photons start in the glass, photon.glsl's inside_photon): there the back faces are
    // what it sees of a refractor (with the front faces alone the hierarchical map traced none
    // of its photons: 3.5% of the reference's caustic on glass_lamp).
    bool inside = frame.caustic_lights[params.light].face.y >= 0.0;
    uint light_side = uint(textureSize(front_tex, 0).x);
    uint grid_side = 64u << params.max_level;
    uint block = light_side >> params.light_size_log2;
    uint per_side = min(block, max(grid_side >> params.light_size_log2, 1u));
    float samples_side = float(side * per_side);
    uint any_refractor = 0u;
    for (uint y = 0u; y < per_side; ++y) {
      for (uint x = 0u; x < per_side; ++x) {
        vec2 uv = (vec2(p * per_side + uvec2(x, y)) + photon_jitter()) / samples_side;
        ivec2 texel = ivec2(uv * float(light_side));
        float seen = inside ? texelFetch(back_tex, texel, 0).y : texelFetch(front_tex, texel, 0).y;
        any_refractor |= seen > 0.0 ? 1u : 0u;
      }
    }
    coverage[p.y * side + p.x] = any_refractor;
    return;
  }
  uint below = offset - (1u << (2u * (params.light_size_log2 - level + 1u)));
  uint below_side = side * 2u;
  uvec2 q = p * 2u;
  uint any_covered = coverage[below + q.y * below_side + q.x] | coverage[below + q.y * below_side + q.x + 1u] |
                     coverage[below + (q.y + 1u) * below_side + q.x] | coverage[below + (q.y + 1u) * below_side + q.x + 1u];
  coverage[offset + p.y * side + p.x] = any_covered;
}
