#pragma once
/// \file paper_switch.h
/// A setting of a query's options that the papers fix: each front door's options struct has
/// paper(), the options with every such setting at the paper's value, and paper_switches(), the
/// settings it changed with the section of the paper that takes each (for `--paper`, its help and
/// the JSON "preset").
#include <string>
#include <vector>

namespace nurbs {

struct PaperSwitch {
  std::string option;   ///< the setting as the command line spells it, without dashes ("search")
  std::string section;  ///< where the paper takes it ("§3.1, §4")
};

/// The section of `option` in `switches`; empty when the papers do not fix it.
[[nodiscard]] inline std::string paper_section(const std::vector<PaperSwitch>& switches, const std::string& option) {
  for (const PaperSwitch& s : switches)
    if (s.option == option) return s.section;
  return {};
}

}  // namespace nurbs
