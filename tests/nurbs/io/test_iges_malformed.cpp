// The malformed-IGES corpus: every case damages one thing in a small valid file written by
// iges_writer (sample_models.h) and expects ReadError with the file name, the place (line or
// entity) and the specific problem in its message.
#include <doctest/doctest.h>

#include <functional>
#include <set>
#include <sstream>

#include "iges_edit.h"
#include "nurbs/io/iges_reader.h"
#include "nurbs/io/iges_writer.h"
#include "nurbs/io/read_error.h"
#include "sample_models.h"

using nurbs::io::test::IgesEdit;

namespace {

struct Mutation {
  std::string text;
  std::vector<std::string> expect;  // substrings of the message besides the file name
};

struct Case {
  const char* name;
  std::function<Mutation(const std::string& base)> mutate;
};

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

std::string join(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

// 1-based number of the first line of section `letter`.
int first_line(const std::vector<std::string>& lines, char letter) {
  for (size_t i = 0; i < lines.size(); ++i)
    if (lines[i][72] == letter) return static_cast<int>(i) + 1;
  return 0;
}

// An entity-level edit: parse, change, re-emit with consistent records.
Case edit(const char* name, std::function<std::vector<std::string>(IgesEdit&)> f) {
  return {name, [f](const std::string& base) {
            IgesEdit e = IgesEdit::parse(base);
            auto expect = f(e);
            return Mutation{e.text(), expect};
          }};
}

// A record-level edit on the lines of the base text.
Case raw(const char* name, std::function<std::vector<std::string>(std::vector<std::string>&)> f) {
  return {name, [f](const std::string& base) {
            auto lines = split_lines(base);
            auto expect = f(lines);
            return Mutation{join(lines), expect};
          }};
}

std::string ent(int de, int type) { return "entity D" + std::to_string(de) + " (type " + std::to_string(type) + ")"; }
std::string at(int line) { return "line " + std::to_string(line) + ":"; }

// Index of the first control point coordinate of a 128 with K1, K2, M1, M2 (IGES §4.24 layout).
size_t surface_point_index(const std::vector<std::string>& f) {
  const int k1 = std::stoi(f[1]), k2 = std::stoi(f[2]), m1 = std::stoi(f[3]), m2 = std::stoi(f[4]);
  return 10 + (k1 + m1 + 2) + (k2 + m2 + 2) + (k1 + 1) * (k2 + 1);
}

const Case kCases[] = {
    raw("truncated line",
        [](auto& l) {
          l.back().resize(40);
          return std::vector<std::string>{at(int(l.size())), "40 columns, expected 80 (truncated)"};
        }),
    raw("overlong line",
        [](auto& l) {
          l[0] += "  ";
          return std::vector<std::string>{at(1), "82 columns", "too long"};
        }),
    raw("no terminate section",
        [](auto& l) {
          l.pop_back();
          return std::vector<std::string>{"no Terminate section"};
        }),
    raw("terminate count wrong",
        [](auto& l) {
          l.back().replace(24, 8, "P      1");
          return std::vector<std::string>{at(int(l.size())), "Terminate record says 'P      1'"};
        }),
    raw("sequence out of order",
        [](auto& l) {
          int d = first_line(l, 'D');
          l[d + 1].replace(73, 7, "      9");
          return std::vector<std::string>{at(d + 2), "sequence number D9 out of order, expected 3"};
        }),
    raw("control bytes in a sequence number (escaped in the message)",
        [](auto& l) {
          int d = first_line(l, 'D');
          l[d + 1].replace(73, 7, "  \x01\x1b[2J");
          return std::vector<std::string>{at(d + 2), "bad sequence number '  \\x01\\x1b[2J' in columns 74-80"};
        }),
    raw("unknown section letter",
        [](auto& l) {
          int d = first_line(l, 'D');
          l[d].replace(72, 1, "X");
          return std::vector<std::string>{at(d + 1), "unknown section letter 'X'"};
        }),
    raw("compressed format",
        [](auto& l) {
          l[1].replace(72, 1, "C");
          return std::vector<std::string>{at(2), "compressed or binary IGES"};
        }),
    raw("sections out of order",
        [](auto& l) {
          int p = first_line(l, 'P');
          l[p - 1][72] = 'G';
          return std::vector<std::string>{at(p), "section 'G' after section 'D'"};
        }),
    raw("empty file",
        [](auto& l) {
          l.clear();
          return std::vector<std::string>{"empty file"};
        }),
    raw("directory type not a number",
        [](auto& l) {
          int d = first_line(l, 'D');
          l[d - 1].replace(0, 8, "   1x4  ");
          return std::vector<std::string>{at(d), "directory entry D1: field 1 '   1x4  ' is not an integer"};
        }),
    raw("directory lines disagree on type",
        [](auto& l) {
          int d = first_line(l, 'D');
          l[d].replace(0, 8, "     128");
          return std::vector<std::string>{at(d + 1), "type 128 on its second line differs from type 144"};
        }),
    raw("unknown unit flag",
        [](auto& l) {
          int g = first_line(l, 'G');
          std::string all;
          for (int i = g - 1; l[i][72] == 'G'; ++i) all += l[i].substr(0, 72);
          size_t p = all.find(",2,2HMM,");
          all.replace(p, 3, ",99,");  // one column longer: the last G line loses a trailing blank
          for (int i = g - 1; l[i][72] == 'G'; ++i) {
            l[i].replace(0, 72, all.substr(0, 72));
            all.erase(0, 72);
          }
          return std::vector<std::string>{"global section", "parameter 14: unknown unit flag 99"};
        }),
    raw("global section unterminated",
        [](auto& l) {
          int g = first_line(l, 'G');
          for (int i = g - 1; l[i][72] == 'G'; ++i)
            for (char& c : l[i])
              if (c == ';' && &c < &l[i][72]) c = ' ';
          return std::vector<std::string>{"global section", "no record delimiter"};
        }),
    edit("parameter record truncated",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.fields(s).resize(20);
           e.at(s).unterminated = true;
           return std::vector<std::string>{"parameter record of " + ent(s, 128) + " truncated (no ';'"};
         }),
    edit("pointer out of range",
         [](IgesEdit& e) {
           int t = e.find(144);
           e.fields(t)[1] = "999";
           return std::vector<std::string>{ent(t, 144), "parameter 1: pointer 999 does not name a directory entry"};
         }),
    edit("even pointer",
         [](IgesEdit& e) {
           int t = e.find(144);
           e.fields(t)[1] = "2";
           return std::vector<std::string>{ent(t, 144), "pointer 2 does not name a directory entry"};
         }),
    edit("pointer to wrong type",
         [](IgesEdit& e) {
           int t = e.find(144);
           e.fields(t)[1] = std::to_string(e.find(142));
           return std::vector<std::string>{
               ent(t, 144), "is an entity of type 142, expected a surface (128/108/120/122/190/192/194/196/198)"};
         }),
    edit("too few parameters",
         [](IgesEdit& e) {
           int s = e.find(128);
           auto& f = e.fields(s);
           f.resize(f.size() - 4);
           return std::vector<std::string>{ent(s, 128), "bad parameter count"};
         }),
    edit("extra parameters",
         [](IgesEdit& e) {
           int s = e.find(128);
           auto& f = e.fields(s);
           f.insert(f.end(), {"1.", "2.", "3."});
           return std::vector<std::string>{ent(s, 128), "bad parameter count"};
         }),
    edit("NaN coordinate",
         [](IgesEdit& e) {
           int s = e.find(128);
           auto& f = e.fields(s);
           f[surface_point_index(f)] = "nan";
           return std::vector<std::string>{ent(s, 128), "'nan' is not a finite number"};
         }),
    edit("infinite coordinate",
         [](IgesEdit& e) {
           int s = e.find(128);
           auto& f = e.fields(s);
           f[surface_point_index(f) + 4] = "1.E999";
           return std::vector<std::string>{ent(s, 128), "'1.E999' is not a finite number"};
         }),
    edit("zero surface weight",
         [](IgesEdit& e) {
           int s = e.find(128);
           auto& f = e.fields(s);
           f[10 + 6 + 6] = "0.";
           return std::vector<std::string>{ent(s, 128), "parameter 22: weight 0 is 0, weights must be > 0"};
         }),
    edit("negative curve weight",
         [](IgesEdit& e) {
           int c = e.find(126);
           auto& f = e.fields(c);
           f[7 + 4 + 1] = "-1.";
           return std::vector<std::string>{ent(c, 126), "weight 1 is -1, weights must be > 0"};
         }),
    edit("decreasing surface knots",
         [](IgesEdit& e) {
           int s = e.find(128);
           auto& f = e.fields(s);
           f[13] = "0.5";
           f[14] = "0.25";
           return std::vector<std::string>{ent(s, 128), "u knot 4 (0.25) is less than knot 3 (0.5)"};
         }),
    edit("decreasing curve knots",
         [](IgesEdit& e) {
           int c = e.find(126);
           auto& f = e.fields(c);
           f[7] = "0.5";
           return std::vector<std::string>{ent(c, 126), "knot 1 (0) is less than knot 0 (0.5)"};
         }),
    edit("wrong knot count (K1 + 1)",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.fields(s)[1] = "3";
           return std::vector<std::string>{ent(s, 128), "bad parameter count"};
         }),
    edit("wrong knot count (K - 1)",
         [](IgesEdit& e) {
           int c = e.find(126, 4);
           e.fields(c)[1] = "7";
           return std::vector<std::string>{ent(c, 126)};
         }),
    edit("degree zero",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.fields(s)[3] = "0";
           return std::vector<std::string>{ent(s, 128), "degree M1 is 0"};
         }),
    edit("knot multiplicity above degree + 1",
         [](IgesEdit& e) {
           int s = e.find(128, 1);
           auto& f = e.fields(s);
           f[14] = "0.";
           return std::vector<std::string>{ent(s, 128), "u knot 0 is repeated 5 times, more than degree + 1 = 4"};
         }),
    edit("word in a real field",
         [](IgesEdit& e) {
           int s = e.find(128);
           auto& f = e.fields(s);
           f[surface_point_index(f) + 1] = "abc";
           return std::vector<std::string>{ent(s, 128), "expected a real number, got 'abc'"};
         }),
    edit("fraction in an integer field",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.fields(s)[2] = "2.5";
           return std::vector<std::string>{ent(s, 128), "parameter 2: expected an integer, got '2.5'"};
         }),
    edit("record starts with another type",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.fields(s)[0] = "126";
           return std::vector<std::string>{ent(s, 128),
                                           "parameter record starts with '126', expected the entity type 128"};
         }),
    edit("bad outer boundary flag",
         [](IgesEdit& e) {
           int t = e.find(144);
           e.fields(t)[2] = "2";
           return std::vector<std::string>{ent(t, 144), "outer boundary flag N1 is 2, must be in [0, 1]"};
         }),
    edit("composite of a surface",
         [](IgesEdit& e) {
           int c = e.find(102);
           e.fields(c)[2] = std::to_string(e.find(128));
           return std::vector<std::string>{ent(c, 102), "is an entity of type 128, expected a curve"};
         }),
    edit("composite containing itself",
         [](IgesEdit& e) {
           int c = e.find(102);
           e.fields(c)[2] = std::to_string(c);
           return std::vector<std::string>{ent(c, 102), "nested more than 64 deep"};
         }),
    edit("empty composite",
         [](IgesEdit& e) {
           int c = e.find(102);
           e.fields(c)[1] = "0";
           return std::vector<std::string>{ent(c, 102), "number of curves N is 0"};
         }),
    edit("transform pointer to a curve",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.set_de_field(s, 7, e.find(126));
           return std::vector<std::string>{ent(s, 128), "is an entity of type 126, expected 124"};
         }),
    edit("singular transform",
         [](IgesEdit& e) {
           int m = e.append(124, {"1.", "0.", "0.", "0.", "0.", "0.", "0.", "0.", "0.", "0.", "1.", "0."});
           e.set_de_field(e.find(128), 7, m);
           return std::vector<std::string>{ent(m, 124), "singular transformation matrix"};
         }),
    edit("transform cycle",
         [](IgesEdit& e) {
           int m = e.append(124, {"1.", "0.", "0.", "0.", "0.", "1.", "0.", "0.", "0.", "0.", "1.", "0."});
           e.set_de_field(m, 7, m);
           e.set_de_field(e.find(128), 7, m);
           return std::vector<std::string>{ent(m, 124), "chained transformation matrices (cycle?)"};
         }),
    edit("empty curve range",
         [](IgesEdit& e) {
           int c = e.find(126);
           auto& f = e.fields(c);
           f[f.size() - 4] = f[f.size() - 5];
           return std::vector<std::string>{ent(c, 126), "is not less than V(1)"};
         }),
    edit("empty knot domain",
         [](IgesEdit& e) {
           int s = e.find(128, 1);
           auto& f = e.fields(s);
           for (int i = 20; i < 24; ++i) f[static_cast<size_t>(i)] = "0.5"; /* 0 0 .5 .5 .5 .5 1 1 */
           return std::vector<std::string>{ent(s, 128), "v knot vector has an empty domain"};
         }),
    edit("Hollerith past the end",
         [](IgesEdit& e) {
           int t = e.find(144);
           e.fields(t)[4] = "99Habc";
           return std::vector<std::string>{ent(t, 144), "Hollerith string of 99 characters runs past the end"};
         }),
    edit("parameter line of another entity",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.at(s).pstart_override = 1;
           return std::vector<std::string>{"belongs to D1, but " + ent(s, 128) + " claims it"};
         }),
    edit("parameter lines outside the section",
         [](IgesEdit& e) {
           int s = e.find(128);
           e.at(s).pstart_override = 9999;
           return std::vector<std::string>{ent(s, 128), "outside the parameter section"};
         }),
    edit("zero-radius arc",
         [](IgesEdit& e) {
           int a = e.append(100, {"0.", "0.5", "0.5", "0.5", "0.5", "0.5", "0.5"});
           e.fields(e.find(102))[2] = std::to_string(a);
           return std::vector<std::string>{ent(a, 100), "zero radius"};
         }),
    edit("zero-length line",
         [](IgesEdit& e) {
           int a = e.append(110, {"0.", "0.", "0.", "0.", "0.", "0."});
           e.fields(e.find(102))[2] = std::to_string(a);
           return std::vector<std::string>{ent(a, 110), "line has zero length"};
         }),
};

}  // namespace

