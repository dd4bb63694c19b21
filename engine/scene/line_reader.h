// Splits text into numbered lines of whitespace-separated words and turns words into
// checked numbers. Shared by the scene and camera-path parsers so both report bad input
// the same way.
#pragma once
#include <string>
#include <string_view>
#include <vector>

#include "scene/input_error.h"

namespace epsray {

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
  float number(const text_line& l, size_t i, const char* what) const;
  // An integer in [lo, hi].
  long integer(const text_line& l, size_t i, const char* what, long lo, long hi) const;
  // Fails unless the line has exactly `n` numbers after its keyword.
  void expect_count(const text_line& l, size_t n, const char* what) const;

 private:
  std::string_view text_;
  std::string name_;
  size_t pos_ = 0;
  int line_ = 0;
  int last_line_ = 0;
};

// Reads a whole file; throws input_error (line 0) when it cannot be read.
std::string read_text_file(const std::string& path);

}  // namespace epsray
