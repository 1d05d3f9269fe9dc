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

struct IgesTokens {
  std::vector<IgesToken> fields;
  bool terminated = false;  ///< the record delimiter was found
  std::string error;        ///< non-empty: what is malformed (then `error_offset` says where)
  size_t error_offset = 0;
};

/// Tokenizes `text` from `start` until the record delimiter (or the end of `text`).
IgesTokens tokenize_iges(std::string_view text, size_t start, char parameter_delimiter, char record_delimiter);

/// A real number in IGES form ("1.", "-2.5E-3", "1.0D+01"; empty = 0); nullopt if not a number.
/// NaN and infinity are returned as such: the caller rejects them with its own context.
std::optional<double> parse_iges_real(std::string_view field);

/// An integer field (empty = 0; "3." is accepted as 3); nullopt if not an integer in range.
std::optional<int> parse_iges_int(std::string_view field);

}  // namespace nurbs::io