TEST_CASE("malformed IGES corpus: each file gives its specific error") {
  const std::string base = nurbs::io::write_iges_text(nurbs::io::test::small_model(), "bad.igs");
  REQUIRE_NOTHROW(nurbs::io::read_iges_text(base, "bad.igs"));
  // The edit helper itself must reproduce a readable file when nothing is changed.
  REQUIRE_NOTHROW(nurbs::io::read_iges_text(IgesEdit::parse(base).text(), "bad.igs"));
  static_assert(std::size(kCases) >= 30, "the corpus covers at least 30 kinds of damage");
  std::set<std::string> messages;
  for (const Case& c : kCases) {
    CAPTURE(std::string(c.name));
    const Mutation m = c.mutate(base);
    // A case proves something only if it damaged the file and names the specific problem.
    REQUIRE(m.text != base);
    REQUIRE_FALSE(m.expect.empty());
    std::string message;
    try {
      nurbs::io::read_iges_text(m.text, "bad.igs");
    } catch (const nurbs::io::ReadError& e) {
      message = e.what();
    }
    CAPTURE(message);
    REQUIRE_FALSE(message.empty());
    CHECK(message.rfind("bad.igs: ", 0) == 0);
    for (const std::string& s : m.expect) CHECK_MESSAGE(message.find(s) != std::string::npos, "missing '" << s << "'");
    CHECK_MESSAGE(messages.insert(message).second, "another case gave the same message");  // each its own error
  }
}

