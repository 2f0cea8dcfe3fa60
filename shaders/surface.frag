#version 330 core
// Surface shading: base colour or a quantity (vertex / triangle / edge
// scalar through a colormap, triangle colours, corner colours), flat or
// smooth normals, a two-sided headlight, the barycentric wireframe and
// highlighted triangles.
in vec3 v_view_position;
in vec3 v_view_normal;
in float v_value;
noperspective in vec3 v_barycentric;

uniform int u_color_mode;            // 0 base, 1 vertex, 2 triangle, 3 edge scalar, 4 triangle colours,
                                     // 5 corner colours
uniform vec3 u_base_color;
uniform sampler2D u_colormap;        // 256 x 1
uniform vec2 u_range;                // mapped values at the colormap ends
uniform samplerBuffer u_triangle_values;   // modes 2 (1 per triangle) and 3 (3 per triangle)
uniform samplerBuffer u_triangle_colors;   // RGBA8: mode 4 (1 per triangle), mode 5 (3 per triangle)
uniform usamplerBuffer u_triangle_flags;   // bit 0: highlighted
uniform bool u_has_flags;
uniform vec3 u_highlight_color;
uniform bool u_flat;
uniform bool u_wireframe;
uniform float u_wire_width;          // pixels
uniform vec3 u_wire_color;
uniform bool u_orthographic;
uniform int u_first_triangle;        // of the draw call (gl_PrimitiveID counts from it)

out vec4 o_color;

vec3 to_linear(vec3 c) { return pow(c, vec3(2.2)); }
vec3 to_display(vec3 c) { return pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)); }

vec3 scalar_color(float value) {
  if (isnan(value) || isinf(value)) return vec3(0.55);
  float t = (value - u_range.x) / max(u_range.y - u_range.x, 1e-30);
  if (u_range.y <= u_range.x) t = 0.5;
  return texture(u_colormap, vec2(clamp(t, 0.0, 1.0) * (255.0 / 256.0) + 0.5 / 256.0, 0.5)).rgb;
}

void main() {
  int triangle = u_first_triangle + gl_PrimitiveID;
  vec3 base = u_base_color;
  if (u_color_mode == 1) {
    base = scalar_color(v_value);
  } else if (u_color_mode == 2) {
    base = scalar_color(texelFetch(u_triangle_values, triangle).r);
  } else if (u_color_mode == 3) {
    // The value of the nearest edge: the edge opposite the corner whose
    // barycentric coordinate is smallest.
    vec3 b = v_barycentric;
    int k = (b.x <= b.y && b.x <= b.z) ? 0 : (b.y <= b.z ? 1 : 2);
    base = scalar_color(texelFetch(u_triangle_values, 3 * triangle + k).r);
  } else if (u_color_mode == 4) {
    base = texelFetch(u_triangle_colors, triangle).rgb;
  } else if (u_color_mode == 5) {
    // The colour of the nearest corner: the largest barycentric coordinate.
    vec3 b = v_barycentric;
    int k = (b.x >= b.y && b.x >= b.z) ? 0 : (b.y >= b.z ? 1 : 2);
    base = texelFetch(u_triangle_colors, 3 * triangle + k).rgb;
  }
  bool highlighted = u_has_flags && (texelFetch(u_triangle_flags, triangle).r & 1u) != 0u;
  if (highlighted) base = u_highlight_color;

  vec3 n;
  if (u_flat) n = normalize(cross(dFdx(v_view_position), dFdy(v_view_position)));
  else n = normalize(v_view_normal);
  vec3 to_eye = u_orthographic ? vec3(0.0, 0.0, 1.0) : normalize(-v_view_position);
  bool back = dot(n, to_eye) < 0.0;
  if (back) n = -n;

  // Key light from the upper left of the viewer, a weaker fill from the
  // right, ambient; Blinn-Phong highlight of the key light.
  vec3 albedo = to_linear(base);
  vec3 key = normalize(vec3(-0.35, 0.55, 1.0));
  vec3 fill = normalize(vec3(0.6, -0.2, 0.8));
  float diffuse = 0.72 * max(dot(n, key), 0.0) + 0.22 * max(dot(n, fill), 0.0);
  float spec = pow(max(dot(n, normalize(key + to_eye)), 0.0), 48.0);
  vec3 lit = albedo * (0.22 + diffuse) + vec3(0.12 * spec);
  if (back) lit *= vec3(0.62, 0.58, 0.55);  // back faces: darker and warmer
  vec3 color = to_display(lit);

  if (u_wireframe || highlighted) {
    vec3 d = v_barycentric / max(fwidth(v_barycentric), vec3(1e-6));
    float dist = min(d.x, min(d.y, d.z));  // pixels to the nearest edge
    float half_width = highlighted && !u_wireframe ? 0.75 : 0.5 * u_wire_width;
    float a = 1.0 - smoothstep(half_width - 0.5, half_width + 0.5, dist);
    vec3 wire = highlighted ? u_highlight_color * 0.45 : u_wire_color;
    color = mix(color, wire, a);
  }
  o_color = vec4(color, 1.0);
}
