// ISO 10303-21 exchange structure: a single-pass scanner over the text (tokens of §6 of the
// standard) that builds the DATA section's instances as value trees.
#include "nurbs/io/step_file.h"

#include <fmt/format.h>

#include <cctype>
#include <charconv>
#include <cstdlib>

#include "nurbs/io/read_error.h"

namespace nurbs::io {
namespace {

// Bytes of a file quoted in a message: at most `max` of them, escaped as ReadError escapes.
std::string quoted(std::string_view s, size_t max = 40) {
  return printable(s.substr(0, max)) + (s.size() > max ? "..." : "");
}

class Scanner {
 public:
  Scanner(const std::string& text, const std::string& name) : s_(text), name_(name) {}

  [[noreturn]] void fail(const std::string& problem) const {
    throw ReadError(name_, fmt::format("line {}", line_), problem);
  }

  // Skips white space and comments; false at the end of the text.
  bool skip() {
    while (pos_ < s_.size()) {
      const char c = s_[pos_];
      if (c == '\n') {
        ++line_;
        ++pos_;
      } else if (c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v') {
        ++pos_;
      } else if (c == '/' && pos_ + 1 < s_.size() && s_[pos_ + 1] == '*') {
        const int start = line_;
        const size_t end = s_.find("*/", pos_ + 2);
        if (end == std::string::npos) {
          line_ = start;
          fail("comment /* is not closed");
        }
        for (size_t i = pos_; i < end; ++i) line_ += s_[i] == '\n';
        pos_ = end + 2;
      } else {
        return true;
      }
    }
    return false;
  }

  char peek() {
    if (!skip()) fail("unexpected end of file");
    return s_[pos_];
  }

  void expect(char c) {
    const char got = peek();
    if (got != c) fail(fmt::format("expected '{}', found '{}'", c, quoted(std::string_view(&s_[pos_], 1))));
    ++pos_;
  }

