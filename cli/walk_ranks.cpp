// epsray walk under mpirun: each rank renders one contiguous segment of the path
// (segments.h), writing its own frames; rank 0 shows the progress over all frames, gathers
// every frame's record into the one --stats file and prints the one summary (docs/mpi.md).
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_scheduler_observer.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <functional>
#include <future>
#include <thread>
#include <type_traits>

#include "common.h"
#include "interrupt.h"
#include "progress.h"
#include "ranks.h"
#include "sched/topology.h"
#include "segments.h"
#include "walk.h"

namespace epsray {

namespace {

using clock_type = std::chrono::steady_clock;

// The messages' tags, and what a rank's end and rank 0's order say besides a signal number.
enum tag : int { frame_done = 1, rank_end = 2, order = 3 };
constexpr int failed = -1;  // a rank failed (its end), or stop because one did (the order)

// Runs f on every rank; the job goes on only where it succeeded on all of them. Returns 0,
// or the largest exit code, printed once, by the first rank that failed with it.
int on_every_rank(const std::function<void()>& f) {
  std::string line;
  int code = 0;
  try {
    f();
  } catch (...) {
    code = describe_error(std::current_exception(), line);
  }
  const job_verdict v = agree(code);
  if (v.code && v.rank == ranks().rank) std::fprintf(stderr, "%s\n", line.c_str());
  return v.code;
}

// f on a thread of its own while the calling thread polls go_on every 2 ms, so that the
// main thread answers messages and signals while a frame renders. True when f finished
// (its exception rethrown here); false when go_on said stop first: f is left running, and
// the process must then end by finish_now (mpirun kills ranks a second after its SIGTERM,
// sooner than a frame may take).
bool run_polling(std::function<void()> f, const std::function<bool()>& go_on) {
  std::packaged_task<void()> task(std::move(f));
  std::future<void> done = task.get_future();
  std::thread t(std::move(task));
  while (done.wait_for(std::chrono::milliseconds(2)) != std::future_status::ready)
    if (!go_on()) {
      t.detach();
      return false;
    }
  t.join();
  done.get();
  return true;
}

// --pin under mpirun: the ranks on one machine take disjoint cores, this rank's threads
// those from local rank x threads on (a pool of workers pins from the first core).
class rank_pinning : public tbb::task_scheduler_observer {
 public:
  rank_pinning(tbb::task_arena& a, int first_core) : tbb::task_scheduler_observer(a), first_(first_core) {
    observe(true);
  }
  ~rank_pinning() override { observe(false); }
  void on_scheduler_entry(bool) override {
    thread_local const void* done_for = nullptr;  // pin once per thread
    if (done_for == this) return;
    done_for = this;
    pins_.pin_current_thread(first_ + tbb::this_task_arena::current_thread_index());
  }

