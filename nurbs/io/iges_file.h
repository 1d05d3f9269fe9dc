#pragma once
/// \file iges_file.h
/// The record layer of an IGES 5.3 file (fixed 80-column ASCII form, spec §2.1): the Start,
/// Global, Directory Entry, Parameter Data and Terminate sections split and checked, before any
/// entity is interpreted. Used by the IGES reader; geometry is built in iges_geometry.h.
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace nurbs::io {

/// The Global section fields the reader uses (spec §2.2.4; G-numbers are parameter indices).
struct IgesGlobal {
  char parameter_delimiter = ',';  ///< G1
  char record_delimiter = ';';     ///< G2
  std::string sender_id;           ///< G3
  std::string file_name;           ///< G4
  std::string system_id;           ///< G5
  double model_scale = 1.0;        ///< G13: model space to real world (not applied)
  int unit_flag = 1;               ///< G14: 1 in, 2 mm, 3 named by G15, 4 ft, ..., 11 microinch
  std::string unit_name;           ///< G15
  double unit_scale_to_mm = 25.4;  ///< length of one file unit in millimetres
  double resolution = 0.0;         ///< G19: minimum user-intended resolution, file units
  int version = 0;                 ///< G23: 11 = IGES 5.3
  /// What was read differently from the letter of the section (a Hollerith count that does not
  /// match its string), each "line L: global parameter k: ...".
  std::vector<std::string> warnings;
};

/// One directory entry: two 80-column lines of 8-column fields (spec §2.2.4.4).
struct IgesDirectoryEntry {
  int de = 0;               ///< sequence number of its first line (odd): the "pointer" to it
  int line = 0;             ///< physical line number of the first line in the file (1-based)
  int type = 0;             ///< field 1
  int parameter_start = 0;  ///< field 2: sequence number of the first parameter line
  int transform = 0;        ///< field 7: pointer to a 124 entry, 0 = none
  int status = 0;           ///< field 9: 8 digits, blank / subordinate / use / hierarchy
  int parameter_lines = 0;  ///< field 14
  int form = 0;             ///< field 15
  std::string label;        ///< field 18, trimmed
  int subscript = 0;        ///< field 19

  /// 0 independent, 1 physically dependent, 2 logically dependent, 3 both (status digits 3-4).
  [[nodiscard]] int subordinate() const { return (status / 10000) % 100; }
};

/// One Parameter Data line: the data columns 1-64 and the directory entry it claims to belong to.
struct IgesParameterLine {
  std::string_view data;  ///< columns 1-64
  int de = 0;             ///< columns 66-72
  int line = 0;           ///< physical line number (1-based)
};

/// A whole file after the record layer: sections checked, directory parsed, parameter lines kept.
struct IgesFile {
  std::string name;                         ///< file name used in error messages
  std::unique_ptr<const std::string> text;  ///< the bytes the string_views point into
  IgesGlobal global;
  std::vector<IgesDirectoryEntry> entries;    ///< entries[(de - 1) / 2]
  std::vector<IgesParameterLine> parameters;  ///< parameters[sequence number - 1]

  /// The entry whose first line has sequence number `de`; `de` must be valid (see has_entry).
  [[nodiscard]] const IgesDirectoryEntry& entry(int de) const { return entries[static_cast<size_t>(de - 1) / 2]; }
  /// True if `de` is an odd sequence number of a directory line (a valid pointer).
  [[nodiscard]] bool has_entry(int de) const {
    return de >= 1 && de % 2 == 1 && static_cast<size_t>(de - 1) / 2 < entries.size();
  }
};

/// Splits `text` (LF or CRLF) into sections and parses Global and Directory; throws ReadError
/// (naming `name` and the line) on records that are not 80 columns, sections out of order,
/// bad sequence numbers, a missing or inconsistent Terminate section, and bad directory fields.
IgesFile parse_iges_file(std::string text, std::string name);

/// Parses the Global section text (columns 1-72 of all G lines, concatenated); `first_line` is
/// the physical line of the first G line, for messages, which name the line holding the problem.
/// A Hollerith string whose count runs past it is read up to the next delimiter, as OpenCASCADE
/// reads Rhino's files, with a line in IgesGlobal::warnings.
IgesGlobal parse_iges_global(std::string_view text, const std::string& name, int first_line);

/// Length of one IGES unit (G14 flag, or G15 name when the flag is 3) in millimetres; returns
/// 0 for an unknown flag or name.
double iges_unit_to_mm(int flag, std::string_view name);

}  // namespace nurbs::io
