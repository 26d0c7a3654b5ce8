// Chapter 05: OBJ text checked line by line before tinyobjloader reads it. See obj_checks.h.
//
// tinyobjloader, like most small OBJ readers, trusts its input. Given the wrong text it does
// not fail, it guesses: "1.5abc" reads as 1.5 and "abc" as 0; the face corner "1x" reads as 1,
// "4294967298" wraps around to 2, and in "f 1/ 2/ 3/" each texture index is taken from the
// next corner; a face with two corners is dropped with a warning; an index past the last
// vertex is only a warning, after which its triangulation reads outside its arrays. Its
// warnings carry no line number we could pass on. So every statement the mesh depends on is
// checked here first, with its line number, by rules under which tinyobjloader reads it right.
#include "obj_checks.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string_view>
#include <system_error>

#include "rt/error.h"
#include "supported_range.h"

namespace rt::ch05 {

namespace {

[[noreturn]] void fail(const std::string& name, long long line, const std::string& what) {
  throw InputError(name + ":" + std::to_string(line) + ": " + what);
}

// A piece of the file shown in an error: control and non-ASCII bytes written as \xNN, and
// cut after 40 characters, so that a hostile file cannot make the message long or multi-line.
std::string shown(std::string_view token) {
  constexpr std::size_t k_shown = 40;
  std::string out;
  std::size_t i = 0;
  for (; i < token.size() && out.size() < k_shown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      std::array<char, 8> hex{};
      std::snprintf(hex.data(), hex.size(), "\\x%02X", c);
      out += hex.data();
    }
  }
  return "'" + out + (i < token.size() ? "...'" : "'");
}

std::string count_of(long long n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

// A limit from LoadLimits, lowered where needed to what an int index can address (tinyobjloader
// and ch04::Mesh index with int).
struct Cap {
  long long value;
  const char* reason;
};

Cap cap_of(long long limit, const char* reason) {
  constexpr long long k_int_max = std::numeric_limits<int>::max();
  if (limit > k_int_max) return {k_int_max, "the most an int index can address"};
  return {std::max(limit, 0LL), reason};
}

// Splits text into lines as tinyobjloader does: a line ends at "\n", "\r\n" or a lone "\r".
// The line numbers in our messages are then the ones tinyobjloader and text editors count.
class Lines {
public:
  explicit Lines(std::string_view text) : text_(text) {}

  // The next line, without its ending; false after the last one.
  bool next(std::string_view& line) {
    if (position_ >= text_.size()) return false;
    const std::size_t found = text_.find_first_of("\r\n", position_);
    const std::size_t end = found == std::string_view::npos ? text_.size() : found;
    line = text_.substr(position_, end - position_);
    position_ = end;
    if (end < text_.size()) {
      position_ = end + 1;
      if (text_[end] == '\r' && position_ < text_.size() && text_[position_] == '\n') {
        ++position_;
      }
    }
    ++number_;
    return true;
  }

  long long number() const { return number_; }

private:
  std::string_view text_;
  std::size_t position_ = 0;
  long long number_ = 0;
};

// tinyobjloader separates words with spaces and tabs only; so do the checks.
bool is_separator(char c) { return c == ' ' || c == '\t'; }

// The first word of a line and the rest. Blank and comment lines have an empty keyword.
struct Statement {
  std::string_view keyword;
  std::string_view arguments;
};

Statement split_statement(std::string_view line) {
  std::size_t start = 0;
  while (start < line.size() && is_separator(line[start])) ++start;
  if (start == line.size() || line[start] == '#') return {};
  std::size_t end = start;
  while (end < line.size() && !is_separator(line[end])) ++end;
  return {line.substr(start, end - start), line.substr(end)};
}

void split_words(std::string_view text, std::vector<std::string_view>& words) {
  words.clear();
  std::size_t i = 0;
  while (i < text.size()) {
    while (i < text.size() && is_separator(text[i])) ++i;
    const std::size_t start = i;
    while (i < text.size() && !is_separator(text[i])) ++i;
    if (i > start) words.push_back(text.substr(start, i - start));
  }
}

enum class Kind {
  blank,     // empty or a comment
  position,  // v
  texcoord,  // vt
  normal,    // vn
  face,      // f
  passed_on, // o, g, usemtl, mtllib: names, passed on to tinyobjloader as they are
  unused,    // valid OBJ that a triangle mesh does not need: blanked out
  unknown    // not OBJ: an error, since it might be a damaged line the mesh needed
};

Kind classify(std::string_view keyword) {
  // Free-form curves and surfaces, lines and points, smoothing groups, display attributes;
  // also tinyobjloader's own extensions `vw` (skin weights) and `t` (subdivision tags).
  static constexpr std::array<std::string_view, 33> k_unused = {
      "vp",     "cstype",     "deg",       "bmat",     "step",     "curv", "curv2",
      "surf",   "parm",       "trim",      "hole",     "scrv",     "sp",   "end",
      "con",    "mg",         "bevel",     "c_interp", "d_interp", "lod",  "usemap",
      "maplib", "shadow_obj", "trace_obj", "ctech",    "stech",    "s",    "l",
      "p",      "call",       "csh",       "vw",       "t"};
  if (keyword.empty()) return Kind::blank;
  if (keyword == "v") return Kind::position;
  if (keyword == "vt") return Kind::texcoord;
  if (keyword == "vn") return Kind::normal;
  if (keyword == "f") return Kind::face;
  if (keyword == "o" || keyword == "g" || keyword == "usemtl" || keyword == "mtllib") {
    return Kind::passed_on;
  }
  if (std::find(k_unused.begin(), k_unused.end(), keyword) != k_unused.end()) {
    return Kind::unused;
  }
  return Kind::unknown;
}

// Plain decimal notation: an optional sign, digits with an optional decimal point (at least
// one digit), then an optional exponent, whose value goes to `exponent` (stopping at 100).
bool is_plain_decimal(std::string_view word, int& exponent) {
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t start = i;
    while (i < word.size() && word[i] >= '0' && word[i] <= '9') ++i;
    return i - start;
  };
  if (i < word.size() && (word[i] == '+' || word[i] == '-')) ++i;
  std::size_t mantissa_digits = digits();
  if (i < word.size() && word[i] == '.') {
    ++i;
    mantissa_digits += digits();
  }
  if (mantissa_digits == 0) return false;
  exponent = 0;
  if (i < word.size() && (word[i] == 'e' || word[i] == 'E')) {
    ++i;
    if (i < word.size() && (word[i] == '+' || word[i] == '-')) ++i;
    const std::size_t start = i;
    if (digits() == 0) return false;
    for (std::size_t k = start; k < i && exponent < 100; ++k) {
      exponent = exponent * 10 + (word[k] - '0');
    }
  }
  return i == word.size();
}

// One number of a `v`, `vt` or `vn` line: an error unless tinyobjloader will read it right.
// Its number reader stops at the first character it does not expect and reads garbage as 0,
// its exponent arithmetic overflows on "0e9999999999", and its digit counter on a number of
// two billion digits. So a number must be plain decimal notation, at most 1000 characters
// long, with an exponent of at most 99 (a float spans about 1e-45 to 3.4e38, so no float is
// lost), and stay finite when rounded to float. Within these rules both readers agree.
// Returns the number.
double check_number(std::string_view word, const char* what, const std::string& name,
                    long long line) {
  const std::string subject = std::string(what) + " " + shown(word);
  int exponent = 0;
  if (!is_plain_decimal(word, exponent)) {
    std::string lower(word.substr(word[0] == '+' || word[0] == '-' ? 1 : 0));
    for (char& c : lower) c = static_cast<char>(c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c);
    if (lower == "nan" || lower == "inf" || lower == "infinity") {
      fail(name, line, subject + " is not a finite number");
    }
    fail(name, line, subject + " is not a number");
  }
  if (word.size() > 1000) fail(name, line, subject + " is too long (over 1000 characters)");
  if (exponent > 99) {
    fail(name, line,
         subject + " has an exponent beyond 99 (a float spans about 1e-45 to 3.4e38)");
  }
  // std::from_chars reads a leading '-' but not a '+'.
  const std::string_view unsigned_part = word[0] == '+' ? word.substr(1) : word;
  double value = 0;
  const auto [end, error] =
      std::from_chars(unsigned_part.data(), unsigned_part.data() + unsigned_part.size(), value);
  if (error != std::errc() || end != unsigned_part.data() + unsigned_part.size()) {
    fail(name, line, subject + " is out of range");
  }
  if (!ch04::is_finite(static_cast<float>(value))) {
    fail(name, line, subject + " is too large for a float (largest 3.4e38)");
  }
  return value;
}

// A position's x, y and z must lie in the range the float pipeline supports (chapter 03's
// supported_range.h): beyond it the triangle tests' products overflow and the model would
// vanish or come out black. (A fourth to sixth number, w or a colour, is not a coordinate.)
void check_coordinate(double value, std::string_view word, const std::string& name,
                      long long line) {
  if (std::abs(value) <= ch03::k_max_coordinate) return;
  char range[32];
  std::snprintf(range, sizeof range, "%g", ch03::k_max_coordinate);
  fail(name, line,
       "coordinate " + shown(word) +
           " is outside the supported range: coordinates lie within "
           "+-" +
           range);
}

// What an index refers to, for checks and messages.
struct IndexedKind {
  const char* index_name; // "face index"
  const char* singular;   // "vertex"
  const char* plural;     // "vertices"
  long long total = 0;    // in the whole file: a positive index may point forward
  long long before = 0;   // above the current line: a negative index counts back from here
};

// [listing:check_index]
// One index of a face corner; an error unless it names an existing element. OBJ counts from
// 1; a negative index counts back from the last element defined above the line (-1 is the
// latest). tinyobjloader turns both into 0-based indices itself.
void check_index(std::string_view word, const IndexedKind& kind, const std::string& name,
                 long long line) {
  long long index = 0;
  const auto [end, error] = std::from_chars(word.data(), word.data() + word.size(), index);
  const bool fits = error == std::errc() && end == word.data() + word.size();
  if (fits && index == 0) {
    fail(name, line, std::string(kind.index_name) + " 0 is invalid: OBJ indices count from 1");
  }
  if (fits && index > 0 && index <= kind.total) return;
  if (fits && index < 0 && -index <= kind.before) return;
  const bool backwards = word[0] == '-';
  fail(name, line,
       std::string(kind.index_name) + " " + std::string(word.substr(0, 24)) +
           (word.size() > 24 ? "..." : "") + " is out of range (" +
           count_of(backwards ? kind.before : kind.total, kind.singular, kind.plural) +
           (backwards ? " before this line)" : ")"));
}
// [/listing:check_index]

bool is_integer(std::string_view word) {
  const std::size_t start = !word.empty() && word[0] == '-' ? 1 : 0;
  if (word.size() == start) return false;
  return std::all_of(word.begin() + static_cast<std::ptrdiff_t>(start), word.end(),
                     [](char c) { return c >= '0' && c <= '9'; });
}

// One corner of a face: "v", "v/vt", "v//vn" or "v/vt/vn", each an integer.
void check_corner(std::string_view word, const IndexedKind& positions,
                  const IndexedKind& texcoords, const IndexedKind& normals,
                  const std::string& name, long long line) {
  constexpr std::size_t none = std::string_view::npos;
  const std::size_t slash1 = word.find('/');
  const std::size_t slash2 = slash1 == none ? none : word.find('/', slash1 + 1);
  const std::string_view v = word.substr(0, slash1);
  const std::string_view vt =
      slash1 == none ? "" : word.substr(slash1 + 1, slash2 - slash1 - 1);
  const std::string_view vn = slash2 == none ? "" : word.substr(slash2 + 1);
  const bool well_formed =
      is_integer(v) && (slash1 == none || is_integer(vt) || (slash2 != none && vt.empty())) &&
      (slash2 == none || is_integer(vn));
  if (!well_formed) {
    if (word == "\\") fail(name, line, "a line continued with '\\' is not supported");
    fail(name, line,
         "face corner " + shown(word) + " is malformed (expected v, v/vt, v//vn or v/vt/vn)");
  }
  check_index(v, positions, name, line);
  if (!vt.empty()) check_index(vt, texcoords, name, line);
  if (slash2 != none) check_index(vn, normals, name, line);
}

} // namespace