TEST_CASE("malformed IGES: a face whose trim curve has no parameter-space curve is dropped, named") {
  nurbs::io::test::IgesEdit e = nurbs::io::test::IgesEdit::parse(
      nurbs::io::write_iges_text(nurbs::io::test::small_model(), "bad.igs"));
  const int c = e.find(142);
  e.fields(c)[3] = "0";
  const nurbs::Model m = nurbs::io::read_iges_text(e.text(), "bad.igs");
  REQUIRE(m.dropped_faces.size() == 1);
  CHECK(m.dropped_faces[0].entity == "D" + std::to_string(e.find(144)));
  CHECK(m.dropped_faces[0].reason.find("trim curve D" + std::to_string(c)) != std::string::npos);
  CHECK(m.dropped_faces[0].reason.find("no parameter-space curve") != std::string::npos);
}

// IGES Global section as real writers produce it (iges_global.cpp): Rhino writes Hollerith counts
// longer than their strings, which OpenCASCADE reads up to the next delimiter; the reader does the
// same with a warning naming the line of the count, and every field after it keeps its place.
namespace global_section {

// A valid small file whose Global section is `global`, cut into 72-column records.
std::string with_global(const std::string& global) {
  IgesEdit e = IgesEdit::parse(nurbs::io::write_iges_text(nurbs::io::test::small_model()));
  e.global.clear();
  for (size_t i = 0; i < global.size(); i += 72) e.global.push_back(global.substr(i, 72));
  return e.text();
}

// Rhino 5's Global section: G3 says 38 characters where its string has 32 (the file name), G14 = 2
// (millimetres) comes after it.
const std::string kRhino = R"(1H,,1H;,38HC:\Users\PP\Desktop\testfile.igs,32HC:\Users\PP\Desktop\testfile.igs,)"
                           R"(7HRhino 5,7HRhino 5,32,38,6,308,15,7HRhino 5,1.0,2,2HMM,1,0.0254,15H20160720.120000,)"
                           R"(0.001,1000.0,5HPPPPP,8HPP Corp.,11,0,15H20160720.120000;)";

// The message of the ReadError that reading `global` in a small file throws ("" if none).
std::string global_error(const std::string& global) {
  try {
    (void)nurbs::io::read_iges_text(with_global(global), "global.igs");
  } catch (const nurbs::io::ReadError& e) {
    return e.what();
  }
  return "";
}

}  // namespace global_section

