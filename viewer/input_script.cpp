#include "viewer/input_script.h"

#include <GLFW/glfw3.h>
#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace viewer {

namespace {

/// GLFW's code of a key name, -1 when unknown.
int key_code(const std::string& k) {
  if (k.size() == 1 && ((k[0] >= 'A' && k[0] <= 'Z') || (k[0] >= '0' && k[0] <= '9')))
    return k[0];  // GLFW's codes of letters and digits are their ASCII upper case
  if (k == "SPACE") return GLFW_KEY_SPACE;
  if (k == "ESCAPE") return GLFW_KEY_ESCAPE;
  if (k == "F1") return GLFW_KEY_F1;
  return -1;
}

/// Splits "shift-left" into its modifiers and the rest.
std::string strip_modifiers(std::string word, InputFrame& state) {
  for (;;) {
    if (word.rfind("shift-", 0) == 0) {
      state.shift = true;
      word = word.substr(6);
    } else if (word.rfind("ctrl-", 0) == 0) {
      state.ctrl = true;
      word = word.substr(5);
    } else {
      return word;
    }
  }
}

}  // namespace

std::vector<InputFrame> parse_input_script(const std::string& text, const std::string& name) {
  std::vector<InputFrame> frames;
  InputFrame state;  // carried from frame to frame: the cursor stays where the last event left it
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const auto fail = [&](const std::string& what) {
      return std::runtime_error(fmt::format("{}:{}: {} ('{}')", name, number, what, line));
    };
    if (const size_t hash = line.find('#'); hash != std::string::npos) line.resize(hash);
    std::istringstream in(line);
    std::string event;
    if (!(in >> event)) continue;
    // Reads `count` finite numbers; a missing or bad one fails the line.
    const auto numbers = [&](int count, double* out) {
      for (int k = 0; k < count; ++k)
        if (!(in >> out[k]) || !std::isfinite(out[k])) throw fail(fmt::format("'{}' needs {} numbers", event, count));
    };
    InputFrame s = state;
    s.wheel = 0.0f;
    s.key = -1;
    s.shift = s.ctrl = false;
    if (event == "drag") {
      std::string word;
      if (!(in >> word)) throw fail("drag needs a button");
      const std::string button = strip_modifiers(word, s);
      const int b = button == "left" ? 0 : button == "right" ? 1 : button == "middle" ? 2 : -1;
      if (b < 0) throw fail("the button is left, right or middle (shift- or ctrl- before it)");
      double v[5];
      numbers(5, v);
      const int steps = static_cast<int>(v[4]);
      if (steps < 1 || steps != v[4] || steps > 10000) throw fail("STEPS is a whole number in 1..10000");
      s.x = v[0], s.y = v[1];
      frames.push_back(s);  // the cursor arrives
      s.buttons[b] = true;
      frames.push_back(s);  // pressed
      for (int k = 1; k <= steps; ++k) {
        const double t = double(k) / steps;
        s.x = v[0] + t * (v[2] - v[0]), s.y = v[1] + t * (v[3] - v[1]);
        frames.push_back(s);
      }
      s.buttons[b] = false;
      frames.push_back(s);  // released
    } else if (event == "click" || event == "move") {
      double v[2];
      numbers(2, v);
      s.x = v[0], s.y = v[1];
      frames.push_back(s);
      if (event == "click") {
        s.buttons[0] = true;
        frames.push_back(s);
        s.buttons[0] = false;
        frames.push_back(s);
      }
    } else if (event == "key") {
      std::string word;
      if (!(in >> word)) throw fail("key needs a key name");
      s.key = key_code(strip_modifiers(word, s));
      if (s.key < 0) throw fail("the key is A-Z, 0-9, SPACE, ESCAPE or F1");
      frames.push_back(s);
      s.key = -1;
      frames.push_back(s);
    } else if (event == "wheel") {
      double dy = 0.0;
      numbers(1, &dy);
      s.wheel = static_cast<float>(dy);
      frames.push_back(s);
      s.wheel = 0.0f;
    } else if (event == "frame") {
      double n = 1.0;
      if (!in.eof() && !(in >> std::ws).eof()) numbers(1, &n);
      if (n < 1 || n != std::floor(n) || n > 100000) throw fail("frame N: N is a whole number in 1..100000");
      for (int k = 0; k < static_cast<int>(n); ++k) frames.push_back(s);
    } else {
      throw fail("unknown event '" + event + "' (drag, click, key, wheel, move, frame)");
    }
    std::string extra;
    if (in >> extra) throw fail("unexpected '" + extra + "' at the end");
    state = s;
    state.shift = state.ctrl = false;
  }
  return frames;
}

std::vector<InputFrame> read_input_script(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error(path + ": cannot read the event script");
  std::stringstream text;
  text << file.rdbuf();
  return parse_input_script(text.str(), path);
}

}  // namespace viewer
