#pragma once
/// \file validators.h
/// Option checks shared by subcommands. CLI11's Range lets NaN through (every comparison with NaN is
/// false) and prints small bounds as 0.000000, so tolerances get their own check.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <cctype>
#include <cmath>
#include <string>

#include "cli/paper_preset.h"
#include "nurbs/request_error.h"
#include "queries/distance/prepared_model.h"

namespace cli {

/// `text` as a whole as a double: "" when it is one, else the message (naming `what`).
inline std::string parse_double(const std::string& text, double& v, const std::string& what) {
  try {
    size_t used = 0;
    v = std::stod(text, &used);
    if (used == text.size()) return "";
  } catch (const std::exception&) {
  }
  return "'" + text + "' is not a number" + (what.empty() ? "" : " (" + what + ")");
}

/// A tolerance relative to the model size: a finite number in [1e-9, 1]. Below 1e-9 no grid could be
/// stored within the sample limits, and float GPU samples carry about 1e-7 of the size anyway.
inline CLI::Validator relative_tolerance() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        double v = 0;
        if (std::string e = parse_double(text, v, ""); !e.empty()) return e;
        if (!std::isfinite(v) || v < nurbs::kMinRelativeTolerance || v > nurbs::kMaxRelativeTolerance)
          return text + " is not a finite number from 1e-9 to 1 (a fraction of the model size)";
        return "";
      },
      "in [1e-9, 1]");
}

/// A positive finite number (CLI11's PositiveNumber prints its range up to DBL_MAX in 300 digits
/// and lets NaN pass). `what` says what the number is, for the message.
inline CLI::Validator positive_number(const std::string& what = "a positive number") {
  return CLI::Validator(
      [what](std::string& text) -> std::string {
        double v = 0;
        if (std::string e = parse_double(text, v, what); !e.empty()) return e;
        if (!std::isfinite(v) || !(v > 0.0)) return text + " is not " + what;
        return "";
      },
      "POSITIVE");
}

/// A finite number in [lo, hi]: the check written so that NaN fails it (CLI11's Range lets NaN
/// through, and prints its bounds as 0.000000).
inline CLI::Validator finite_range(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double v = 0;
        if (std::string e = parse_double(text, v, ""); !e.empty()) return e;
        if (!(v >= lo && v <= hi)) return fmt::format("{} is not a finite number from {:g} to {:g}", text, lo, hi);
        return "";
      },
      fmt::format("in [{:g}, {:g}]", lo, hi));
}

/// A file name ending in `ext` (any case), e.g. ".ply".
inline CLI::Validator extension_is(const std::string& ext) {
  return CLI::Validator(
      [ext](std::string& text) -> std::string {
        std::string tail = text.size() >= ext.size() ? text.substr(text.size() - ext.size()) : "";
        for (char& c : tail) c = char(std::tolower(static_cast<unsigned char>(c)));
        return tail == ext ? "" : text + ": a " + ext + " file is wanted";
      },
      "*" + ext);
}

/// `--search faithful|coarse-to-fine` (queries::Search): the paper's grids at the tolerance, or
/// coarse grids refined where the answer can be (the default).
inline CLI::Option* add_search_option(CLI::App* cmd, queries::Search& search) {
  return cmd
      ->add_option_function<std::string>(
          "--search",
          [&search](const std::string& name) {
            search = name == "faithful" ? queries::Search::Faithful : queries::Search::CoarseToFine;
          },
          "faithful: every face on a grid at the tolerance (the paper); coarse-to-fine: coarse grids, candidate "
          "cells refined in double until they meet it (same bound, fewer samples)")
      ->check(CLI::IsMember({"faithful", "coarse-to-fine"}))
      ->type_name("faithful|coarse-to-fine")
      ->default_str("coarse-to-fine");
}

/// --search's value as the option spells it.
inline std::string search_name(queries::Search search) {
  return search == queries::Search::Faithful ? "faithful" : "coarse-to-fine";
}

/// --search under the --paper preset: faithful (`section`: where the paper puts every face on a grid
/// at the tolerance).
inline void govern_search(PaperPreset& preset, CLI::Option* option, queries::Search& search, std::string section) {
  preset.govern(
      option, "faithful", std::move(section), [&search] { return search_name(search); },
      [&search] { search = queries::Search::Faithful; });
}

}  // namespace cli
