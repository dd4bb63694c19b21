// outputs: build/epsray's files appear whole or not at all. A walk stopped by SIGINT or
// SIGTERM keeps its complete frames and their stats; a render stopped writes nothing; a
// run whose last write fails removes what it wrote; and the progress line shows on a
// terminal only. The subprocesses here run while the test watches them (a file appears,
// a terminal shows a phase) and signals them.
#include <fcntl.h>
#include <poll.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "image/image_io.h"
#include "test_process.h"

namespace epsray {
namespace {

namespace fs = std::filesystem;
using test::temp_dir;

const std::string artroom = std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff";
const std::string long_path = std::string(EPSRAY_SOURCE_DIR) + "/scenes/paths/artroom-long.path";

// A pseudo-terminal: the child's stderr, read here as a user's terminal would show it.
class terminal {
 public:
  terminal() {
    master_ = posix_openpt(O_RDWR | O_NOCTTY);
    if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0) return;
    const char* name = ptsname(master_);
    if (name) slave_ = name;
  }
  ~terminal() {
    if (master_ >= 0) close(master_);
  }
  bool ok() const { return !slave_.empty(); }
  const std::string& slave() const { return slave_; }
  // Reads what is there within `ms` milliseconds; false once the child's side is closed.
  bool read_some(int ms) {
    pollfd p{master_, POLLIN, 0};
    if (poll(&p, 1, ms) <= 0) return true;
    char buf[4096];
    const ssize_t n = read(master_, buf, sizeof buf);
    if (n <= 0) return false;
    text.append(buf, size_t(n));
    return true;
  }
  std::string text;

 private:
  int master_ = -1;
  std::string slave_;
};

// build/epsray started in `cwd` and left running: stdout to a file, stderr to a file or
// to a terminal's slave side.
class child {
 public:
  child(std::vector<std::string> args, const fs::path& cwd, const std::string& out, const std::string& err) {
    std::vector<std::string> argv{EPSRAY_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<std::string> env = test::environment();
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err.c_str(), O_RDWR | O_CREAT | O_TRUNC | O_NOCTTY, 0644);
    posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
    const int rc = posix_spawn(&pid_, argv[0].c_str(), &fa, nullptr, test::c_strings(argv).data(),
                               test::c_strings(env).data());
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) ADD_FAILURE() << "cannot start " << argv[0] << ": " << std::strerror(rc), pid_ = -1;
  }
  ~child() {
    if (pid_ > 0) finish(0);
  }
  bool running() const { return pid_ > 0; }
  void signal(int s) const { kill(pid_, s); }
  // Waits at most `seconds` (then kills it); the exit code, or -1 when it did not exit.
  int finish(double seconds) {
    int status = 0;
    const bool exited = test::wait_or_kill(pid_, seconds, status) && WIFEXITED(status);
    pid_ = -1;
    return exited ? WEXITSTATUS(status) : -1;
  }

 private:
  pid_t pid_ = -1;
};

using test::appears;
using test::names_in;

class Outputs : public testing::Test {
 protected:
  temp_dir work, io;
  std::string out() const { return test::read_file(io.file("stdout")); }
  std::string err() const { return test::read_file(io.file("stderr")); }
};

// --- a walk stopped by a signal -------------------------------------------------------------

class WalkSignal : public Outputs, public testing::WithParamInterface<int> {};

TEST_P(WalkSignal, KeepsCompleteFramesAndTheirStats) {
  const int sig = GetParam();
  child c({"walk", artroom, "--path", long_path, "--size", "160x120", "--out-dir", "frames", "--pfm", "--stats",
           "w.json"},
          work.path(), io.file("stdout"), io.file("stderr"));
  ASSERT_TRUE(c.running());
  ASSERT_TRUE(appears(work.path() / "frames" / "frame_0000.pfm", 60)) << err();
  c.signal(sig);
  const int code = c.finish(60);
  EXPECT_EQ(code, 128 + sig) << err();

  const std::vector<std::string> files = names_in(work.path() / "frames");
  for (const std::string& f : files) EXPECT_EQ(f.find(".tmp"), std::string::npos) << f << " left behind";
  EXPECT_EQ(names_in(work.path()), (std::vector<std::string>{"frames", "w.json"}));
  const nlohmann::json j = nlohmann::json::parse(test::read_file(work.file("w.json")));
  EXPECT_EQ(j.at("interrupted"), true);
  const nlohmann::json& frames = j.at("frames");
  ASSERT_GE(frames.size(), 1u);
  EXPECT_LT(frames.size(), 1002u) << "the walk was not stopped";
  ASSERT_EQ(files.size(), frames.size()) << "one file per frame in the stats";
  for (size_t k = 0; k < files.size(); ++k) {
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04zu.pfm", k);
    EXPECT_EQ(files[k], name);
    EXPECT_EQ(frames[k].at("index"), k);
    const image img = read_pfm((work.path() / "frames" / name).string());  // throws if cut short
    EXPECT_EQ(img.width, 160);
    EXPECT_EQ(img.height, 120);
  }
  EXPECT_NE(err().find("interrupted"), std::string::npos) << err();
}

