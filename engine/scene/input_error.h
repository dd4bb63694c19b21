// Bad input carries its location: the CLI prints `file:line: what` and exits 2.
#pragma once
#include <stdexcept>
#include <string>

namespace epsray {

struct input_error : std::runtime_error {
  std::string file;
  int line = 0;  // 1-based; 0 when the problem is not tied to one line
  std::string what_is_wrong;
  input_error(std::string file_, int line_, std::string what_)
      : std::runtime_error(file_ + ":" + std::to_string(line_) + ": " + what_),
        file(std::move(file_)), line(line_), what_is_wrong(std::move(what_)) {}
};

}  // namespace epsray
