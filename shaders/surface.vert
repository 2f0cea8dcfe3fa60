#version 330 core
// Triangles drawn as a soup (3 vertices per triangle, glDrawArrays), so the
// barycentric coordinates of the wireframe come from gl_VertexID and the
// triangle id from gl_PrimitiveID.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_value;  // vertex scalar (already log-mapped if needed)

uniform mat4 u_view;
uniform mat4 u_projection;

out vec3 v_view_position;
out vec3 v_view_normal;
out float v_value;
noperspective out vec3 v_barycentric;

void main() {
  vec4 p = u_view * vec4(a_position, 1.0);
  v_view_position = p.xyz;
  v_view_normal = mat3(u_view) * a_normal;  // the view matrix is a rotation + translation
  v_value = a_value;
  int k = gl_VertexID % 3;
  v_barycentric = vec3(k == 0, k == 1, k == 2);
  gl_Position = u_projection * p;
}
