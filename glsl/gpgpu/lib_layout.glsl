// Long 1D arrays in 2D textures, row-major (gpgpu/layout.h): element i at (i % width, i / width).
ivec2 layout_texel(int i, int width) { return ivec2(i % width, i / width); }
int layout_index(ivec2 texel, int width) { return texel.y * width + texel.x; }
// Arrays with a power-of-two width (gpgpu/layout.h, layout_pow2): no integer division.
ivec2 pow2_texel(int i, int width) { return ivec2(i & (width - 1), i >> findMSB(width)); }