INSTANTIATE_TEST_SUITE_P(Signals, WalkSignal, testing::Values(SIGINT, SIGTERM),
                         [](const testing::TestParamInfo<int>& i) {
                           return std::string(i.param == SIGINT ? "SIGINT" : "SIGTERM");
                         });

// --- a render stopped by a signal, seen on a terminal ------------------------------------------

class RenderSignal : public Outputs, public testing::WithParamInterface<int> {};

TEST_P(RenderSignal, WritesNothing) {
  terminal tty;
  if (!tty.ok()) GTEST_SKIP() << "no pseudo-terminal here";
  const int sig = GetParam();
  // Large enough to be still rendering when the signal comes (half a second in a release
  // build on one thread); the frame in hand is finished before the signal is looked at.
  child c({"render", artroom, "--mode", "base", "--size", "640x480", "--threads", "1", "--png", "a.png", "--pfm",
           "a.pfm", "--stats", "a.json"},
          work.path(), io.file("stdout"), tty.slave());
  ASSERT_TRUE(c.running());
  // The progress line names the phase: once it says rendering, the handlers are in place.
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (tty.text.find("rendering") == std::string::npos && std::chrono::steady_clock::now() < end)
    if (!tty.read_some(20)) break;
  ASSERT_NE(tty.text.find("rendering"), std::string::npos) << tty.text;
  EXPECT_NE(tty.text.find("1/4 building the BVH"), std::string::npos) << tty.text;
  c.signal(sig);
  const int code = c.finish(120);
  while (tty.read_some(100)) {
  }
  EXPECT_EQ(code, 128 + sig) << tty.text;
  EXPECT_TRUE(names_in(work.path()).empty()) << "an interrupted render writes nothing";
  EXPECT_NE(tty.text.find("interrupted"), std::string::npos) << tty.text;
}

INSTANTIATE_TEST_SUITE_P(Signals, RenderSignal, testing::Values(SIGINT, SIGTERM),
                         [](const testing::TestParamInfo<int>& i) {
                           return std::string(i.param == SIGINT ? "SIGINT" : "SIGTERM");
                         });

// --- the progress line: on a terminal, with the time left; never into a file -----------------

const std::string small_scene =
    "v\nfrom 0 -5 2\nat 0 0 0.5\nup 0 0 1\nangle 45\nhither 0.1\nresolution 10 8\n"
    "l 3 -3 5\nf 0.9 0.9 0.9 0.7 0.3 20 0 1\np 4\n-4 -4 0\n4 -4 0\n4 4 0\n-4 4 0\n"
    "f 1 0.3 0.3 0.6 0.2 10 0.4 1.4\ns 0 0 1 0.8\n";
const std::string three_frames = "0 -5 2 0 0 0.5 0 0 1 45\n1 -5 2 0 0 0.5 0 0 1 45\n2 -5 2 0 0 0.5 0 0 1 45\n";

TEST_F(Outputs, WalkProgressShowsOnATerminalWithTheTimeLeft) {
  terminal tty;
  if (!tty.ok()) GTEST_SKIP() << "no pseudo-terminal here";
  test::write_file(work.file("s.nff"), small_scene);
  test::write_file(work.file("p.path"), three_frames);
  child c({"walk", "s.nff", "--path", "p.path", "--size", "16x12"}, work.path(), io.file("stdout"), tty.slave());
  ASSERT_TRUE(c.running());
  const int code = c.finish(60);
  while (tty.read_some(100)) {
  }
  EXPECT_EQ(code, 0) << tty.text;
  EXPECT_NE(tty.text.find("1/3 frames"), std::string::npos) << tty.text;
  EXPECT_NE(tty.text.find("left"), std::string::npos) << tty.text;
  EXPECT_NE(tty.text.find("3/3 frames"), std::string::npos) << tty.text;
}

// A render long enough to be seen (about 0.7 s in a release build on one thread; the line
// is redrawn every 0.2 s): it counts the rows shaded, with the time left.
TEST_F(Outputs, RenderProgressCountsRowsOnATerminal) {
  terminal tty;
  if (!tty.ok()) GTEST_SKIP() << "no pseudo-terminal here";
  child c({"render", artroom, "--mode", "base", "--size", "960x720", "--threads", "1", "--png", "a.png"}, work.path(),
          io.file("stdout"), tty.slave());
  ASSERT_TRUE(c.running());
  const int code = c.finish(120);
  while (tty.read_some(100)) {
  }
  EXPECT_EQ(code, 0) << tty.text;
  EXPECT_NE(tty.text.find("/720 rows rendered"), std::string::npos) << tty.text;
  EXPECT_NE(tty.text.find("left"), std::string::npos) << tty.text;
}

