#version 330 core
// Ellipse glyphs c + cos(t) u + sin(t) v, one instance per ellipse, a quad
// spanning [-1, 1]^2 in the (u, v) frame.
layout(location = 0) in vec3 a_center;
layout(location = 1) in vec3 a_u;
layout(location = 2) in vec3 a_v;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform float u_scale;
uniform float u_lift;      // fraction of the glyph radius lifted toward the eye
uniform bool u_orthographic;

out vec2 v_uv;

void main() {
  vec2 uv = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
  // Slightly larger quad so the outline is not cut.
  uv *= 1.08;
  vec3 p = a_center + u_scale * (uv.x * a_u + uv.y * a_v);
  vec4 v = u_view * vec4(p, 1.0);
  vec3 to_eye = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v.xyz);
  v.xyz += to_eye * (u_lift * u_scale * max(length(a_u), length(a_v)));
  v_uv = uv;
  gl_Position = u_projection * v;
}