 private:
  core_pinning pins_;
  int first_;
};

// The messages of a walk over ranks. Each rank reports every frame it finishes and, once,
// how it ended; rank 0 sends every other rank exactly one order: stop (a rank was
// interrupted or failed: a signal number or `failed`), or 0 once all have ended.
class walk_link {
 public:
  walk_link(int frames, bool quiet) : frames_(frames), bar_(quiet || ranks().rank != 0, stderr_reaches_terminal()), size_(ranks().size) {
    ended_.assign(size_t(size_), false), ordered_.assign(size_t(size_), false);
    ended_[0] = ordered_[0] = true;
    if (root()) bar_.show(0, frames_, "frames", -1);
  }
  // Between frames and while one renders: false once this rank is to stop.
  bool go_on() {
    if (const int s = interrupt_signal()) note(s);
    int from = 0, value = 0;
    if (root()) {
      while (poll(frame_done, from, value)) shown(1);
      while (poll(rank_end, from, value)) {
        ended_[size_t(from)] = true;
        if (value) note(value);
      }
      if (reason_) order_all(reason_);
    } else if (!ordered_[0] && poll(order, from, value)) {
      ordered_[0] = true;
      if (value) note(value);
    }
    return reason_ == 0;
  }
  void failed_here() { note(failed); }
  void finished_frame() {
    if (root()) shown(1);
    else post(0, frame_done, 0);
  }
  // After this rank's last frame, with how it ended (0, a signal number or failed): rank 0
  // waits for every rank's end, answering as it goes; the others for rank 0's order.
  void end(int how) {
    if (how) note(how);
    if (!root()) {
      post(0, rank_end, how);
      if (!ordered_[0]) note_order(wait_for(0, order));
      return;
    }
    while (std::find(ended_.begin(), ended_.end(), false) != ended_.end()) {
      go_on();
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    order_all(0);
    bar_.finish();
  }
  // What stopped the job early: 0, a signal number or failed.
  int reason() const { return reason_; }

 private:
  bool root() const { return ranks().rank == 0; }
  void note(int why) {
    if (!reason_) reason_ = why;
  }
  void note_order(int value) {
    ordered_[0] = true;
    if (value) note(value);
  }
  void order_all(int value) {
    for (int r = 1; r < size_; ++r)
      if (!ordered_[size_t(r)]) post(r, order, value), ordered_[size_t(r)] = true;
  }
  void shown(int more) {
    done_ += more;
    const double spent = std::chrono::duration<double>(clock_type::now() - start_).count();
    char what[64];
    std::snprintf(what, sizeof what, "frames on %d ranks", size_);
    bar_.show(done_, frames_, what, done_ < frames_ ? spent / done_ * (frames_ - done_) : -1);
  }

  int frames_;
  progress_line bar_;
  int size_;
  std::vector<bool> ended_, ordered_;  // rank 0: per rank; the others: ordered_[0], the order came
  int reason_ = 0, done_ = 0;
  clock_type::time_point start_ = clock_type::now();
};

// What each rank sends rank 0 at the end: how it ended, its times, its frames' records and
// the line of its error. The ranks run one executable, so records travel as their bytes.
struct rank_report {
  int how = 0, code = 0;  // code and line: with how == failed
  double total_ms = 0;
  std::uint64_t peak_memory_bytes = 0;
  std::vector<frame_record> frames;
  std::string line, host;
};
static_assert(std::is_trivially_copyable_v<frame_record>, "frame records travel between ranks as bytes");

template <class T>
void put(std::string& out, const T& x) {
  out.append(reinterpret_cast<const char*>(&x), sizeof x);
}
template <class T>
T take(const std::string& in, size_t& at) {
  T x{};
  if (at + sizeof x <= in.size()) std::memcpy(&x, in.data() + at, sizeof x);
  at += sizeof x;
  return x;
}

std::string pack(const rank_report& r) {
  std::string out;
  put(out, r.how), put(out, r.code), put(out, r.total_ms), put(out, r.peak_memory_bytes);
  put(out, r.frames.size());
  for (const frame_record& f : r.frames) put(out, f);
  for (const std::string* s : {&r.line, &r.host}) put(out, s->size()), out += *s;
  return out;
}

rank_report unpack(const std::string& in) {
  rank_report r;
  size_t at = 0;
  r.how = take<int>(in, at), r.code = take<int>(in, at), r.total_ms = take<double>(in, at);
  r.peak_memory_bytes = take<std::uint64_t>(in, at);
  r.frames.resize(take<size_t>(in, at));
  for (frame_record& f : r.frames) f = take<frame_record>(in, at);
  for (std::string* s : {&r.line, &r.host}) {
    const size_t n = take<size_t>(in, at);
    *s = in.substr(std::min(at, in.size()), n), at += n;
  }
  return r;
}

}  // namespace

int run_walk_ranks(const cli_options& o) {
  const rank_info& me = ranks();
  const bool root = me.rank == 0;
  // Every rank checks every input before any renders; where one finds a fault, all stop.
  walk_inputs in;
  if (const int code = on_every_rank([&] { in = check_walk_inputs(o); })) return code;
  const int count = int(in.path.frames.size());
  const std::vector<segment> segs = split_path(estimate_frame_costs(in.path.frames, o.keyframe), me.size, o.keyframe);
  const segment mine = segs[size_t(me.rank)];

  workers pool(in.threads, false);
  std::unique_ptr<tbb::task_arena> arena;  // the pool's, for rank_pinning
  std::unique_ptr<rank_pinning> pins;
  if (o.pin) {
    pool.run([&] { arena = std::make_unique<tbb::task_arena>(tbb::task_arena::attach()); });
    pins = std::make_unique<rank_pinning>(*arena, me.local_rank * in.threads);
  }
  pool.warm_up();
  output_files outs;  // removed again unless the job succeeds or is interrupted
  if (!o.out_dir.empty()) {
    // Made by rank 0; then found, or made where the ranks share no file system, by the others.
    if (const int code = on_every_rank([&] {
          if (root) outs.made_folder(o.out_dir), std::filesystem::create_directories(o.out_dir);
        }))
      return code;
    if (const int code = on_every_rank([&] {
          if (!root) std::filesystem::create_directories(o.out_dir);
        }))
      return code;
  }

  const auto t0 = clock_type::now();
  std::unique_ptr<world> w;
  std::unique_ptr<walk_frames> frames;
  walk_link link(count, o.quiet);
  rank_report mine_report;
  mine_report.host = me.host;
  double io_ms = 0;
  bool abandoned = false;  // a frame left rendering on its thread: the process ends by finish_now
  auto fail = [&] {
    mine_report.code = describe_error(std::current_exception(), mine_report.line);
    mine_report.how = failed;
    link.failed_here();
  };
  for (int k = mine.first; k <= mine.last && link.go_on(); ++k) {
    // The result belongs to the task: a frame abandoned still rendering writes into it.
    const auto result = std::make_shared<walk_frames::rendered>();
    try {
      const bool finished = run_polling(
          [&, result, k] {
            if (!frames) {
              w = std::make_unique<world>(make_world(std::move(in.sc)));
              frames = std::make_unique<walk_frames>(o, *w, pool, in, std::move(in.reproj));
            }
            *result = frames->render(k, mine.first, mine.last);
          },
          [&] { return link.go_on(); });
      if (!finished) {
        abandoned = true;
        break;
      }
    } catch (...) {
      fail();
      break;
    }
    // Stopped meanwhile: the frame in hand is abandoned, as in one process.
    if (!link.go_on()) break;
    const walk_frames::rendered& r = *result;
    mine_report.frames.push_back(make_frame_record(k, r.fr, o.verify ? &r.vr : nullptr));
    mine_report.frames.back().rank = me.rank;
    try {
      io_ms += write_frame_files(o, k, r.fr.img, outs);
    } catch (...) {
      fail();
      break;
    }
    link.finished_frame();
  }
  mine_report.total_ms = std::chrono::duration<double, std::milli>(clock_type::now() - t0).count() - io_ms;
  mine_report.peak_memory_bytes = peak_memory_bytes();
  if (mine_report.how != failed && link.reason() > 0) mine_report.how = link.reason();
  link.end(mine_report.how);

  // Rank 0 merges the records and writes the stats; its verdict goes to every rank.
  const std::vector<std::string> packed = gather_to_root(pack(mine_report));
  int outcome = 0;
  run_record rec = make_run_record(o, in.width, in.height, in.threads);
  if (root) {
    rec.ranks = me.size;
    int interrupted_by = 0;
    const rank_report* failure = nullptr;
    std::vector<rank_report> reports;
    for (const std::string& p : packed) reports.push_back(unpack(p));
    for (const rank_report& r : reports) {
      rec.frames.insert(rec.frames.end(), r.frames.begin(), r.frames.end());
      rec.total_ms = std::max(rec.total_ms, r.total_ms);
      rec.peak_memory_bytes = std::max(rec.peak_memory_bytes, r.peak_memory_bytes);
      rec.hosts.push_back(r.host);
      if (r.how == failed && !failure) failure = &r;
      if (r.how > 0 && !interrupted_by) interrupted_by = r.how;
    }
    for (const segment& s : segs) rec.segments.emplace_back(s.first, s.last);
    std::sort(rec.frames.begin(), rec.frames.end(),
              [](const frame_record& a, const frame_record& b) { return a.index < b.index; });
    rec.interrupted = interrupted_by != 0;
    std::string line;
    if (failure) {
      outcome = failure->code, line = failure->line;
    } else if (!o.stats.empty()) {
      try {
        write_stats_json(rec, o.stats), outs.wrote(o.stats);
      } catch (...) {
        outcome = describe_error(std::current_exception(), line);
      }
    }
    if (outcome) std::fprintf(stderr, "%s\n", line.c_str());
    else if (interrupted_by) outcome = interrupted_exit_code(interrupted_by);
  }
  outcome = broadcast_from_root(outcome);
  const bool kept = outcome == 0 || outcome > 128;
  if (kept) {
    outs.keep();
  } else {
    // Every rank removes the frames it wrote; then rank 0 the stats and the folder it made.
    if (!root) outs.roll_back();
    barrier();
    if (root) outs.roll_back();
  }
  if (root && outcome > 128)
    std::fprintf(stderr, "epsray: interrupted by %s after %d of %d frames; those and their stats are kept\n",
                 signal_name(outcome - 128), int(rec.frames.size()), count);
  if (root && kept) print_walk_summary(o, rec, me.size);
  // Settled above: nothing may run destructors while the abandoned frame renders.
  if (abandoned) finish_now(outcome);
  return outcome;
}

}  // namespace epsray
