// NFF as a token stream (whitted.md 2): an entity is its keyword and then its numbers,
// however they are spread over lines. Each token keeps its line so errors still name it.
#pragma once
#include <string>
#include <string_view>

namespace epsray {

struct token {
  std::string_view text;  // empty at the end of the file
  int line = 0;           // 1-based
  bool end() const { return text.empty(); }
};

class token_reader {
 public:
  // Words are separated by blanks, tabs and line ends (LF, CRLF or a lone CR); `#` starts
  // a comment to the end of its line. Outside comments, bytes other than printable ASCII,
  // tab, CR and LF are bad input at their line.
  token_reader(std::string_view text, std::string name);

  // The next token without taking it; end() at the end of the file.
  const token& peek() const { return ahead_; }
  token next();
  // The line of the last token taken (0 before any).
  int last_line() const { return last_line_; }
  const std::string& name() const { return name_; }
  [[noreturn]] void fail(int line, const std::string& what) const;

 private:
  void scan();
  std::string_view text_;
  std::string name_;
  size_t pos_ = 0;
  int line_ = 1;
  int last_line_ = 0;
  token ahead_;
};

}  // namespace epsray
