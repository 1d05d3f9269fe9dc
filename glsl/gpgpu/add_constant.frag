// A map pass used by the tests and the self-check: o = src + u_value, texel by texel.
uniform sampler2D u_src;
uniform vec4 u_value;
out vec4 o_value;

void main() { o_value = texelFetch(u_src, ivec2(gl_FragCoord.xy), 0) + u_value; }