  bool accept(char c) {
    if (skip() && s_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }

  // A keyword: [!]letter (letter | digit | _ | -)*, returned upper case.
  std::string keyword() {
    peek();
    size_t b = pos_;
    if (s_[pos_] == '!') ++pos_;
    if (pos_ >= s_.size() || !std::isalpha(static_cast<unsigned char>(s_[pos_])))
      fail(fmt::format("expected a keyword, found '{}'", quoted(std::string_view(s_).substr(b, 20))));
    while (pos_ < s_.size() &&
           (std::isalnum(static_cast<unsigned char>(s_[pos_])) || s_[pos_] == '_' || s_[pos_] == '-'))
      ++pos_;
    std::string k = s_.substr(b, pos_ - b);
    for (char& c : k) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    return k;
  }

  // A lexical problem inside an instance's parameters: kept as the instance's damage while one is
  // being read (the token is already consumed, the caller reads it as $), else the file fails.
  void damaged(const std::string& problem) {
    if (!damage_) fail(problem);
    if (damage_->empty()) *damage_ = problem;
  }

  // Lexical damage of the parameters read next goes to `damage` (null: it fails the file).
  void keep_damage(std::string* damage) { damage_ = damage; }

  // #digits; 0 for a damaged reference (see damaged) when `in_parameters`.
  long instance_name(bool in_parameters = false) {
    expect('#');
    const size_t b = pos_;
    while (pos_ < s_.size() && std::isdigit(static_cast<unsigned char>(s_[pos_]))) ++pos_;
    long id = 0;
    const auto r = std::from_chars(s_.data() + b, s_.data() + pos_, id);
    if (b == pos_ || r.ec != std::errc() || r.ptr != s_.data() + pos_ || id <= 0) {
      const std::string text = quoted(std::string_view(s_).substr(b, std::max<size_t>(pos_ - b, 1)));
      const std::string problem = r.ec == std::errc::result_out_of_range
                                      ? fmt::format("reference #{} out of range", text)
                                      : fmt::format("bad instance name '#{}'", text);
      if (!in_parameters) fail(problem);
      damaged(problem);
      return 0;
    }
    return id;
  }

  StepValue value(int depth) {
    if (depth > kMaxStepNesting) fail(fmt::format("lists nested deeper than {}", kMaxStepNesting));
    const char c = peek();
    StepValue v;
    if (c == '$') {
      ++pos_;
      v.kind = StepValue::Kind::Null;
    } else if (c == '*') {
      ++pos_;
      v.kind = StepValue::Kind::Derived;
    } else if (c == '#') {
      v.ref = instance_name(true);
      v.kind = v.ref > 0 ? StepValue::Kind::Ref : StepValue::Kind::Null;
    } else if (c == '\'') {
      v.kind = StepValue::Kind::String;
      v.text = string();
    } else if (c == '"') {
      ++pos_;
      const size_t e = s_.find('"', pos_);
      if (e == std::string::npos) fail("binary value \" is not closed");
      v.kind = StepValue::Kind::Binary;
      v.text = s_.substr(pos_, e - pos_);
      pos_ = e + 1;
    } else if (c == '.') {
      ++pos_;
      const size_t e = s_.find('.', pos_);
      if (e == std::string::npos || e - pos_ > 64) fail("enumeration value .X. is not closed");
      v.kind = StepValue::Kind::Enum;
      v.text = s_.substr(pos_, e - pos_);
      for (char& ch : v.text) ch = static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
      pos_ = e + 1;
    } else if (c == '(') {
      v.kind = StepValue::Kind::List;
      v.items = list(depth + 1);
    } else if (c == '+' || c == '-' || std::isdigit(static_cast<unsigned char>(c))) {
      number(v);
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '!') {
      v.kind = StepValue::Kind::Typed;
      v.text = keyword();
      expect('(');
      v.items.push_back(value(depth + 1));
      expect(')');
    } else {
      fail(fmt::format("unexpected '{}' in a parameter list", quoted(std::string_view(&s_[pos_], 1))));
    }
    return v;
  }

  // ( value, value, ... ) after its '(' was seen by peek.
  std::vector<StepValue> list(int depth) {
    expect('(');
    std::vector<StepValue> out;
    if (accept(')')) return out;
    do out.push_back(value(depth));
    while (accept(','));
    expect(')');
    return out;
  }

  std::string string() {
    expect('\'');
    const int start = line_;
    std::string out;
    while (true) {
      if (pos_ >= s_.size()) {
        line_ = start;
        fail("string ' is not closed");
      }
      const char c = s_[pos_++];
      if (c == '\n') ++line_;
      if (c == '\'') {
        if (pos_ < s_.size() && s_[pos_] == '\'') {
          out += '\'';
          ++pos_;
          continue;
        }
        return out;
      }
      out += c;
    }
  }

  void number(StepValue& v) {
    const size_t b = pos_;
    if (s_[pos_] == '+' || s_[pos_] == '-') ++pos_;
    bool real = false;
    while (pos_ < s_.size()) {
      const char c = s_[pos_];
      if (std::isdigit(static_cast<unsigned char>(c))) {
        ++pos_;
      } else if (c == '.' || c == 'E' || c == 'e') {
        real = true;
        ++pos_;
        if ((c == 'E' || c == 'e') && pos_ < s_.size() && (s_[pos_] == '+' || s_[pos_] == '-')) ++pos_;
      } else {
        break;
      }
    }
    // from_chars reads "1." and "1.E5" too, but not a leading '+'.
    const char* first = s_.data() + b + (s_[b] == '+' ? 1 : 0);
    double x = 0.0;
    const auto r = std::from_chars(first, s_.data() + pos_, x);
    if (pos_ == b || r.ec != std::errc() || r.ptr != s_.data() + pos_) {
      damaged(fmt::format("bad number '{}'", quoted(std::string_view(s_).substr(b, pos_ - b))));
      v.kind = StepValue::Kind::Null;
      return;
    }
    v.kind = real ? StepValue::Kind::Real : StepValue::Kind::Integer;
    v.number = x;
  }

  size_t pos() const { return pos_; }
  int line() const { return line_; }
  bool at_end() { return !skip(); }

 private:
  const std::string& s_;
  const std::string& name_;
  std::string* damage_ = nullptr;
  size_t pos_ = 0;
  int line_ = 1;
};

void parse_header(Scanner& sc, StepFile& f) {
  // HEADER; FILE_DESCRIPTION(...); FILE_NAME(...); FILE_SCHEMA((...)); [more] ENDSEC;
  while (true) {
    const std::string k = sc.keyword();
    if (k == "ENDSEC") {
      sc.expect(';');
      return;
    }
    const std::vector<StepValue> params = sc.list(1);
    sc.expect(';');
    if (k == "FILE_SCHEMA" && !params.empty())
      for (const StepValue& s : params.front().items)
        if (s.kind == StepValue::Kind::String) f.schemas.push_back(s.text);
  }
}

void parse_data(Scanner& sc, StepFile& f) {
  while (true) {
    if (sc.peek() != '#') {
      const std::string k = sc.keyword();
      if (k != "ENDSEC") sc.fail(fmt::format("expected an instance #N = ... or ENDSEC, found {}", quoted(k)));
      sc.expect(';');
      return;
    }
    StepEntity e;
    e.line = sc.line();
    e.id = sc.instance_name();
    sc.expect('=');
    sc.keep_damage(&e.damage);
    if (sc.peek() == '(') {  // complex instance: (A(...) B(...) ...)
      sc.expect('(');
      while (!sc.accept(')')) {
        StepRecord r;
        r.type = sc.keyword();
        r.params = sc.list(1);
        e.records.push_back(std::move(r));
      }
      if (e.records.empty()) sc.fail(fmt::format("instance #{} is an empty complex instance", e.id));
    } else {
      StepRecord r;
      r.type = sc.keyword();
      r.params = sc.list(1);
      e.records.push_back(std::move(r));
    }
    sc.keep_damage(nullptr);
    sc.expect(';');
    const long id = e.id;
    const int line = e.line;
    if (!f.entities.emplace(id, std::move(e)).second)
      throw ReadError(f.name, fmt::format("line {}", line), fmt::format("instance #{} is defined twice", id));
    f.order.push_back(id);
  }
}

}  // namespace

const StepRecord* StepEntity::record(const std::string& type) const {
  for (const StepRecord& r : records)
    if (r.type == type) return &r;
  return nullptr;
}

std::string StepEntity::type_name() const {
  if (records.size() == 1) return records.front().type;
  std::string out = "(";
  for (size_t i = 0; i < records.size(); ++i) out += (i ? " " : "") + records[i].type;
  return out + ")";
}

bool looks_like_step(const std::string& text) {
  size_t i = 0;
  while (i < text.size() && std::isspace(static_cast<unsigned char>(text[i]))) ++i;
  return text.compare(i, 13, "ISO-10303-21;") == 0;
}

StepFile parse_step_file(const std::string& text, const std::string& name) {
  StepFile f;
  f.name = name;
  f.bytes = text.size();
  f.entities.reserve(text.size() / 48);  // CAD files hold an instance per 40-60 bytes
  Scanner sc(text, name);
  if (!looks_like_step(text)) throw ReadError(name, "line 1", "not a STEP file (it does not start with ISO-10303-21;)");
  sc.keyword();  // ISO-10303-21
  sc.expect(';');
  bool data = false;
  while (true) {
    if (sc.at_end()) sc.fail("END-ISO-10303-21; is missing");
    const std::string k = sc.keyword();
    if (k == "END-ISO-10303-21") {
      sc.expect(';');
      break;
    }
    if (k == "HEADER") {
      sc.expect(';');
      parse_header(sc, f);
    } else if (k == "DATA") {
      if (sc.accept('(')) {  // DATA('name', ('schema')); of the second edition
        sc.fail("DATA sections with parameters (several data sections) are not supported");
      }
      sc.expect(';');
      parse_data(sc, f);
      data = true;
    } else {
      sc.fail(fmt::format("unexpected section {}", quoted(k)));
    }
  }
  if (!data) throw ReadError(name, "", "no DATA section");
  return f;
}

}  // namespace nurbs::io
