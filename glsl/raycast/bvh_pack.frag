// GPU BVH build, step 6: the node table of glsl/raycast/raycast.frag (4 texels per node, see there and
// queries/raycast/raycast_gpu.h) from the build's arrays, one fragment per texel: (box min, parent), (box
// max, left), (2 x left centre - right centre, right) or for a leaf (first, last, 0, -1), then the
// parent's such vector and the sibling (-1 - sibling for a right child; zeros at the root).
#include "lib_layout.glsl"

uniform sampler2D u_internal;  // (left, right, first, last) of internal nodes
uniform sampler2D u_parent;    // (parent, sibling, is left, 0)
uniform sampler2D u_min;       // node boxes
uniform sampler2D u_max;
uniform int u_nodes_width;     // of the node arrays
uniform int u_width;           // of the table
uniform int u_n;
out vec4 o_texel;

vec4 at(sampler2D s, int i) { return texelFetch(s, pow2_texel(i, u_nodes_width), 0); }

vec3 centre_vector(int c) {  // (l.min + l.max) - (r.min + r.max) of internal node c
  vec4 node = at(u_internal, c);
  int l = int(node.x), r = int(node.y);
  return (at(u_min, l).xyz + at(u_max, l).xyz) - (at(u_min, r).xyz + at(u_max, r).xyz);
}

void main() {
  int e = layout_index(ivec2(gl_FragCoord.xy), u_width);
  int c = e >> 2, part = e & 3;
  if (c >= 2 * u_n - 1) {
    o_texel = vec4(0.0);
    return;
  }
  bool leaf = c >= u_n - 1;
  vec4 parent = at(u_parent, c);
  if (part == 0) {
    o_texel = vec4(at(u_min, c).xyz, parent.x);
  } else if (part == 1) {
    o_texel = vec4(at(u_max, c).xyz, leaf ? -1.0 : at(u_internal, c).x);
  } else if (part == 2) {
    float k = float(c - (u_n - 1));
    o_texel = leaf ? vec4(k, k, 0.0, -1.0) : vec4(centre_vector(c), at(u_internal, c).y);
  } else if (parent.x < 0.0) {
    o_texel = vec4(0.0);
  } else {
    o_texel = vec4(centre_vector(int(parent.x)), parent.z > 0.5 ? parent.y : -1.0 - parent.y);
  }
}
