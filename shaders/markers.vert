#version 330 core
// Discs of constant pixel radius, one instance per point.
layout(location = 0) in vec3 a_center;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform vec2 u_viewport;
uniform float u_radius;    // pixels
uniform float u_lift;      // world units toward the eye
uniform bool u_orthographic;

out vec2 v_offset;         // pixels from the centre

void main() {
  vec4 v = u_view * vec4(a_center, 1.0);
  vec3 to_eye = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v.xyz);
  v.xyz += to_eye * u_lift;
  vec4 c = u_projection * v;
  vec2 corner = vec2((gl_VertexID & 1) == 0 ? -1.0 : 1.0, (gl_VertexID & 2) == 0 ? -1.0 : 1.0);
  v_offset = corner * (u_radius + 1.5);
  c.xy += v_offset / (u_viewport * 0.5) * c.w;
  gl_Position = c;
}
