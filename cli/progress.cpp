#include "progress.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <unistd.h>

namespace epsray {

progress_line::progress_line(bool quiet) : progress_line(quiet, ::isatty(STDERR_FILENO)) {}

progress_line::progress_line(bool quiet, bool on_terminal)
    : shown_(!quiet && on_terminal), start_(std::chrono::steady_clock::now()) {}

std::string duration_text(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buf[48];
  if (seconds < 9.95) std::snprintf(buf, sizeof buf, "%.1f s", std::max(0.0, seconds));
  else if (s < 60) std::snprintf(buf, sizeof buf, "%ld s", s);
  else if (s < 3600) std::snprintf(buf, sizeof buf, "%ld min %ld s", s / 60, s % 60);
  else std::snprintf(buf, sizeof buf, "%ld h %ld min", s / 3600, s / 60 % 60);
  return buf;
}

void progress_line::show(int done, int total, const std::string& what, double seconds_left) {
  if (!shown_) return;
  constexpr int width = 30;
  const int filled = total > 0 ? std::min(width, done * width / total) : width;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::string left = seconds_left >= 0 ? ", about " + duration_text(seconds_left) + " left" : "";
  // \033[K clears what a longer line drawn before left at the end.
  std::fprintf(stderr, "\r[%.*s%*s] %d/%d %s, %s so far%s\033[K", filled, "##############################",
               width - filled, "", done, total, what.c_str(), duration_text(elapsed).c_str(), left.c_str());
  std::fflush(stderr);
  drawn_ = true;
}

void progress_line::finish() {
  if (!drawn_) return;
  std::fputc('\n', stderr);
  std::fflush(stderr);
  drawn_ = false;
}

}  // namespace epsray