TEST_F(Outputs, NoProgressIntoAFile) {
  test::write_file(work.file("s.nff"), small_scene);
  test::write_file(work.file("p.path"), three_frames);
  for (const std::vector<std::string>& args : {std::vector<std::string>{"walk", "s.nff", "--path", "p.path"},
                                               std::vector<std::string>{"render", "s.nff", "--pfm", "a.pfm"}}) {
    const test::proc_result r = test::run_process([&] {
      std::vector<std::string> a{EPSRAY_BINARY};
      a.insert(a.end(), args.begin(), args.end());
      return a;
    }(), work.path(), test::environment(), io);
    EXPECT_EQ(r.code, 0) << r;
    EXPECT_EQ(r.err, "") << "stderr is a file: no progress line";
    EXPECT_EQ(r.out.rfind("s.nff: ", 0), 0u) << r;  // not quiet: the summary
  }
}

// --- a failing last write: exit 1, every output removed ---------------------------------------

// /dev/full: opens, takes writes, and fails them at the flush (ENOSPC): a late failure no
// check before the work can see.
bool dev_full_fails() {
  std::FILE* f = std::fopen("/dev/full", "wb");
  if (!f) return false;
  std::fputc('x', f);
  const bool failed = std::fflush(f) != 0;
  std::fclose(f);
  return failed;
}

TEST_F(Outputs, RenderWhoseStatsCannotBeWrittenLeavesNothing) {
  if (!dev_full_fails()) GTEST_SKIP() << "no /dev/full here";
  test::write_file(work.file("s.nff"), small_scene);
  const test::proc_result r = test::run_process({EPSRAY_BINARY, "render", "s.nff", "--png", "a.png", "--pfm", "a.pfm",
                                                 "--reasons", "r.png", "--stats", "/dev/full"},
                                                work.path(), test::environment(), io);
  EXPECT_EQ(r.code, 1) << r;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r;
  EXPECT_NE(r.err.find("/dev/full"), std::string::npos) << r;
  EXPECT_EQ(names_in(work.path()), std::vector<std::string>{"s.nff"}) << "the images written are removed";
  EXPECT_TRUE(fs::is_character_file("/dev/full")) << "the device itself is never replaced";
}

TEST_F(Outputs, WalkWhoseStatsCannotBeWrittenLeavesNothing) {
  if (!dev_full_fails()) GTEST_SKIP() << "no /dev/full here";
  test::write_file(work.file("s.nff"), small_scene);
  test::write_file(work.file("p.path"), three_frames);
  const test::proc_result r =
      test::run_process({EPSRAY_BINARY, "walk", "s.nff", "--path", "p.path", "--out-dir", "frames", "--png", "--pfm",
                         "--stats", "/dev/full"},
                        work.path(), test::environment(), io);
  EXPECT_EQ(r.code, 1) << r;
  EXPECT_EQ(names_in(work.path()), (std::vector<std::string>{"p.path", "s.nff"}))
      << "the frames and the folder made for them are removed";
}

// --- outputs that are not plain files ---------------------------------------------------------

TEST_F(Outputs, StatsToStdoutAreWrittenInPlace) {
  // /proc/self/fd/1 leads to the file that holds the process's stdout here: renamed over,
  // the process's own stdout would be left unlinked.
  test::write_file(work.file("s.nff"), small_scene);
  const test::proc_result r = test::run_process(
      {EPSRAY_BINARY, "render", "s.nff", "--pfm", "a.pfm", "--stats", "/proc/self/fd/1", "--quiet"}, work.path(),
      test::environment(), io);
  ASSERT_EQ(r.code, 0) << r;
  const nlohmann::json j = nlohmann::json::parse(r.out);  // stdout holds the stats, nothing else
  EXPECT_EQ(j.at("frames").size(), 1u);
  EXPECT_EQ(names_in(io.path()), (std::vector<std::string>{"stderr", "stdout"})) << "no temporary beside it";
}

TEST_F(Outputs, SymbolicLinkOutputIsWrittenThrough) {
  test::write_file(work.file("s.nff"), small_scene);
  fs::create_directory(work.path() / "real");
  test::write_file(work.file("real/a.png"), "old");
  fs::create_symlink("real/a.png", work.path() / "a.png");
  const test::proc_result r =
      test::run_process({EPSRAY_BINARY, "render", "s.nff", "--png", "a.png", "--quiet"}, work.path(),
                        test::environment(), io);
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_TRUE(fs::is_symlink(work.path() / "a.png")) << "the link is kept";
  EXPECT_EQ(test::read_file(work.file("real/a.png")).substr(1, 3), "PNG");
  EXPECT_EQ(names_in(work.path() / "real"), std::vector<std::string>{"a.png"});
}

}  // namespace
}  // namespace epsray
