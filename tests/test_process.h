// Subprocesses for the tests that drive build/epsray (and servers such as Xvfb): started
// with posix_spawn in a chosen folder and environment, output captured, never waited for
// past a time limit.
#pragma once
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <algorithm>
#include <initializer_list>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "test_util.h"

extern char** environ;

namespace epsray::test {

struct proc_result {
  bool exited = false;  // false: killed by a signal (a crash) or past its time limit
  bool timed_out = false;
  int code = -1;
  int signal = 0;
  std::string out, err;
};

inline std::ostream& operator<<(std::ostream& os, const proc_result& r) {
  return os << (r.timed_out ? std::string("timed out")
                : r.exited  ? "exit " + std::to_string(r.code)
                            : "signal " + std::to_string(r.signal))
            << ", stderr: [" << r.err << "], stdout: [" << r.out << "]";
}

// This process's environment less the variables named, plus `extra` ("NAME=value").
inline std::vector<std::string> environment(std::initializer_list<const char*> without = {},
                                            std::initializer_list<std::string> extra = {}) {
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e) {
    bool keep = true;
    for (const char* name : without)
      keep = keep && !(std::strncmp(*e, name, std::strlen(name)) == 0 && (*e)[std::strlen(name)] == '=');
    if (keep) env.push_back(*e);
  }
  env.insert(env.end(), extra.begin(), extra.end());
  return env;
}

// Pointers for exec: each string, then a null.
inline std::vector<char*> c_strings(std::vector<std::string>& v) {
  std::vector<char*> p;
  for (std::string& s : v) p.push_back(s.data());
  p.push_back(nullptr);
  return p;
}

// Waits for `pid` at most `seconds`, then kills it; false when it had to be killed.
inline bool wait_or_kill(pid_t pid, double seconds, int& status) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    const pid_t r = waitpid(pid, &status, WNOHANG);
    if (r == pid || (r < 0 && errno != EINTR)) return r == pid;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  kill(pid, SIGKILL);
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  return false;
}

// Starts `argv` (argv[0] the executable's path) in folder `cwd` with environment `env`, its
// stdout and stderr into the files `out` and `err`, and leaves it running: its pid, or -1
// (a test failure) when it cannot start.
inline pid_t start_process(std::vector<std::string> argv, const fs::path& cwd, std::vector<std::string> env,
                           const std::string& out, const std::string& err) {
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
  pid_t pid = -1;
  const int rc = posix_spawn(&pid, argv[0].c_str(), &fa, nullptr, c_strings(argv).data(), c_strings(env).data());
  posix_spawn_file_actions_destroy(&fa);
  if (rc != 0) {
    ADD_FAILURE() << "cannot start " << argv[0] << ": " << std::strerror(rc);
    return -1;
  }
  return pid;
}

// Runs `argv` (argv[0] the executable's path) in folder `cwd` with environment `env`, its
// stdout and stderr captured through files in `io`.
inline proc_result run_process(std::vector<std::string> argv, const fs::path& cwd, std::vector<std::string> env,
                               const temp_dir& io, double timeout_s = 120) {
  const std::string out_path = io.file("stdout"), err_path = io.file("stderr");
  const pid_t pid = start_process(std::move(argv), cwd, std::move(env), out_path, err_path);
  proc_result r;
  if (pid < 0) return r;
  int status = 0;
  r.timed_out = !wait_or_kill(pid, timeout_s, status);
  r.exited = !r.timed_out && WIFEXITED(status);
  r.code = r.exited ? WEXITSTATUS(status) : -1;
  r.signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  r.out = read_file(out_path);
  r.err = read_file(err_path);
  return r;
}

// Polls for `file` at most `seconds`.
inline bool appears(const fs::path& file, double seconds) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    if (fs::exists(file)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// The names in folder `dir`, sorted (none when it does not exist).
inline std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

}  // namespace epsray::test
