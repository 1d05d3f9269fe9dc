#pragma once
/// \file ping_pong.h
/// Two same-size textures for iterative passes: read src(), write dst(), then swap(). A texture is
/// never read and written in one pass (that would be a feedback loop, undefined in GL).
#include <utility>

#include "gpgpu/texture.h"

namespace gpgpu {

class PingPong {
 public:
  PingPong(int width, int height, Format format) : a_(width, height, format), b_(width, height, format) {}
  [[nodiscard]] Texture& src() { return flipped_ ? b_ : a_; }
  [[nodiscard]] Texture& dst() { return flipped_ ? a_ : b_; }
  void swap() { flipped_ = !flipped_; }

 private:
  Texture a_, b_;
  bool flipped_ = false;
};

}  // namespace gpgpu
