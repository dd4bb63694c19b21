#include "scene/line_reader.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>

namespace epsray {

line_reader::line_reader(std::string_view text, std::string name)
    : text_(text), name_(std::move(name)) {}

void line_reader::fail(int line, const std::string& what) const { throw input_error(name_, line, what); }

bool line_reader::next(text_line& out) {
  while (pos_ < text_.size()) {
    size_t end = text_.find('\n', pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view raw = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    ++line_;
    size_t hash = raw.find('#');
    std::string_view body = raw.substr(0, hash);
    for (unsigned char c : body) {
      if (c == '\t' || c == '\r' || (c >= 32 && c < 127)) continue;
      char buf[64];
      std::snprintf(buf, sizeof buf, "byte 0x%02x is not printable ASCII", unsigned(c));
      fail(line_, buf);
    }
    out.number = line_;
    out.words.clear();
    size_t i = 0;
    while (i < body.size()) {
      while (i < body.size() && (body[i] == ' ' || body[i] == '\t' || body[i] == '\r')) ++i;
      size_t j = i;
      while (j < body.size() && body[j] != ' ' && body[j] != '\t' && body[j] != '\r') ++j;
      if (j > i) out.words.push_back(body.substr(i, j - i));
      i = j;
    }
    if (!out.words.empty()) {
      last_line_ = line_;
      return true;
    }
  }
  return false;
}

namespace {
bool looks_decimal(std::string_view w) {
  // strtod also takes hex floats, "inf" and "nan"; NFF numbers are plain decimals.
  bool digit = false;
  for (char c : w) {
    if (c >= '0' && c <= '9') digit = true;
    else if (c != '+' && c != '-' && c != '.' && c != 'e' && c != 'E') return false;
  }
  return digit;
}
}  // namespace

float line_reader::number(const text_line& l, size_t i, const char* what) const {
  std::string w(l.words.at(i));
  if (!looks_decimal(w)) {  // only then is it worth telling nan/inf from other words
    std::string lower;
    for (char c : w) lower += char(std::tolower(static_cast<unsigned char>(c)));
    if (lower.find("nan") != std::string::npos || lower.find("inf") != std::string::npos)
      fail(l.number, std::string(what) + ": '" + w + "' is not a finite number");
    fail(l.number, std::string(what) + ": '" + w + "' is not a number");
  }
  errno = 0;
  char* end = nullptr;
  double v = std::strtod(w.c_str(), &end);
  if (end != w.c_str() + w.size()) fail(l.number, std::string(what) + ": '" + w + "' is not a number");
  if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max()))
    fail(l.number, std::string(what) + ": '" + w + "' is not a finite number");
  return float(v);
}

long line_reader::integer(const text_line& l, size_t i, const char* what, long lo, long hi) const {
  std::string w(l.words.at(i));
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(w.c_str(), &end, 10);
  if (w.empty() || end != w.c_str() + w.size() || errno == ERANGE)
    fail(l.number, std::string(what) + ": '" + w + "' is not an integer");
  if (v < lo || v > hi) {
    std::ostringstream m;
    m << what << ": " << v << " is out of range [" << lo << ", " << hi << "]";
    fail(l.number, m.str());
  }
  return v;
}

void line_reader::expect_count(const text_line& l, size_t n, const char* what) const {
  size_t got = l.words.size() - 1;
  if (got != n) {
    std::ostringstream m;
    m << what << " needs " << n << (n == 1 ? " number" : " numbers") << ", got " << got;
    fail(l.number, m.str());
  }
}

std::string read_text_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw input_error(path, 0, "cannot open file");
  std::ostringstream ss;
  ss << in.rdbuf();
  if (in.bad()) throw input_error(path, 0, "cannot read file");
  return ss.str();
}

}  // namespace epsray
