// Sorted Morton keys of the GPU BVH build (queries/raycast/bvh_gpu.h): one RGBA32F texel per element in a
// power-of-two-wide layout, (code >> 15, code & 32767, index, 0) with the 30-bit Morton code in two
// 15-bit halves so every field is exact in float. Karras' delta(i, j) is the common prefix length
// of the 64-bit keys code << 32 | index (nurbs/raycast/morton_bvh.cpp, Prefix), -1 outside [0, n).
uniform sampler2D u_keys;
uniform int u_keys_width;
uniform int u_n;  // leaves

uvec2 bvh_key(int i) {
  vec4 k = texelFetch(u_keys, pow2_texel(i, u_keys_width), 0);
  return uvec2(uint(k.x) * 32768u + uint(k.y), uint(k.z));
}

int bvh_delta(int i, int j) {
  if (j < 0 || j >= u_n) return -1;
  uvec2 a = bvh_key(i), b = bvh_key(j);
  uint x = a.x ^ b.x;
  if (x != 0u) return 31 - findMSB(x);
  return 63 - findMSB(a.y ^ b.y);
}
