#pragma once
/// \file screenshot.h
/// The default framebuffer's back buffer as a PNG (stb_image_write from Debian's libstb).
#include <string>

namespace viewer {

/// Reads the width x height back buffer of the current context (call before swapping) and writes
/// it to `path` as 8-bit RGB PNG, top row first. Throws std::runtime_error naming the file.
void write_screenshot(const std::string& path, int width, int height);

}  // namespace viewer
