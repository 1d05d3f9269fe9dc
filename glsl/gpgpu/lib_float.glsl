// IEEE helpers that do not rely on the compiler honouring isnan/isinf (fast-math drivers may fold
// them away): classification by bit pattern.
float pos_inf() { return uintBitsToFloat(0x7f800000u); }
bool is_nan_bits(float x) { return (floatBitsToUint(x) & 0x7fffffffu) > 0x7f800000u; }
