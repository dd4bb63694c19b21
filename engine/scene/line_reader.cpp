#include "scene/line_reader.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>

namespace epsray {

std::string quote_word(std::string_view w) {
  constexpr size_t keep = 40;
  std::string out = "'";
  for (size_t i = 0; i < w.size() && i < keep; ++i) {
    unsigned char c = static_cast<unsigned char>(w[i]);
    if (c >= 32 && c < 127) {
      out += char(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(c));
      out += buf;
    }
  }
  if (w.size() > keep) out += "...' (" + std::to_string(w.size()) + " characters)";
  else out += "'";
  return out;
}

bool looks_decimal(std::string_view w) {
  bool digit = false;
  for (char c : w) {
    if (c >= '0' && c <= '9') digit = true;
    else if (c != '+' && c != '-' && c != '.' && c != 'e' && c != 'E') return false;
  }
  return digit;
}

std::string bad_byte_message(unsigned char c) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "byte 0x%02x is not printable ASCII", unsigned(c));
  return buf;
}

float parse_number(std::string_view w, const char* what, const std::string& file, int line) {
  auto fail = [&](const char* why) { throw input_error(file, line, std::string(what) + ": " + quote_word(w) + why); };
  if (!looks_decimal(w)) {  // only then is it worth telling nan/inf from other words
    std::string lower;
    for (char c : w.substr(0, 64)) lower += char(std::tolower(static_cast<unsigned char>(c)));
    if (lower.find("nan") != std::string::npos || lower.find("inf") != std::string::npos)
      fail(" is not a finite number");
    fail(" is not a number");
  }
  // A decimal of more digits than a double holds is still a number; the copy is bounded
  // only by the word, which the file's size bound limits.
  std::string s(w);
  char* end = nullptr;
  double v = std::strtod(s.c_str(), &end);
  if (end != s.c_str() + s.size()) fail(" is not a number");
  if (!std::isfinite(v) || std::fabs(v) > double(std::numeric_limits<float>::max())) fail(" is not a finite number");
  return float(v);
}

long parse_integer(std::string_view w, const char* what, long lo, long hi, const std::string& file, int line) {
  std::string s(w.substr(0, 32));
  char* end = nullptr;
  errno = 0;
  long v = std::strtol(s.c_str(), &end, 10);
  if (w.empty() || w.size() > 32 || end != s.c_str() + s.size() || errno == ERANGE)
    throw input_error(file, line, std::string(what) + ": " + quote_word(w) + " is not an integer");
  if (v < lo || v > hi) {
    std::ostringstream m;
    m << what << ": " << v << " is out of range [" << lo << ", " << hi << "]";
    throw input_error(file, line, m.str());
  }
  return v;
}

line_reader::line_reader(std::string_view text, std::string name)
    : text_(text), name_(std::move(name)) {}

void line_reader::fail(int line, const std::string& what) const { throw input_error(name_, line, what); }

bool line_reader::next(text_line& out) {
  while (pos_ < text_.size()) {
    // LF, CRLF and a lone CR (old Mac files) each end a line.
    size_t end = text_.find_first_of("\r\n", pos_);
    if (end == std::string_view::npos) end = text_.size();
    std::string_view raw = text_.substr(pos_, end - pos_);
    pos_ = end + 1;
    if (end < text_.size() && text_[end] == '\r' && pos_ < text_.size() && text_[pos_] == '\n') ++pos_;
    ++line_;
    size_t hash = raw.find('#');
    std::string_view body = raw.substr(0, hash);
    for (unsigned char c : body)
      if (!is_text_byte(c)) fail(line_, bad_byte_message(c));
    out.number = line_;
    out.words.clear();
    size_t i = 0;
    while (i < body.size()) {
      while (i < body.size() && (body[i] == ' ' || body[i] == '\t')) ++i;
      size_t j = i;
      while (j < body.size() && body[j] != ' ' && body[j] != '\t') ++j;
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

void line_reader::expect_count(const text_line& l, size_t n, const char* what) const {
  size_t got = l.words.size() - 1;
  if (got != n) {
    std::ostringstream m;
    m << what << " needs " << n << (n == 1 ? " number" : " numbers") << ", got " << got;
    fail(l.number, m.str());
  }
}

std::string read_input_file(const std::string& path, std::size_t limit) {
  // O_NONBLOCK: opening a FIFO with no writer returns at once, and fstat then refuses it.
  int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) throw input_error(path, 0, std::string("cannot open file (") + std::strerror(errno) + ")");
  struct closer {
    int fd;
    ~closer() { ::close(fd); }
  } guard{fd};
  struct stat st {};
  if (::fstat(fd, &st) != 0) throw input_error(path, 0, "cannot read file");
  if (S_ISDIR(st.st_mode)) throw input_error(path, 0, "is a folder, not a file");
  if (!S_ISREG(st.st_mode)) throw input_error(path, 0, "is not a regular file (a device, FIFO or socket)");
  if (std::size_t(st.st_size) > limit) {
    std::ostringstream m;
    m << "file is " << st.st_size << " bytes, over the limit of " << limit << " bytes";
    throw input_error(path, 0, m.str());
  }
  // Back to blocking reads: a regular file never blocks, and EAGAIN is not worth handling.
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  std::string out(std::size_t(st.st_size), '\0');
  std::size_t got = 0;
  while (got < out.size()) {
    ssize_t k = ::read(fd, out.data() + got, out.size() - got);
    if (k < 0 && errno == EINTR) continue;
    if (k < 0) throw input_error(path, 0, std::string("cannot read file (") + std::strerror(errno) + ")");
    if (k == 0) break;  // the file shrank while read: take what is there
    got += std::size_t(k);
  }
  out.resize(got);
  return out;
}

}  // namespace epsray