// Two passes: the first counts positions, texture coordinates and normals, because a positive
// index may name one defined further down; the second checks each line in turn, so the error
// reported is the first one in the file.
ObjCounts check_obj_lines(std::string& text, const std::string& name, const LoadLimits& limits,
                          const std::function<void(std::size_t)>& read_up_to) {
  // A UTF-8 byte order mark, which some Windows editors put first, would hide the first
  // statement from tinyobjloader (it would read "\xEF\xBB\xBFv" as an unknown keyword).
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.replace(0, 3, "   ");

  ObjCounts counts;
  std::string_view line;
  for (Lines lines(text); lines.next(line);) {
    const Kind kind = classify(split_statement(line).keyword);
    counts.positions += kind == Kind::position;
    counts.texcoords += kind == Kind::texcoord;
    counts.normals += kind == Kind::normal;
  }

  const Cap max_vertices = cap_of(limits.max_vertices, "LoadLimits::max_vertices");
  const Cap max_triangles = cap_of(limits.max_triangles, "LoadLimits::max_triangles");
  const auto count_one = [&](IndexedKind& kind, long long line_number) {
    if (++kind.before > max_vertices.value) {
      fail(name, line_number,
           "more than " + std::to_string(max_vertices.value) + " " + kind.plural + " (" +
               max_vertices.reason + ")");
    }
  };
  IndexedKind positions{"face index", "vertex", "vertices", counts.positions};
  IndexedKind texcoords{"texture coordinate index", "texture coordinate", "texture coordinates",
                        counts.texcoords};
  IndexedKind normals{"normal index", "normal", "normals", counts.normals};
  std::vector<std::string_view> words;
  for (Lines lines(text); lines.next(line);) {
    const long long number = lines.number();
    if (read_up_to && number % 4096 == 0)
      read_up_to(static_cast<std::size_t>(line.data() - text.data()));
    // tinyobjloader reads each line as a C string, which would end at a NUL byte.
    if (line.find('\0') != std::string_view::npos) {
      fail(name, number, "NUL byte: this is a binary file, not OBJ text");
    }
    const Statement statement = split_statement(line);
    split_words(statement.arguments, words);
    const auto count = static_cast<long long>(words.size());
    switch (classify(statement.keyword)) {
    case Kind::blank:
    case Kind::passed_on:
      break;
    case Kind::position:
      if (count < 3 || count > 6) {
        fail(name, number,
             "'v' needs x y z (optionally followed by w, or by r g b); this one has " +
                 count_of(count, "number", "numbers"));
      }
      for (std::size_t k = 0; k < words.size(); ++k) {
        const double value = check_number(words[k], "coordinate", name, number);
        if (k < 3) check_coordinate(value, words[k], name, number);
      }
      count_one(positions, number);
      break;
    case Kind::texcoord:
      if (count < 1 || count > 3) {
        fail(name, number,
             "'vt' needs 1 to 3 numbers (u v w); this one has " + std::to_string(count));
      }
      for (std::string_view word : words) {
        check_number(word, "texture coordinate", name, number);
      }
      count_one(texcoords, number);
      break;
    case Kind::normal:
      if (count != 3) {
        fail(name, number,
             "'vn' needs 3 numbers (x y z); this one has " + std::to_string(count));
      }
      for (std::string_view word : words) check_number(word, "normal component", name, number);
      count_one(normals, number);
      break;
    case Kind::face:
      if (count < 3) {
        fail(name, number,
             "face has " + count_of(count, "corner", "corners") + "; a face needs at least 3");
      }
      for (std::string_view word : words) {
        check_corner(word, positions, texcoords, normals, name, number);
      }
      counts.triangles += count - 2;
      if (counts.triangles > max_triangles.value) {
        fail(name, number,
             "more than " + std::to_string(max_triangles.value) + " triangles (" +
                 max_triangles.reason + ")");
      }
      if (count > 255) counts.large_faces.emplace_back(counts.faces, count);
      ++counts.faces;
      counts.corners += count;
      break;
    case Kind::unused: {
      // Spaces keep every later line on its line number.
      const auto offset = static_cast<std::size_t>(line.data() - text.data());
      std::fill_n(text.begin() + static_cast<std::ptrdiff_t>(offset), line.size(), ' ');
      break;
    }
    case Kind::unknown:
      fail(name, number, "unknown statement " + shown(statement.keyword) + " (not OBJ)");
    }
  }
  return counts;
}

} // namespace rt::ch05
