#version 330 core
// Screen-space thick line segments, one instance per segment, a quad of 4
// vertices (triangle strip) expanded across the projected segment. Core GL
// has no wide lines, so widths are made here.
layout(location = 0) in vec3 a_p0;
layout(location = 1) in vec3 a_p1;

uniform mat4 u_view;
uniform mat4 u_projection;
uniform vec2 u_viewport;   // pixels
uniform float u_width;     // pixels
uniform float u_lift;      // world units toward the eye (keeps lines above the surface)
uniform bool u_orthographic;

out float v_across;        // -1 .. 1 across the line
out float v_half_width;    // pixels

vec4 lifted(vec3 p) {
  vec4 v = u_view * vec4(p, 1.0);
  vec3 to_eye = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v.xyz);
  v.xyz += to_eye * u_lift;
  return u_projection * v;
}

void main() {
  vec4 c0 = lifted(a_p0), c1 = lifted(a_p1);
  int corner = gl_VertexID;  // 0..3
  vec4 c = (corner & 1) == 0 ? c0 : c1;
  vec2 s0 = c0.xy / c0.w * u_viewport * 0.5, s1 = c1.xy / c1.w * u_viewport * 0.5;
  vec2 dir = s1 - s0;
  float len = length(dir);
  dir = len > 1e-6 ? dir / len : vec2(1.0, 0.0);
  vec2 normal = vec2(-dir.y, dir.x);
  float side = (corner & 2) == 0 ? -1.0 : 1.0;
  float half_width = 0.5 * u_width + 1.0;  // one pixel more for the smooth edge
  // Extend half a width along the segment so joints have no gaps.
  vec2 offset = normal * side * half_width + dir * (((corner & 1) == 0) ? -0.5 : 0.5) * u_width;
  c.xy += offset / (u_viewport * 0.5) * c.w;
  gl_Position = c;
  v_across = side;
  v_half_width = half_width;
}
