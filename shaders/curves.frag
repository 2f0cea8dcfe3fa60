#version 330 core
in float v_across;
in float v_half_width;
uniform vec3 u_color;
uniform float u_width;
out vec4 o_color;
void main() {
  float d = abs(v_across) * v_half_width;  // pixels from the centre line
  float a = 1.0 - smoothstep(0.5 * u_width - 0.5, 0.5 * u_width + 0.5, d);
  if (a <= 0.0) discard;
  o_color = vec4(u_color, a);
}
