#include "cli/paper_preset.h"

#include <fmt/format.h>

#include "cli/common.h"

namespace cli {
// Named, not anonymous: the nurbsgl target is a unity build (cli/CMakeLists.txt).
namespace paper_preset_impl {

/// The option's long name without its dashes ("first-stage"), the key of its setting in JSON.
std::string key(const CLI::Option* option) {
  std::string name = option->get_name();
  return name.substr(name.find_first_not_of('-'));
}

/// A value as the command line spells it after the option's name ("voxels", "2"); "off" for a flag
/// left out.
std::string spelled(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  if (value.is_boolean()) return value.get<bool>() ? "" : "off";
  return value.dump();
}

/// "--first-stage voxels", "--per-point", "--watertight off".
std::string setting(const CLI::Option* option, const nlohmann::json& value) {
  const std::string v = spelled(value);
  return v.empty() ? option->get_name() : option->get_name() + " " + v;
}

}  // namespace paper_preset_impl

void PaperPreset::add_flag(CLI::App* cmd, std::string paper) {
  paper_name_ = std::move(paper);
  flag_ = cmd->add_flag("--paper", paper_, "");
  describe();
}

void PaperPreset::govern(CLI::Option* option, nlohmann::json paper, std::string section,
                         std::function<nlohmann::json()> get, std::function<void()> set) {
  switches_.push_back({option, std::move(paper), std::move(section), std::move(get), std::move(set)});
  describe();
}

void PaperPreset::describe() {
  using namespace paper_preset_impl;
  if (!flag_) return;
  std::string list;
  for (const Switch& s : switches_)
    list += fmt::format("{}{} ({})", list.empty() ? "" : ", ", setting(s.option, s.paper), s.section);
  flag_->description(
      fmt::format("Every switch set to the paper's algorithm ({}): {}. An option given with it that "
                  "contradicts it exits 2",
                  paper_name_, list));
}

void PaperPreset::apply() const {
  using namespace paper_preset_impl;
  if (!paper_) return;
  for (const Switch& s : switches_) {
    if (s.option->count() == 0 || s.get() == s.paper) continue;
    const std::string given =
        s.paper.is_boolean() ? s.option->get_name() : s.option->get_name() + " " + s.option->as<std::string>();
    throw BadInput(fmt::format("--paper sets {}; {} contradicts it", setting(s.option, s.paper), given));
  }
  for (const Switch& s : switches_) s.set();
}

nlohmann::json PaperPreset::json(const nlohmann::json& used) const {
  nlohmann::json settings = nlohmann::json::object();
  for (const Switch& s : switches_) settings[paper_preset_impl::key(s.option)] = s.get();
  settings.update(used);
  return {{"name", paper_ ? "paper" : "default"}, {"settings", settings}};
}

void PaperPreset::print_text() const {
  if (paper_) fmt::print("preset: paper\n");
}

}  // namespace cli
