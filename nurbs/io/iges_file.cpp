#include "nurbs/io/iges_file.h"

#include <fmt/format.h>

#include <array>

#include "nurbs/io/iges_tokens.h"
#include "nurbs/io/read_error.h"

namespace nurbs::io {
namespace {

constexpr std::string_view kSectionOrder = "SGDPT";

struct Record {
  std::string_view text;  // exactly 80 columns
  int line;
};

std::string at_line(int line) { return fmt::format("line {}", line); }

// Splits into 80-column records (LF or CRLF); trailing blank lines and a DOS end-of-file mark
// are ignored, any other line must be exactly 80 columns.
std::vector<Record> split_records(std::string_view text, const std::string& name) {
  std::vector<Record> records;
  std::vector<std::pair<std::string_view, int>> lines;
  size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string_view::npos) end = text.size();
    std::string_view s = text.substr(pos, end - pos);
    if (!s.empty() && s.back() == '\r') s.remove_suffix(1);
    lines.emplace_back(s, ++line);
    pos = end + 1;
  }
  while (!lines.empty() && lines.back().first.find_first_not_of(" \t\x1a") == std::string_view::npos) lines.pop_back();
  for (const auto& [s, n] : lines) {
    if (s.size() != 80)
      throw ReadError(
          name, at_line(n),
          fmt::format("record has {} columns, expected 80 ({})", s.size(), s.size() < 80 ? "truncated" : "too long"));
    records.push_back({s, n});
  }
  return records;
}

int parse_sequence(const Record& r, const std::string& name) {
  auto v = parse_iges_int(r.text.substr(73, 7));
  if (!v)
    throw ReadError(name, at_line(r.line),
                    fmt::format("bad sequence number '{}' in columns 74-80", r.text.substr(73, 7)));
  return *v;
}

// Field `field` (0-based) of one directory line; the second line's fields are numbered 11..20.
int de_field(const Record& r, int field, const std::string& name, int de, bool second = false) {
  std::string_view s = r.text.substr(static_cast<size_t>(field) * 8, 8);
  auto v = parse_iges_int(s);
  if (!v)
    throw ReadError(
        name, at_line(r.line),
        fmt::format("directory entry D{}: field {} '{}' is not an integer", de, field + (second ? 11 : 1), s));
  return *v;
}

IgesDirectoryEntry parse_entry(const Record& a, const Record& b, int de, const std::string& name) {
  IgesDirectoryEntry e;
  e.de = de;
  e.line = a.line;
  e.type = de_field(a, 0, name, de);
  e.parameter_start = de_field(a, 1, name, de);
  e.transform = de_field(a, 6, name, de);
  e.status = de_field(a, 8, name, de);
  e.parameter_lines = de_field(b, 3, name, de, true);
  e.form = de_field(b, 4, name, de, true);
  e.subscript = de_field(b, 8, name, de, true);
  int type2 = de_field(b, 0, name, de, true);
  if (type2 != e.type)
    throw ReadError(name, at_line(b.line),
                    fmt::format("directory entry D{}: type {} on its second line differs from type {} on its first", de,
                                type2, e.type));
  std::string_view label = b.text.substr(56, 8);
  while (!label.empty() && label.front() == ' ') label.remove_prefix(1);
  while (!label.empty() && label.back() == ' ') label.remove_suffix(1);
  e.label = std::string(label);
  return e;
}

}  // namespace

IgesFile parse_iges_file(std::string text_in, std::string name) {
  IgesFile file;
  file.name = std::move(name);
  file.text = std::make_unique<const std::string>(std::move(text_in));
  const std::string& fname = file.name;
  std::vector<Record> records = split_records(*file.text, fname);
  if (records.empty()) throw ReadError(fname, "", "empty file (no IGES records)");

  std::array<std::vector<Record>, 5> sections;
  size_t current = 0;
  for (const Record& r : records) {
    char letter = r.text[72];
    size_t idx = kSectionOrder.find(letter);
    if (letter == 'C' || letter == 'B' || letter == 'F')
      throw ReadError(fname, at_line(r.line),
                      "compressed or binary IGES is not supported (section letter in column 73)");
    if (idx == std::string_view::npos)
      throw ReadError(fname, at_line(r.line), fmt::format("unknown section letter '{}' in column 73", letter));
    if (idx < current)
      throw ReadError(fname, at_line(r.line),
                      fmt::format("section '{}' after section '{}'", letter, kSectionOrder[current]));
    if (current == 4 && !sections[4].empty()) throw ReadError(fname, at_line(r.line), "more than one Terminate record");
    current = idx;
    auto& sec = sections[idx];
    int seq = parse_sequence(r, fname);
    if (seq != static_cast<int>(sec.size()) + 1)
      throw ReadError(fname, at_line(r.line),
                      fmt::format("sequence number {}{} out of order, expected {}", letter, seq, sec.size() + 1));
    sec.push_back(r);
  }
  const auto& [s_sec, g_sec, d_sec, p_sec, t_sec] = sections;
  int last_line = records.back().line;
  if (t_sec.empty()) throw ReadError(fname, at_line(last_line), "no Terminate section (file truncated?)");
  if (g_sec.empty()) throw ReadError(fname, "", "no Global section");
  // Terminate record: counts of S, G, D, P lines in fields "Snnnnnnn" (spec §2.2.6).
  const Record& t = t_sec.front();
  for (size_t k = 0; k < 4; ++k) {
    std::string_view field = t.text.substr(k * 8, 8);
    auto count = parse_iges_int(field.substr(1));
    if (field[0] != kSectionOrder[k] || !count || *count != static_cast<int>(sections[k].size()))
      throw ReadError(fname, at_line(t.line),
                      fmt::format("Terminate record says '{}' but the file has {} {} records (file truncated?)", field,
                                  sections[k].size(), kSectionOrder[k]));
  }

  std::string global_text;
  for (const Record& r : g_sec) global_text.append(r.text.substr(0, 72));
  file.global = parse_iges_global(global_text, fname, g_sec.front().line);

  if (d_sec.size() % 2 != 0)
    throw ReadError(fname, at_line(d_sec.back().line), "odd number of directory lines (an entry needs two)");
  file.entries.reserve(d_sec.size() / 2);
  for (size_t i = 0; i + 1 < d_sec.size(); i += 2)
    file.entries.push_back(parse_entry(d_sec[i], d_sec[i + 1], static_cast<int>(i + 1), fname));

  file.parameters.reserve(p_sec.size());
  for (const Record& r : p_sec) {
    auto de = parse_iges_int(r.text.substr(64, 8));
    if (!de) throw ReadError(fname, at_line(r.line), "bad directory pointer in columns 65-72 of a parameter record");
    file.parameters.push_back({r.text.substr(0, 64), *de, r.line});
  }
  return file;
}

}  // namespace nurbs::io
