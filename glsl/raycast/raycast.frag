// GPU ray caster of Lemasson et al., one fragment per ray, in float: the Morton BVH of
// bicubic patches (§3.2) walked without a stack (Hapala et al. 2011: parent pointers, three states,
// near child by box centre along the ray), pruned by the best t so far + u_slack; at each leaf the
// ray / patch Newton iteration (§3.3, lib_raycast_newton.glsl) from up to 4 starts, and a converged
// hit nearer than the best gets the cubic trim test (§3.4, lib_raycast_trim.glsl) unless its face
// is untrimmed. CPU twin (double): nurbs/raycast/raycast_cpu.cpp cast_ray (Trim::Cubics,
// Traversal::Stackless), less its final step on the exact surface (queries/raycast/raycast_gpu.cpp does it).
// Output 0: (t, patch in leaf order, s, t) of the nearest hit, (-1, -1, 0, 0) for a miss.
// Output 1: (box tests, patch tests, trim tests, flags) with the twin's counting (Fig. 7 of the
// paper); flags: 1 (doubt) when the trim test rejected a hit nearer than the answer within u_doubt of the
// trim curve, where the exact test may say otherwise (the CPU casts such rays again); + 2 when the
// walk was cut short: llvmpipe ends every loop of an invocation after 65535 iterations in all
// (LP_MAX_TGSI_LOOP_ITERATIONS), which a walk through 10^5 overlapping patches reaches. Fixed
// counts (NEWTON_ITERATIONS, TRIM_ITERATIONS: generated defines) unroll and spend none of them.
#include "lib_float.glsl"
#include "lib_layout.glsl"
#include "lib_raycast_newton.glsl"
#include "lib_raycast_patch.glsl"
#include "lib_raycast_trim.glsl"

uniform sampler2D u_origins;     // RGBA32F ray origins relative to the scene centre, 16 per 4 x 4 tile
uniform sampler2D u_directions;  // RGBA32F unit directions, same layout
uniform int u_count;             // rays in this pass
uniform int u_width;             // width of the ray textures (a power of two >= 4)
// BVH: 4 texels per node: (box min, parent), (box max, left), then for an internal node (centre of
// the left box - centre of the right box, times 2; right) and for a leaf (first, last, 0, -1), then
// the parent's such vector and the sibling (>= 0 for a left child, -1 - sibling for a right one), so
// that a step needs no texel of the parent: near child of the parent <=> (vector . d <= 0) == left.
uniform sampler2D u_nodes;
uniform int u_nodes_width;
uniform int u_max_steps;  // guard: each node is entered at most 3 times, plus a step after each leaf
uniform float u_t_min;
uniform float u_slack;   // 4 tolerance size, as cast_ray's: boxes are padded, exact hits move
uniform float u_ulps;    // eps3 = u_ulps 2^-24 (|origin| + u_radius)
uniform float u_radius;  // largest |control point - centre|
uniform float u_doubt;   // trim doubt margin (model units) at normal incidence
uniform int u_two;       // 2: the end-of-walk probe loop runs twice unless the loop budget is spent
layout(location = 0) out vec4 o_hit;
layout(location = 1) out vec4 o_counts;

// The walk's state (set in main: global initialisers must be constant expressions).
float g_best, g_doubt;
int g_patch, g_boxes, g_patches, g_trims;
vec2 g_st;

vec4 node_texel(int i, int k) { return texelFetch(u_nodes, pow2_texel(4 * i + k, u_nodes_width), 0); }

// near_is_left: c = the children's box centre difference. The walk decides it twice per node, on
// the way down and back up from a child; `precise` (no fused multiply-add) makes both bit-identical
// even where the sum is a rounding error from 0 (children with equal boxes), else the walk would
// skip the far subtree.
bool left_is_near(vec3 c, vec3 d) {
  precise float s = c.x * d.x + c.y * d.y + c.z * d.z;
  return s <= 0.0;
}

// Slab test for t in [u_t_min, t_max] (as ray_box: a zero direction component with the origin in
// the slab, even on its planes, constrains nothing).
bool ray_box(RayF r, vec3 inv, vec3 lo, vec3 hi, float t_max) {
  vec3 t0 = (lo - r.o) * inv, t1 = (hi - r.o) * inv;
  bvec3 z = equal(r.d, vec3(0.0));
  if (any(z)) {
    bvec3 out_slab = bvec3(lessThan(r.o, lo).x || greaterThan(r.o, hi).x, lessThan(r.o, lo).y || greaterThan(r.o, hi).y,
                           lessThan(r.o, lo).z || greaterThan(r.o, hi).z);
    if (any(bvec3(z.x && out_slab.x, z.y && out_slab.y, z.z && out_slab.z))) return false;
    t0 = mix(t0, vec3(-pos_inf()), z);
    t1 = mix(t1, vec3(pos_inf()), z);
  }
  vec3 tn = min(t0, t1), tf = max(t0, t1);
  return max(u_t_min, max(tn.x, max(tn.y, tn.z))) <= min(t_max, min(tf.x, min(tf.y, tf.z)));
}

