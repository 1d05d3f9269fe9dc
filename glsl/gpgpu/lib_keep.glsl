// Whether a texel of the stream reduction's input is kept (gpgpu/compact.h), for the first count
// level (histopyramid_build.frag) and the gather's last step (histopyramid_gather.frag): channel 0
// > 0 (a predicate texture), or with PREDICATE_CUT channel 0 <= u_cut (compact_at_most). NaN is
// never kept.
#if PREDICATE_CUT
uniform float u_cut;
uint kept(float v) { return v <= u_cut ? 1u : 0u; }
#else
uint kept(float v) { return v > 0.0 ? 1u : 0u; }
#endif
