#pragma once
// The vertex shader of a pass over the whole viewport (composited layers that work per pixel):
// one triangle covering it, at window depth `uPassDepth` (a uniform, 0 unless set; with the
// layer hook's GEQUAL test, pixels whose terrain is nearer than that depth are skipped before
// the fragment shader runs).

namespace terralod {

inline constexpr const char* kFullScreenVertexShader = R"(#version 450 core
uniform float uPassDepth;
void main() {
  vec2 p = vec2((gl_VertexID << 1) & 2, gl_VertexID & 2);
  gl_Position = vec4(p * 2.0 - 1.0, uPassDepth, 1.0);
}
)";

}  // namespace terralod
