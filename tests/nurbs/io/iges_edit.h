#pragma once
// Test helper: an IGES text split into editable entities and re-emitted with consistent
// directory pointers, parameter line counts and Terminate record, so that a test can damage one
// thing at a time. Assumes parameter records without Hollerith strings (as iges_writer writes).
#include <fmt/format.h>

#include <sstream>
#include <string>
#include <vector>

namespace nurbs::io::test {

/// An integer as an IGES parameter (for building parameter lists by hand).
inline std::string s(int v) { return std::to_string(v); }

struct IgesEdit {
  struct Entity {
    std::string d1, d2;               // columns 1-72 of the two directory lines
    std::vector<std::string> fields;  // parameter fields, fields[0] = type
    int pstart_override = 0;          // nonzero: written instead of the real first P line
    bool unterminated = false;        // true: the record delimiter ';' is left out
  };
  std::vector<std::string> start, global;  // columns 1-72
  std::vector<Entity> entities;

  static IgesEdit parse(const std::string& text) {
    IgesEdit e;
    std::istringstream in(text);
    std::string line, pdata;
    std::vector<std::string> dlines;
    while (std::getline(in, line)) {
      if (line.size() < 73) continue;
      const char s = line[72];
      if (s == 'S') e.start.push_back(line.substr(0, 72));
      if (s == 'G') e.global.push_back(line.substr(0, 72));
      if (s == 'D') dlines.push_back(line.substr(0, 72));
      if (s == 'P') pdata += line.substr(0, 64);
    }
    // Parameter records in directory order, each ended by ';'.
    size_t pos = 0;
    for (size_t i = 0; i + 1 < dlines.size(); i += 2) {
      const size_t end = pdata.find(';', pos);
      Entity ent{dlines[i], dlines[i + 1], {}, 0, false};
      std::string rec = pdata.substr(pos, end - pos);
      size_t a = 0;
      while (true) {
        const size_t b = rec.find(',', a);
        std::string f = rec.substr(a, b == std::string::npos ? std::string::npos : b - a);
        while (!f.empty() && f.back() == ' ') f.pop_back();
        while (!f.empty() && f.front() == ' ') f.erase(0, 1);
        ent.fields.push_back(f);
        if (b == std::string::npos) break;
        a = b + 1;
      }
      e.entities.push_back(ent);
      pos = end + 1;
      // Skip the padding up to the next line start.
      pos = (pos + 63) / 64 * 64;
    }
    return e;
  }

  // D-number of the nth entity of `type`.
  int find(int type, int nth = 0) const {
    for (size_t i = 0; i < entities.size(); ++i)
      if (std::stoi(entities[i].d1.substr(0, 8)) == type && nth-- == 0) return static_cast<int>(2 * i + 1);
    return 0;
  }
  Entity& at(int de) { return entities[static_cast<size_t>(de - 1) / 2]; }
  std::vector<std::string>& fields(int de) { return at(de).fields; }
  // Sets directory field `field` (1-9 on the first line, 11-19 on the second) to `value`.
  void set_de_field(int de, int field, int value) {
    std::string& line = field <= 10 ? at(de).d1 : at(de).d2;
    const int k = field <= 10 ? field - 1 : field - 11;
    line.replace(static_cast<size_t>(k) * 8, 8, fmt::format("{:8}", value));
  }
  int append(int type, std::vector<std::string> f, int form = 0) {
    f.insert(f.begin(), std::to_string(type));
    entities.push_back({fmt::format("{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:8}", type, 0, 0, 0, 0, 0, 0, 0, "00010000"),
                        fmt::format("{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:8}{:8}", type, 0, 0, 0, form, "", "", "", 0), f, 0,
                        false});
    return static_cast<int>(2 * entities.size() - 1);
  }

  // The whole file, with parameter lines, directory pointers and Terminate counts recomputed.
  std::string text() const {
    std::string out;
    auto rec = [&](const std::string& data, char s, int seq) { out += fmt::format("{:<72}{}{:7}\n", data, s, seq); };
    int n = 0;
    for (const auto& s : start) rec(s, 'S', ++n);
    n = 0;
    for (const auto& g : global) rec(g, 'G', ++n);
    std::vector<std::vector<std::string>> plines;
    for (const auto& e : entities) {
      std::vector<std::string> lines(1);
      for (size_t i = 0; i < e.fields.size(); ++i) {
        const std::string f = e.fields[i] + (i + 1 == e.fields.size() && !e.unterminated ? ";" : ",");
        if (lines.back().size() + f.size() > 64) lines.emplace_back();
        lines.back() += f;
      }
      if (e.fields.empty()) lines.back() = " ";
      plines.push_back(lines);
    }
    int d = 0, p = 1;
    for (size_t i = 0; i < entities.size(); ++i) {
      std::string d1 = entities[i].d1, d2 = entities[i].d2;
      d1.replace(8, 8, fmt::format("{:8}", entities[i].pstart_override ? entities[i].pstart_override : p));
      d2.replace(24, 8, fmt::format("{:8}", plines[i].size()));
      rec(d1, 'D', ++d);
      rec(d2, 'D', ++d);
      p += static_cast<int>(plines[i].size());
    }
    p = 0;
    for (size_t i = 0; i < entities.size(); ++i)
      for (const auto& l : plines[i]) out += fmt::format("{:<64} {:7}P{:7}\n", l, 2 * i + 1, ++p);
    rec(fmt::format("S{:7}G{:7}D{:7}P{:7}", start.size(), global.size(), d, p), 'T', 1);
    return out;
  }
};

}  // namespace nurbs::io::test
