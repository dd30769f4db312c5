#version 460
layout(location = 0) in vec3 uv;
layout(location = 0) out vec4 view;
void main() { view = vec4(uv, 1.0); }
