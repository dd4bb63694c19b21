// Bad input carries its location: the CLI prints `file:line: what` and exits 2.
#pragma once
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace epsray {

struct input_error : std::runtime_error {
  std::string file;
  int line = 0;  // 1-based; 0 when the problem is not tied to one line
  std::string what_is_wrong;
  input_error(std::string file_, int line_, std::string what_)
      : std::runtime_error(file_ + ":" + std::to_string(line_) + ": " + what_),
        file(std::move(file_)), line(line_), what_is_wrong(std::move(what_)) {}
};

// Control characters (a newline in a file name) as C escapes, so that a message stays one
// line and says exactly which bytes were given. Other bytes, UTF-8 included, are kept.
inline std::string escape_controls(std::string_view s) {
  std::string out;
  out.reserve(s.size());
  for (const char ch : s) {
    const unsigned char c = static_cast<unsigned char>(ch);
    switch (c) {
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char hex[8];
          std::snprintf(hex, sizeof hex, "\\x%02x", c);
          out += hex;
        } else {
          out += ch;
        }
    }
  }
  return out;
}

// A file name as messages print it: as given, or, when it holds a control character,
// inside double quotes with C escapes (a quote or a backslash in it escaped too).
inline std::string printable_name(std::string_view file) {
  if (escape_controls(file) == file) return std::string(file);
  std::string out = "\"";
  for (const char ch : file) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += escape_controls(std::string_view(&ch, 1));
  }
  return out + "\"";
}

// The one line the CLI prints for e: `file:line: what`, with the file name printable and
// no control character left in what is wrong (which may quote a texture's file name).
inline std::string one_line(const input_error& e) {
  return printable_name(e.file) + ":" + std::to_string(e.line) + ": " + escape_controls(e.what_is_wrong);
}

}  // namespace epsray
