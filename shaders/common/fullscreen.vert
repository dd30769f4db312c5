#version 460
// One triangle covering the viewport; no vertex buffer.
#ifdef FULLSCREEN_UV
// For a fragment shader that reads it (a fullscreen user pass's, docs/shader_passes.md): 0 to 1
// across the target from its top-left corner, (x + 0.5) / width at a pixel's centre. Only then, so
// that no other fragment shader leaves an output of this stage unread.
layout(location = 0) out vec2 uv;
#endif
void main() {
  vec2 corner = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
#ifdef FULLSCREEN_UV
  uv = corner;
#endif
}
