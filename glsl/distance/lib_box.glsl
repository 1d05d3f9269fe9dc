// Box-box distances of Krishnamurthy et al. §5.1: for boxes [lo1, hi1] and [lo2, hi2], x = the
// minimum distance between them (0 when they overlap, Eqs. 17-20) and y = the maximum distance
// between a point of one and a point of the other (Eqs. 13-16). CPU twin: queries::box_box_minmax.
vec2 box_box_minmax(vec3 lo1, vec3 hi1, vec3 lo2, vec3 hi2) {
  vec3 B1 = 0.5 * (hi1 - lo1), B2 = 0.5 * (hi2 - lo2);
  vec3 Dc = abs(0.5 * (lo1 + hi1) - 0.5 * (lo2 + hi2));
  return vec2(length(max(Dc - B1 - B2, vec3(0))), length(Dc + B1 + B2));
}
