// viewer_check_screenshot FILE.png [--min-segment N] [--count R,G,B M]...: the picture check of the
// viewer's tests. Prints the size, the standard deviation of the luminance, the number of distinct
// colours and the pixels of exactly the distance segment's colour (pure magenta,
// viewer/app_render.cpp), and of each --count colour; exit 1 when the picture is blank (deviation <
// 4 grey levels or < 16 colours), shows fewer than N segment pixels (default 40) or fewer than M
// pixels of exactly colour R,G,B (0-255: the overlays' unlit line colours), 2 when it cannot be read
// or the arguments are wrong.
#include <stb_image.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <set>
#include <vector>

namespace {

struct ColourCount {
  unsigned rgb = 0;
  long at_least = 0, found = 0;
};

}  // namespace

int main(int argc, char** argv) {
  long min_segment = 40;
  std::vector<ColourCount> counts;
  bool usage = argc < 2;
  for (int k = 2; k < argc && !usage;) {
    unsigned r = 256, g = 256, b = 256;
    if (std::strcmp(argv[k], "--min-segment") == 0 && k + 1 < argc) {
      min_segment = std::atol(argv[k + 1]);
      k += 2;
    } else if (std::strcmp(argv[k], "--count") == 0 && k + 2 < argc &&
               std::sscanf(argv[k + 1], "%u,%u,%u", &r, &g, &b) == 3 && r < 256 && g < 256 && b < 256) {
      counts.push_back({(r << 16) | (g << 8) | b, std::atol(argv[k + 2]), 0});
      k += 3;
    } else {
      usage = true;
    }
  }
  if (usage) {
    std::fprintf(stderr, "usage: viewer_check_screenshot FILE.png [--min-segment N] [--count R,G,B M]...\n");
    return 2;
  }
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
    const unsigned rgb = (unsigned(r) << 16) | (unsigned(g) << 8) | b;
    if (colours.size() < 100000) colours.insert(rgb);
    for (ColourCount& c : counts) c.found += c.rgb == rgb ? 1 : 0;
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
  for (const ColourCount& c : counts) {
    std::printf("%ld pixels of colour %u,%u,%u\n", c.found, c.rgb >> 16, (c.rgb >> 8) & 255, c.rgb & 255);
    if (c.found < c.at_least) {
      std::printf("FAIL: at least %ld expected\n", c.at_least);
      return 1;
    }
  }
  return 0;
}
