#include "scene/token_reader.h"

#include "scene/input_error.h"
#include "scene/line_reader.h"

namespace epsray {

token_reader::token_reader(std::string_view text, std::string name) : text_(text), name_(std::move(name)) { scan(); }

void token_reader::fail(int line, const std::string& what) const { throw input_error(name_, line, what); }

token token_reader::next() {
  token t = ahead_;
  if (!t.end()) {
    last_line_ = t.line;
    scan();
  }
  return t;
}

void token_reader::scan() {
  const size_t n = text_.size();
  auto line_end = [&](size_t i) {  // consumes one line end at i: LF, CR or CRLF
    if (text_[i] == '\r' && i + 1 < n && text_[i + 1] == '\n') ++i;
    ++line_;
    return i + 1;
  };
  while (pos_ < n) {
    unsigned char c = static_cast<unsigned char>(text_[pos_]);
    if (c == '\n' || c == '\r') {
      pos_ = line_end(pos_);
    } else if (c == ' ' || c == '\t') {
      ++pos_;
    } else if (c == '#') {
      while (pos_ < n && text_[pos_] != '\n' && text_[pos_] != '\r') ++pos_;
    } else if (!is_text_byte(c)) {
      fail(line_, bad_byte_message(c));
    } else {
      size_t j = pos_;
      while (j < n) {
        unsigned char d = static_cast<unsigned char>(text_[j]);
        if (d == ' ' || d == '\t' || d == '\n' || d == '\r' || d == '#') break;
        if (!is_text_byte(d)) fail(line_, bad_byte_message(d));
        ++j;
      }
      ahead_ = {text_.substr(pos_, j - pos_), line_};
      pos_ = j;
      return;
    }
  }
  ahead_ = {std::string_view(), line_};
}

}  // namespace epsray
