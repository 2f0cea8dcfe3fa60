#version 330 core
in vec2 v_uv;
uniform vec3 u_color;
out vec4 o_color;
void main() {
  float r = length(v_uv);             // 1 on the ellipse
  float w = max(fwidth(r), 1e-6);     // one pixel in r units
  if (r > 1.0 + 1.5 * w) discard;
  float outline = 1.0 - smoothstep(0.6, 1.4, abs(r - 1.0) / w);  // ~1.5 px ring
  float inside = 1.0 - smoothstep(1.0 - w, 1.0, r);
  vec3 color = mix(u_color, u_color * 0.35, outline);
  float alpha = max(outline, 0.32 * inside);
  if (alpha <= 0.0) discard;
  o_color = vec4(color, alpha);
}
