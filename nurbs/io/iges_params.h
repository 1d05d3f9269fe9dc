#pragma once
/// \file iges_params.h
/// Typed access to the Parameter Data record of one directory entry, with every failure turned
/// into a ReadError that names the file, the line, the entity (D-number and type) and the field.
#include <string>
#include <vector>

#include "nurbs/io/iges_file.h"
#include "nurbs/io/iges_tokens.h"

namespace nurbs::io {

class EntityParams {
 public:
  /// Gathers and tokenizes the parameter lines of `entry`; throws ReadError when the directory's
  /// line range is out of the P section, a line belongs to another entry, the record has no
  /// record delimiter (truncated), or its first field is not the entity type.
  EntityParams(const IgesFile& file, const IgesDirectoryEntry& entry);

  /// Number of parameters after the entity type (spec index 1..size()).
  [[nodiscard]] int size() const { return static_cast<int>(fields_.size()) - 1; }
  /// Throws "bad parameter count" unless at least `count` parameters are present.
  void require(int count) const;
  /// Parameter `i` (1-based) as a finite real.
  [[nodiscard]] double real(int i) const;
  /// Parameter `i` as an integer (also called only to check a field, hence no [[nodiscard]]).
  int integer(int i) const;
  /// Parameter `i` as an integer in [lo, hi], `what` names it in the message.
  int integer(int i, int lo, int hi, const char* what) const;
  /// Parameter `i` as a directory pointer: 0 (only if `allow_null`) or the D-number of an entry.
  int pointer(int i, bool allow_null = false) const;
  /// Parameter `i` as a string (Hollerith content or raw field text).
  [[nodiscard]] std::string string(int i) const;
  /// Checks that what follows parameter `used` is only the optional groups of associativity and
  /// property pointers (spec §2.2.4.5.2); anything else means a wrong count in the record.
  void check_trailing(int used) const;

  /// "line L: entity Dn (type t)" for parameter `i` (0 = the record start).
  [[nodiscard]] std::string where(int i = 0) const;
  /// Throws ReadError at parameter `i` with `problem`.
  [[noreturn]] void fail(int i, const std::string& problem) const;

  [[nodiscard]] const IgesDirectoryEntry& entry() const { return entry_; }
  [[nodiscard]] const IgesFile& file() const { return file_; }

 private:
  const IgesFile& file_;
  const IgesDirectoryEntry& entry_;
  std::string data_;               // the data columns of all lines, 64 per line
  std::vector<IgesToken> fields_;  // fields_[0] is the type
  int first_line_ = 0;
};

/// "entity Dn (type t)", the name of an entity in messages.
std::string entity_name(const IgesDirectoryEntry& e);

}  // namespace nurbs::io
