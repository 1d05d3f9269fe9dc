#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>

#include "nurbs/io/iges_file.h"
#include "nurbs/io/iges_tokens.h"
#include "nurbs/io/read_error.h"

namespace nurbs::io {
namespace {

struct UnitName {
  std::string_view name;
  double mm;
};
// Spec §2.2.4.3.15: the unit names that go with flags 1..11.
constexpr std::array<UnitName, 13> kUnits{{{"IN", 25.4},
                                           {"INCH", 25.4},
                                           {"MM", 1.0},
                                           {"FT", 304.8},
                                           {"MI", 1609344.0},
                                           {"M", 1000.0},
                                           {"KM", 1.0e6},
                                           {"MIL", 0.0254},
                                           {"UM", 1.0e-3},
                                           {"CM", 10.0},
                                           {"UIN", 2.54e-5},
                                           {"MICRON", 1.0e-3},
                                           {"MICROINCH", 2.54e-5}}};
constexpr std::array<double, 12> kFlagMm{0.0,    25.4,  1.0,    0.0,    304.8, 1609344.0,
                                         1000.0, 1.0e6, 0.0254, 1.0e-3, 10.0,  2.54e-5};

}  // namespace

double iges_unit_to_mm(int flag, std::string_view name) {
  if (flag == 3) {
    std::string upper(name);
    for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    for (const auto& u : kUnits)
      if (u.name == upper) return u.mm;
    return 0.0;
  }
  if (flag < 1 || flag >= static_cast<int>(kFlagMm.size())) return 0.0;
  return kFlagMm[static_cast<size_t>(flag)];
}

IgesGlobal parse_iges_global(std::string_view text, const std::string& name, int first_line) {
  IgesGlobal g;
  // Line of a character offset: G records contribute 72 columns each.
  auto line_of = [&](size_t offset) {
    return first_line + static_cast<int>(std::min(offset, text.empty() ? 0 : text.size() - 1) / 72);
  };
  auto where = [&](size_t offset) { return fmt::format("line {}: global section", line_of(offset)); };
  // G1 and G2 define the delimiters themselves, so they are read before general tokenizing.
  size_t pos = 0;
  auto read_delimiter = [&](char fallback, int index) {
    char d = fallback;
    if (text.substr(pos, 2) == "1H" && pos + 2 < text.size()) {
      d = text[pos + 2];
      pos += 3;
    } else if (pos < text.size() && text[pos] != g.parameter_delimiter && text[pos] != fallback) {
      throw ReadError(name, where(pos),
                      fmt::format("parameter {} must be empty or 1Hc (a delimiter character)", index));
    }
    return d;
  };
  g.parameter_delimiter = read_delimiter(',', 1);
  if (pos >= text.size() || text[pos] != g.parameter_delimiter)
    throw ReadError(name, where(pos), "expected the parameter delimiter after parameter 1");
  ++pos;
  g.record_delimiter = read_delimiter(';', 2);
  if (g.record_delimiter == g.parameter_delimiter)
    throw ReadError(name, where(0), "parameter and record delimiters are the same character");
  IgesTokens tokens = tokenize_iges(text, pos, g.parameter_delimiter, g.record_delimiter, /*lenient_hollerith=*/true);
  if (!tokens.error.empty()) throw ReadError(name, where(tokens.error_offset), tokens.error);
  for (const IgesHollerithRepair& r : tokens.repairs)
    g.warnings.push_back(fmt::format(
        "line {}: global parameter {}: Hollerith count {} {} its string; read up to the "
        "delimiter",
        line_of(r.offset), r.field + 2, r.count, r.count > r.length ? "runs past" : "ends before the end of"));
  if (!tokens.terminated) throw ReadError(name, where(text.size()), "no record delimiter (section truncated?)");
  // tokens.fields[0] is the (empty) remainder of G2, so G-number k is fields[k - 2].
  const auto& f = tokens.fields;
  auto field = [&](int k) -> const IgesToken* {
    return k - 2 < static_cast<int>(f.size()) ? &f[static_cast<size_t>(k - 2)] : nullptr;
  };
  auto str = [&](int k) {
    const IgesToken* t = field(k);
    return t ? std::string(t->text) : std::string();
  };
  auto real = [&](int k, double fallback) {
    const IgesToken* t = field(k);
    if (!t || t->text.empty()) return fallback;
    auto v = parse_iges_real(t->text);
    if (!v || !std::isfinite(*v))
      throw ReadError(name, where(t->offset), fmt::format("parameter {} '{}' is not a finite number", k, t->text));
    return *v;
  };
  auto integer = [&](int k, int fallback) {
    const IgesToken* t = field(k);
    if (!t || t->text.empty()) return fallback;
    auto v = parse_iges_int(t->text);
    if (!v) throw ReadError(name, where(t->offset), fmt::format("parameter {} '{}' is not an integer", k, t->text));
    return *v;
  };
  g.sender_id = str(3);
  g.file_name = str(4);
  g.system_id = str(5);
  g.model_scale = real(13, 1.0);
  g.unit_flag = integer(14, 1);
  g.unit_name = str(15);
  g.resolution = real(19, 0.0);
  g.version = integer(23, 0);
  g.unit_scale_to_mm = iges_unit_to_mm(g.unit_flag, g.unit_name);
  if (g.unit_scale_to_mm == 0.0 && g.unit_flag != 3)
    throw ReadError(name, where(field(14) ? field(14)->offset : 0),
                    fmt::format("parameter 14: unknown unit flag {}", g.unit_flag));
  if (g.unit_scale_to_mm == 0.0)
    throw ReadError(name, where(field(15) ? field(15)->offset : 0),
                    fmt::format("parameter 15: unknown unit name '{}'", g.unit_name));
  return g;
}

}  // namespace nurbs::io
