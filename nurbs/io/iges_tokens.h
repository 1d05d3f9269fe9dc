#pragma once
/// \file iges_tokens.h
/// Free-format parameter tokenizing shared by the Global and Parameter Data sections (IGES 5.3
/// §2.2.3): fields split by the parameter delimiter, ended by the record delimiter, with
/// Hollerith strings (nHxxx) that may contain either delimiter.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nurbs::io {

struct IgesToken {
  std::string_view text;  ///< trimmed field text, or the string content for a Hollerith field
  size_t offset = 0;      ///< offset of the field start in the tokenized text
  bool hollerith = false;
};

/// A Hollerith field whose count does not match its string, read up to the next delimiter instead.
struct IgesHollerithRepair {
  size_t field = 0;   ///< index in IgesTokens::fields
  size_t offset = 0;  ///< offset of the count's first digit in the tokenized text
  size_t count = 0;   ///< the count the file gives
  size_t length = 0;  ///< the characters read: up to the next delimiter
};

struct IgesTokens {
  std::vector<IgesToken> fields;
  std::vector<IgesHollerithRepair> repairs;  ///< only with `lenient_hollerith`
  bool terminated = false;                   ///< the record delimiter was found
  std::string error;                         ///< non-empty: what is malformed (then `error_offset` says where)
  size_t error_offset = 0;
};

/// Tokenizes `text` from `start` until the record delimiter (or the end of `text`). A Hollerith count
/// that runs past the end of `text`, or is not followed by a delimiter, is an error; with
/// `lenient_hollerith` the string is read up to the next delimiter instead and listed in `repairs`
/// (as OpenCASCADE reads such Global sections: Rhino writes counts longer than their strings).
IgesTokens tokenize_iges(std::string_view text, size_t start, char parameter_delimiter, char record_delimiter,
                         bool lenient_hollerith = false);

/// A real number in IGES form ("1.", "-2.5E-3", "1.0D+01"; empty = 0); nullopt if not a number.
/// NaN and infinity are returned as such: the caller rejects them with its own context.
std::optional<double> parse_iges_real(std::string_view field);

/// An integer field (empty = 0; "3." is accepted as 3); nullopt if not an integer in range.
std::optional<int> parse_iges_int(std::string_view field);

}  // namespace nurbs::io
