// Writes one constant to every covered texel (masks, clears under a stencil test).
uniform vec4 u_value;
out vec4 o_value;

void main() { o_value = u_value; }
