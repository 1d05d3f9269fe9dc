// Predicate for stream compaction (gpgpu/compact.h): 1 where channel 0 of the input is <= u_cut.
// The potentially-closest cells of Krishnamurthy et al. §3.1: lower bound within the cut-off.
uniform sampler2D u_values;
uniform float u_cut;
out vec4 o_keep;

void main() { o_keep = vec4(texelFetch(u_values, ivec2(gl_FragCoord.xy), 0).r <= u_cut ? 1.0 : 0.0); }
