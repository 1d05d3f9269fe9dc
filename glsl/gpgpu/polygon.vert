// Rasterised 2D geometry given in window coordinates (texel centres at i + 0.5).
layout(location = 0) in vec2 a_window;
uniform vec2 u_target_size;

void main() { gl_Position = vec4(a_window / u_target_size * 2.0 - 1.0, 0.0, 1.0); }
