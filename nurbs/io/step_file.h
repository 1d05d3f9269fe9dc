#pragma once
/// \file step_file.h
/// ISO 10303-21 (STEP Part 21) exchange structure: the HEADER's schema and the DATA section's
/// entity instances, parsed into values without interpreting them (step_reader.h does that).
/// Internal to the STEP reader, public for its tests.
///
/// Accepted: simple instances `#12 = NAME(p, ...);` and complex ones `#12 = (A(...) B(...));`,
/// parameters of every Part 21 kind (integer, real, 'string', .ENUM., #ref, (list), $, *,
/// TYPED(value), "binary"), /* comments */ anywhere between tokens. Lexical damage inside an
/// instance's parameters (a reference beyond the instance numbers' range, a malformed number) is
/// kept with the instance (StepEntity::damage) instead of refusing the file: a reader fails only
/// when it uses that instance. Limits keep any input bounded:
/// lists nest at most kMaxStepNesting deep and every value costs at least one byte of the file,
/// so memory grows with the file only.
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace nurbs::io {

inline constexpr int kMaxStepNesting = 64;

struct StepValue {
  enum class Kind : std::uint8_t { Null, Derived, Integer, Real, String, Enum, Ref, List, Typed, Binary };
  Kind kind = Kind::Null;
  double number = 0.0;           ///< Integer, Real
  long ref = 0;                  ///< Ref: the instance number
  std::string text;              ///< String (unescaped ''), Enum (without dots), Typed (its type name), Binary
  std::vector<StepValue> items;  ///< List; Typed: its one value
};

/// One partial record: a simple instance has one, a complex instance several (alphabetical in the file).
struct StepRecord {
  std::string type;  ///< upper case as in the file
  std::vector<StepValue> params;
};

struct StepEntity {
  long id = 0;
  int line = 0;  ///< line of the file where the instance starts
  std::vector<StepRecord> records;
  /// The first lexical problem of its parameters ("reference #18446744073709551615 out of range"),
  /// empty when intact. A damaged parameter reads as $ (StepValue::Kind::Null).
  std::string damage;
  /// The record of `type`, or null.
  [[nodiscard]] const StepRecord* record(const std::string& type) const;
  /// The simple instance's type, or "(A B ...)" for a complex one.
  [[nodiscard]] std::string type_name() const;
};

struct StepFile {
  std::string name;                  ///< file name, for messages
  size_t bytes = 0;                  ///< size of the text
  std::vector<std::string> schemas;  ///< FILE_SCHEMA
  std::vector<long> order;           ///< instance numbers in file order
  std::unordered_map<long, StepEntity> entities;
  [[nodiscard]] const StepEntity* find(long id) const {
    const auto it = entities.find(id);
    return it == entities.end() ? nullptr : &it->second;
  }
};

/// Parses `text`; throws ReadError ("NAME: line L: problem") on any syntax error outside an
/// instance's parameters (their lexical damage is kept, see StepEntity::damage), on an unclosed
/// string or comment, on an instance number defined twice and beyond the limits above.
StepFile parse_step_file(const std::string& text, const std::string& name);

/// Quick test of the first bytes: "ISO-10303-21;".
bool looks_like_step(const std::string& text);

}  // namespace nurbs::io
