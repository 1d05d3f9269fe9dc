// A tessellated model: position, normal, face index and a scalar (thickness; < 0 = none) per vertex.
// u_model_view is rigid, so its upper 3x3 also moves the normals.
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in float a_face;
layout(location = 3) in float a_scalar;

uniform mat4 u_mvp;
uniform mat4 u_model_view;

out vec3 v_normal;
out float v_face;
out float v_scalar;

void main() {
  gl_Position = u_mvp * vec4(a_position, 1.0);
  v_normal = mat3(u_model_view) * a_normal;
  v_face = a_face;
  v_scalar = a_scalar;
}
