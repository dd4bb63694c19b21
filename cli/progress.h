// The progress line of render and walk: one line on stderr redrawn in place, only when
// stderr is a terminal (never in a file or a pipe) and not --quiet.
#pragma once
#include <chrono>
#include <string>

namespace epsray {

class progress_line {
 public:
  explicit progress_line(bool quiet);
  // on_terminal: whether stderr reaches a terminal, where isatty cannot tell (a rank's
  // stderr is a pipe to mpirun's).
  progress_line(bool quiet, bool on_terminal);
  bool shown() const { return shown_; }
  // done of total steps (walk: frames; render: its phases), what the next or last step
  // is, and the seconds left where they can be estimated (negative: not known).
  void show(int done, int total, const std::string& what, double seconds_left);
  // Ends the line, so that what is printed next starts on its own.
  void finish();

 private:
  bool shown_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
};

// "0.4 s", "12 s", "3 min 20 s", "2 h 5 min".
std::string duration_text(double seconds);

}  // namespace epsray
