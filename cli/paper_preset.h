#pragma once
/// \file paper_preset.h
/// `--paper`: one flag that sets every switch of a command which chooses between a paper's algorithm
/// and the project's improvements to the paper's value. An explicit option that contradicts the
/// preset is refused (exit 2, naming both); one that agrees is fine. The JSON object "preset" names
/// the preset in force ("paper" or "default") and the value each governed switch had, so that a
/// default run shows what it changed.
#include <CLI/CLI.hpp>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace cli {

class PaperPreset {
 public:
  /// Adds the flag --paper to `cmd`; `paper` names the paper in its help ("Krishnamurthy et al.").
  /// The help lists the governed switches as they are added.
  void add_flag(CLI::App* cmd, std::string paper);

  /// A switch the preset governs: `option` is the command's own (given when its count() > 0),
  /// `paper` the paper's value as JSON (a string or number as the option spells it; a bool for a
  /// flag: true = given), `section` where the paper takes it (for --help), `get` the value in the
  /// command's options (compared with `paper` when the option is given), `set` stores the paper's.
  void govern(CLI::Option* option, nlohmann::json paper, std::string section, std::function<nlohmann::json()> get,
              std::function<void()> set);
  /// The same for an option or flag that stores into `value` (a string, an integer or a bool).
  template <class T>
  void govern(CLI::Option* option, T& value, T paper, std::string section) {
    govern(
        option, nlohmann::json(paper), std::move(section), [&value] { return nlohmann::json(value); },
        [&value, paper] { value = paper; });
  }

  /// In the command's callback, before its own checks: with --paper, BadInput (exit 2) "--paper sets
  /// OPTION VALUE; OPTION GIVEN contradicts it" for the first given option that differs from the
  /// paper's value, then every governed switch set to it. Without --paper, nothing.
  void apply() const;

  [[nodiscard]] bool paper() const { return paper_; }

  /// {"name": "paper" | "default", "settings": {OPTION: value}} with OPTION the long name without
  /// dashes and the value as the command's options hold it after apply(); `used` replaces values the
  /// command resolved itself (an "auto" that became "gpu", a -1 that became 65536).
  [[nodiscard]] nlohmann::json json(const nlohmann::json& used = nlohmann::json::object()) const;

  /// "preset: paper" on a line of its own on stdout with --paper; nothing without.
  void print_text() const;

 private:
  struct Switch {
    CLI::Option* option;
    nlohmann::json paper;
    std::string section;
    std::function<nlohmann::json()> get;
    std::function<void()> set;
  };
  void describe();

  bool paper_ = false;
  CLI::Option* flag_ = nullptr;
  std::string paper_name_;
  std::vector<Switch> switches_;
};

}  // namespace cli
