// Splits text into numbered lines of whitespace-separated words and turns words into
// checked numbers. The camera-path and viewer-script parsers read lines; the NFF parser
// reads a token stream (token_reader.h) with the same checks, so all report bad input the
// same way.
#pragma once
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "scene/input_error.h"

namespace epsray {

// A word as it appears in a message: quoted, control bytes escaped and cut to a few dozen
// characters, so a 10 MB "number" gives a one-line error of sane length.
std::string quote_word(std::string_view w);
// Plain decimal digits, signs, dots and exponents: what NFF numbers are made of (strtod
// also takes hex floats, "inf" and "nan").
bool looks_decimal(std::string_view w);
// A finite float from a word, or input_error at file:line naming `what` the number is for.
float parse_number(std::string_view w, const char* what, const std::string& file, int line);
// An integer in [lo, hi], or input_error at file:line.
long parse_integer(std::string_view w, const char* what, long lo, long hi, const std::string& file, int line);
// The byte at which printable text must stop: tab, CR and LF pass; anything else outside
// printable ASCII is bad input (whitted.md 3).
inline bool is_text_byte(unsigned char c) { return c == '\t' || c == '\r' || c == '\n' || (c >= 32 && c < 127); }
std::string bad_byte_message(unsigned char c);

struct text_line {
  int number = 0;                       // 1-based line number in the file
  std::vector<std::string_view> words;  // comment stripped
};

class line_reader {
 public:
  // Rejects bytes outside printable ASCII, tab, CR and LF before any `#` comment.
  line_reader(std::string_view text, std::string name);

  // Next line holding at least one word; false at the end of the text.
  bool next(text_line& out);
  int last_line() const { return last_line_; }
  const std::string& name() const { return name_; }

  [[noreturn]] void fail(int line, const std::string& what) const;
  // A finite number; the message names `what` the number is for.
  float number(const text_line& l, size_t i, const char* what) const {
    return parse_number(l.words.at(i), what, name_, l.number);
  }
  // An integer in [lo, hi].
  long integer(const text_line& l, size_t i, const char* what, long lo, long hi) const {
    return parse_integer(l.words.at(i), what, lo, hi, name_, l.number);
  }
  // Fails unless the line has exactly `n` numbers after its keyword.
  void expect_count(const text_line& l, size_t n, const char* what) const;

 private:
  std::string_view text_;
  std::string name_;
  size_t pos_ = 0;
  int line_ = 0;
  int last_line_ = 0;
};

// Input files are read whole, and only regular files up to this size: a device, a FIFO
// or a sparse file of gigabytes is refused before any byte is read.
constexpr std::size_t max_input_bytes = std::size_t(2) << 30;  // 2 GiB
// Reads a whole regular file of at most `limit` bytes; throws input_error (line 0) when it
// is not one or cannot be read. Never blocks on a FIFO.
std::string read_input_file(const std::string& path, std::size_t limit = max_input_bytes);
// read_input_file for the text formats (scene, path, script).
inline std::string read_text_file(const std::string& path) { return read_input_file(path); }

}  // namespace epsray
