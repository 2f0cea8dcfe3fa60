#version 330 core
in vec2 v_offset;
uniform vec3 u_color;
uniform float u_radius;
out vec4 o_color;
void main() {
  float r = length(v_offset);
  float a = 1.0 - smoothstep(u_radius - 0.5, u_radius + 0.5, r);
  if (a <= 0.0) discard;
  // A dark rim of 1.2 pixels around a coloured disc.
  float rim = smoothstep(u_radius - 1.9, u_radius - 1.0, r);
  o_color = vec4(mix(u_color, u_color * 0.25, rim), a);
}
