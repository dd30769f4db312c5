#version 460
// One frame of an accumulate pass (passes/accumulate.cpp): the source's texels, times the frame's
// weight, added into a running sum per texel and layer, with Kahan's compensation so that thousands
// of frames of small values keep their low bits in fp32, and the weighted mean so far written out.
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0) uniform sampler2DArray source;
layout(binding = 1, r32f) uniform writeonly image2DArray average;
layout(binding = 2, std430) buffer SumBlock { vec2 sums[]; };  // per texel and layer: sum, compensation

const uint MODE_START = 0u;  // the sum becomes this frame (the first after a reset)
const uint MODE_ADD = 1u;
const uint MODE_HOLD = 2u;   // the most frames are in: the mean stays as it is

layout(push_constant) uniform Params {
  uvec2 size;
  uint layers;
  uint mode;
  float weight;        // this frame's
  float total_weight;  // of the frames in the sum, this one included
} params;

void main() {
  uvec3 id = gl_GlobalInvocationID;
  if (any(greaterThanEqual(id.xy, params.size)) || id.z >= params.layers) return;
  uint i = (id.z * params.size.y + id.y) * params.size.x + id.x;
  vec2 s = sums[i];
  float value = params.weight * texelFetch(source, ivec3(id), 0).r;
  if (params.mode == MODE_START) {
    s = vec2(value, 0.0);
  } else if (params.mode == MODE_ADD) {
    // precise: without it the compiler may fold (t - s) - y to zero and drop the compensation.
    precise float y = value - s.y;
    precise float t = s.x + y;
    precise float c = (t - s.x) - y;
    s = vec2(t, c);
  }
  sums[i] = s;
  imageStore(average, ivec3(id), vec4(s.x / params.total_weight));
}
