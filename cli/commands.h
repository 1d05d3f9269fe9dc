#pragma once
/// \file commands.h
/// Each subcommand registers itself on the CLI11 app; its callback does the work and throws on
/// failure (main maps the exception type to the exit code).
#include <CLI/CLI.hpp>
#include <stdexcept>

#include "cli/common.h"

namespace cli {

/// A command ran but its result is wrong (a self-check mismatch): exit code 1.
class CommandFailed : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

void add_gpu_info(CLI::App& app, const GlobalOptions& global);
void add_selftest(CLI::App& app, const GlobalOptions& global);
void add_info(CLI::App& app, const GlobalOptions& global);
void add_generate(CLI::App& app, const GlobalOptions& global);
void add_evaluate(CLI::App& app, const GlobalOptions& global);
void add_distance(CLI::App& app, const GlobalOptions& global);
void add_clearance(CLI::App& app, const GlobalOptions& global);
void add_clash(CLI::App& app, const GlobalOptions& global);
void add_tessellate(CLI::App& app, const GlobalOptions& global);
void add_deviation(CLI::App& app, const GlobalOptions& global);
void add_inspect(CLI::App& app, const GlobalOptions& global);
void add_raycast(CLI::App& app, const GlobalOptions& global);
void add_thickness(CLI::App& app, const GlobalOptions& global);

}  // namespace cli
