#include "nurbs/io/iges_tokens.h"

#include <charconv>
#include <cmath>
#include <limits>

namespace nurbs::io {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t'; }

std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

}  // namespace

IgesTokens tokenize_iges(std::string_view text, size_t start, char pd, char rd, bool lenient_hollerith) {
  IgesTokens out;
  size_t pos = start;
  while (pos < text.size()) {
    size_t field_start = pos;
    while (pos < text.size() && is_space(text[pos])) ++pos;
    // Hollerith: digits, 'H', then exactly that many characters (spec §2.2.2.6).
    size_t digits_end = pos;
    while (digits_end < text.size() && text[digits_end] >= '0' && text[digits_end] <= '9') ++digits_end;
    if (digits_end > pos && digits_end < text.size() && (text[digits_end] == 'H' || text[digits_end] == 'h')) {
      size_t n = 0;
      std::from_chars(text.data() + pos, text.data() + digits_end, n);
      const size_t content = digits_end + 1;
      size_t after = n <= text.size() - content ? content + n : text.size();
      while (after < text.size() && is_space(text[after])) ++after;
      const bool fits = n <= text.size() - content && (after >= text.size() || text[after] == pd || text[after] == rd);
      size_t length = n;
      if (!fits) {
        const size_t delimiter = text.find_first_of(std::string{pd, rd}, content);
        if (!lenient_hollerith || delimiter == std::string_view::npos) {
          out.error = n > text.size() - content
                          ? "Hollerith string of " + std::to_string(n) + " characters runs past the end of the record"
                          : "unexpected character after Hollerith string";
          out.error_offset = n > text.size() - content ? pos : after;
          return out;
        }
        length = delimiter - content;
        out.repairs.push_back({out.fields.size(), pos, n, length});
      }
      out.fields.push_back({text.substr(content, length), field_start, true});
      pos = content + length;
      while (pos < text.size() && is_space(text[pos])) ++pos;
      if (pos >= text.size()) break;
    } else {
      while (pos < text.size() && text[pos] != pd && text[pos] != rd) ++pos;
      out.fields.push_back({trim(text.substr(field_start, pos - field_start)), field_start, false});
      if (pos >= text.size()) break;
    }
    if (text[pos] == rd) {
      out.terminated = true;
      return out;
    }
    ++pos;  // parameter delimiter
    if (pos == text.size()) out.fields.push_back({std::string_view{}, pos, false});
  }
  return out;
}

std::optional<double> parse_iges_real(std::string_view field) {
  field = trim(field);
  if (field.empty()) return 0.0;
  std::string buf(field);
  for (char& c : buf)
    if (c == 'D' || c == 'd') c = 'E';  // Fortran double-precision exponent
  const char* first = buf.data();
  const char* last = buf.data() + buf.size();
  if (*first == '+') ++first;
  double value = 0.0;
  auto [end, ec] = std::from_chars(first, last, value);
  if (ec == std::errc::result_out_of_range) return std::numeric_limits<double>::infinity();
  if (ec != std::errc() || end != last) return std::nullopt;
  return value;
}

std::optional<int> parse_iges_int(std::string_view field) {
  field = trim(field);
  if (field.empty()) return 0;
  const char* first = field.data();
  const char* last = field.data() + field.size();
  if (*first == '+') ++first;
  int value = 0;
  auto [end, ec] = std::from_chars(first, last, value);
  if (ec == std::errc() && end == last) return value;
  // Some writers put integers in real form ("3."); accept those that are exactly integral.
  auto real = parse_iges_real(field);
  if (!real || !std::isfinite(*real) || std::floor(*real) != *real || std::abs(*real) > 2.0e9) return std::nullopt;
  return static_cast<int>(*real);
}

}  // namespace nurbs::io
