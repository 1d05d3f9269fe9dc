#pragma once
/// \file input_script.h
/// `--events FILE`: a text script of mouse and keyboard input, expanded into one input state per
/// frame. The viewer writes each state into Dear ImGui's IO, where the GLFW callbacks leave the live
/// input, before the frame starts; App::handle_input then treats it as it treats a real mouse.
///
/// One event a line ('#' starts a comment), coordinates in window pixels (origin top left):
///   drag [shift-|ctrl-]left|right|middle X0 Y0 X1 Y1 STEPS   cursor to (X0, Y0), press, STEPS
///                                                           frames of equal moves to (X1, Y1), release
///   click X Y                                               cursor to (X, Y), left press, release
///   key [shift-|ctrl-]K     K: A-Z, 0-9, SPACE, ESCAPE, F1   held one frame, released the next
///   wheel DY                                                one frame of DY wheel steps
///   move X Y                                                the cursor to (X, Y), no button
///   frame [N]                                               N frames (default 1) of no change
#include <string>
#include <vector>

namespace viewer {

/// What the GLFW callbacks would have left in Dear ImGui's IO for one frame.
struct InputFrame {
  double x = -1.0, y = -1.0;                ///< cursor in window pixels (-1: not over the window yet)
  bool buttons[3] = {false, false, false};  ///< left, right, middle held
  bool shift = false, ctrl = false;
  int key = -1;        ///< a GLFW key held during this frame, -1 for none
  float wheel = 0.0f;  ///< wheel steps this frame
};

/// The frames of the script `text` (`name` for the messages). Throws std::runtime_error
/// "NAME:LINE: what is wrong" for an unknown event, a bad number or a missing field.
std::vector<InputFrame> parse_input_script(const std::string& text, const std::string& name);

/// Reads the file `path` and parses it; std::runtime_error naming the file when it cannot be read.
std::vector<InputFrame> read_input_script(const std::string& path);

}  // namespace viewer