TEST_CASE("IGES Global section: a Hollerith count past its string is read up to the delimiter") {
  const std::string text = global_section::with_global(global_section::kRhino);
  nurbs::io::IgesReadLog log;
  const nurbs::Model m = nurbs::io::read_iges_text(text, "rhino.igs", {}, &log);
  // The start section has one record: the Global section begins on line 2.
  REQUIRE(m.read_warnings.size() == 1);
  CHECK(m.read_warnings[0] ==
        "line 2: global parameter 3: Hollerith count 38 runs past its string; read up to the delimiter");
  CHECK(log.global.sender_id == R"(C:\Users\PP\Desktop\testfile.igs)");
  CHECK(log.global.file_name == R"(C:\Users\PP\Desktop\testfile.igs)");
  CHECK(log.global.system_id == "Rhino 5");
  // The fields after the repaired one keep their numbers: millimetres, IGES 5.3.
  CHECK(m.unit_scale_to_mm == 1.0);
  CHECK(log.global.unit_name == "MM");
  CHECK(log.global.resolution == 0.001);
  CHECK(log.global.version == 11);
}

TEST_CASE("IGES Global section: messages name the line that holds the problem") {
  // G14 = 99 lies on the second Global record (line 3), after a string that spans records 1 and 2.
  std::string g = global_section::kRhino;
  g.replace(g.find("38HC"), 2, "32");
  g.replace(g.find(",2,2HMM"), 3, ",99,");
  REQUIRE(g.find(",99,") / 72 == 1);
  REQUIRE(g.find("32HC") / 72 == 0);
  const std::string units = global_section::global_error(g);
  CHECK(units.find("line 3: global section") != std::string::npos);
  CHECK(units.find("unknown unit flag 99") != std::string::npos);
  // A count that runs past the end of the section (record 3): the line of the count (record 2).
  g = global_section::kRhino.substr(0, global_section::kRhino.find(",7HRhino 5,32")) + ",400HRhino" +
      std::string(100, 'x');
  g.replace(g.find("38HC"), 2, "32");
  REQUIRE(g.find("400H") / 72 == 1);
  REQUIRE(g.size() / 72 == 2);
  const std::string past = global_section::global_error(g);
  CHECK(past.find("line 3: global section") != std::string::npos);
  CHECK(past.find("Hollerith string of 400 characters") != std::string::npos);
}
