// viewer_check_screenshot FILE.png [--min-segment N]: the picture check of the viewer.screenshot
// test. Prints the size, the standard deviation of the luminance, the number of distinct colours
// and the pixels of exactly the distance segment's colour (pure magenta, viewer/app_render.cpp);
// exit 1 when the picture is blank (deviation < 4 grey levels or < 16 colours) or shows fewer
// than N segment pixels (default 40), 2 when it cannot be read.
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: viewer_check_screenshot FILE.png [--min-segment N]\n");
    return 2;
  }
  long min_segment = 40;
  if (argc >= 4 && std::strcmp(argv[2], "--min-segment") == 0) min_segment = std::atol(argv[3]);
  int w = 0, h = 0, channels = 0;
  unsigned char* px = stbi_load(argv[1], &w, &h, &channels, 3);
  if (px == nullptr) {
    std::fprintf(stderr, "%s: cannot read the PNG (%s)\n", argv[1], stbi_failure_reason());
    return 2;
  }
  double sum = 0.0, sum2 = 0.0;
  long segment = 0;
  std::set<unsigned> colours;
  const long n = static_cast<long>(w) * h;
  for (long i = 0; i < n; ++i) {
    const unsigned char r = px[3 * i], g = px[3 * i + 1], b = px[3 * i + 2];
    const double y = 0.2126 * r + 0.7152 * g + 0.0722 * b;
    sum += y;
    sum2 += y * y;
    if (r == 255 && g == 0 && b == 255) ++segment;
    if (colours.size() < 100000) colours.insert((unsigned(r) << 16) | (unsigned(g) << 8) | b);
  }
  stbi_image_free(px);
  const double mean = sum / double(n), deviation = std::sqrt(std::max(0.0, sum2 / double(n) - mean * mean));
  std::printf("png %dx%d, luminance mean %.1f deviation %.1f, %zu colours, %ld segment pixels\n", w, h, mean, deviation,
              colours.size(), segment);
  if (deviation < 4.0 || colours.size() < 16) {
    std::printf("FAIL: the picture is blank\n");
    return 1;
  }
  if (segment < min_segment) {
    std::printf("FAIL: %ld segment pixels, at least %ld expected\n", segment, min_segment);
    return 1;
  }
  return 0;
}