// One patch: Newton from each start; a converged hit in front of u_t_min and nearer than the best
// gets the trim test (§3.4). The order of the starts does not matter: the nearest material hit wins.
void test_patch(int k, RayF r) {
  Patch P = load_patch(k, r);
  Starts q = initial_guesses(P);
  bool trimmed = trim_count(P.face) > 0;
  for (int m = 0; m < 4 && q.t.x < pos_inf(); ++m) {
    NewtonHit h = newton_patch(P, r.eps3, vec2(q.s.x, q.u.x));
    q.t = vec4(q.t.yzw, pos_inf()), q.s = q.s.yzwx, q.u = q.u.yzwx;
    if (!h.converged || !(h.t > u_t_min) || !(h.t < g_best)) continue;
    if (trimmed) {
      ++g_trims;
      vec2 size = P.range.yw - P.range.xz, uv = P.range.xz + h.st * size, pc;
      if (!inside_trim(P.face, uv, pc)) {
        // Near the edge the exact hit (up to the bicubic tolerance / cos away) may be material.
        vec2 dst = (pc - uv) / size;
        float cosine = abs(normalize(cross(h.e.ss, h.e.st)).z);  // the ray is z in its frame
        if (length(h.e.ss * dst.x + h.e.st * dst.y) <= u_doubt / max(cosine, 1.0 / 16.0)) g_doubt = min(g_doubt, h.t);
        continue;
      }
    }
    g_best = h.t, g_patch = k, g_st = h.st;
  }
}

// A reached leaf: its patches, then the new t_max (cast_ray's visit).
float visit(int i, RayF r) {
  vec4 c = node_texel(i, 2);  // (first, last, 0, -1)
  for (int k = int(c.x); k <= int(c.y); ++k) test_patch(k, r);
  g_patches += int(c.y) - int(c.x) + 1;
  return g_patch >= 0 ? g_best + u_slack : pos_inf();
}

void main() {
  ivec2 g = ivec2(gl_FragCoord.xy);
  int index = (((g.y >> 2) * (u_width >> 2) + (g.x >> 2)) << 4) + ((g.y & 3) << 2) + (g.x & 3);
  o_hit = vec4(-1.0, -1.0, 0.0, 0.0);
  o_counts = vec4(0.0);
  if (index >= u_count) return;
  g_best = g_doubt = pos_inf();
  g_patch = -1, g_boxes = g_patches = g_trims = 0;
  g_st = vec2(0.0);
  vec3 o = texelFetch(u_origins, g, 0).xyz, d = texelFetch(u_directions, g, 0).xyz;
  RayF r = make_ray(o, d, u_ulps * exp2(-24.0) * (length(o) + u_radius));
  vec3 inv = 1.0 / d;
  float t_max = pos_inf();
  // traverse_stackless, states from parent (0), from sibling (1), from child (2), in the
  // "while-while" form of Aila and Laine (HPG 2009): the inner loop walks until the ray reaches a
  // leaf, so the lanes of a SIMD group run their (costly) leaves together rather than each in turn.
  // Each step reads the current node's four texels whatever the state (SIMD lanes run every branch
  // anyway); `visited` sends a leaf just visited on as a missed box would go.
  const int kRoot = 0;
  bool done = false, visited = false;
  int cur = kRoot, state = 0, steps = 0;
  while (!done) {
    int leaf = -1;
    while (leaf < 0 && !done) {
      vec4 n0 = node_texel(cur, 0), n1 = node_texel(cur, 1), n2 = node_texel(cur, 2), n3 = node_texel(cur, 3);
      int parent = int(n0.w), sib = n3.w >= 0.0 ? int(n3.w) : -1 - int(n3.w);
      bool near = left_is_near(n3.xyz, r.d) == (n3.w >= 0.0);  // cur is its parent's near child
      bool hit = false;
      if (state != 2 && !visited) {
        ++g_boxes;
        hit = ray_box(r, inv, n0.xyz, n1.xyz, t_max);
      }
      visited = false;
      if (++steps > u_max_steps || (cur == kRoot && (state == 2 || !hit))) {
        done = true;  // back at the root, or its box missed
      } else if (state == 2) {
        if (near)
          cur = sib, state = 1;
        else
          cur = parent;
      } else if (hit && n1.w < 0.0) {
        leaf = cur;
      } else if (hit) {
        cur = left_is_near(n2.xyz, r.d) ? int(n1.w) : int(n2.w), state = 0;
      } else if (state == 0) {
        cur = sib, state = 1;
      } else {
        cur = parent, state = 2;
      }
    }
    if (leaf < 0) break;  // done, or cut (then done is false)
    t_max = visit(leaf, r);
    visited = true;
    done = leaf == kRoot;  // a one-patch scene
  }
  int probe = 0;
  for (int i = 0; i < u_two; ++i) ++probe;
  bool cut = !done || steps > u_max_steps || probe != 2;
  if (g_patch >= 0) o_hit = vec4(g_best, float(g_patch), g_st);
  o_counts = vec4(float(g_boxes), float(g_patches), float(g_trims), (g_doubt < g_best ? 1.0 : 0.0) + (cut ? 2.0 : 0.0));
}
