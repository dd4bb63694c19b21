#include "render.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <memory>
#include <mutex>
#include <thread>

#include "accel/world.h"
#include "common.h"
#include "image/image_io.h"
#include "interrupt.h"
#include "outputs.h"
#include "progress.h"
#include "scene/input_error.h"
#include "scene/nff.h"
#include "scene/path_file.h"
#include "sched/verify.h"
#include "stats_json.h"

namespace epsray {

namespace {

// An interrupted render writes nothing: what the outputs' destructor has not yet removed
// was never renamed into place.
int interrupted(progress_line& bar, int signal) {
  bar.finish();
  std::fprintf(stderr, "epsray: interrupted by %s; nothing written\n", signal_name(signal));
  return interrupted_exit_code(signal);
}

// The frame, with the progress line redrawn from its rows as tiles finish (on a terminal
// only): the time left is the time so far scaled by the rows left.
frame_result render_frame_with_progress(workers& pool, const world& w, const camera& cam, frame_params fp,
                                        progress_line& bar) {
  if (!bar.shown()) return render_frame(pool, w, cam, fp);
  std::atomic<int> rows{0};
  fp.rows_done = &rows;
  std::mutex m;
  std::condition_variable wake;
  bool finished = false;
  const auto t0 = std::chrono::steady_clock::now();
  std::thread watcher([&] {
    std::unique_lock<std::mutex> lock(m);
    // Woken at once when the frame ends, so the frame's time holds no wait for this thread.
    while (!wake.wait_for(lock, std::chrono::milliseconds(200), [&] { return finished; })) {
      const int done = rows.load(std::memory_order_relaxed);
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      bar.show(done, cam.height, "rows rendered", done ? s * (cam.height - done) / done : -1);
    }
  });
  struct joiner {
    std::thread& t;
    std::mutex& m;
    std::condition_variable& c;
    bool& f;
    ~joiner() {
      {
        std::lock_guard<std::mutex> lock(m);
        f = true;
      }
      c.notify_one();
      t.join();
    }
  } join{watcher, m, wake, finished};
  return render_frame(pool, w, cam, fp);
}

}  // namespace

int run_render(const cli_options& o) {
  // The render's phases, for the progress line: sched/ reports nothing from inside a frame.
  const int phases = o.verify ? 5 : 4;
  progress_line bar(o.quiet);
  bar.show(0, phases, "loading the scene", -1);
  scene sc = load_scene(o.scene);
  camera_view view = sc.view;
  if (!o.path.empty()) {
    camera_path path = load_camera_path(o.path);
    int k = o.frame.value_or(0);
    if (k >= int(path.frames.size()))
      throw usage_error("epsray: bad --frame " + std::to_string(k) + ": " + printable_name(o.path) + " has " +
                        std::to_string(path.frames.size()) + " frames");
    view = path.frames[size_t(k)];
  }
  check_writable(o.png, "--png");
  check_writable(o.pfm, "--pfm");
  check_writable(o.stats, "--stats");
  check_writable(o.reasons, "--reasons");
  reject_unbuilt(o);
  reprojection_state reproj;  // full: the cells carried to the next frame
  open_reprojection(o, reproj);

  int width = o.size ? o.size->first : sc.view.width;
  int height = o.size ? o.size->second : sc.view.height;
  int threads = o.threads ? o.threads : hardware_threads();
  // The worker threads are start-up (contract: total_ms excludes it): started and woken
  // before the clock, as a walk or the viewer does once for all its frames.
  workers pool(threads, o.pin);
  pool.warm_up();
  if (int s = interrupt_signal()) return interrupted(bar, s);
  bar.show(1, phases, "building the BVH", -1);
  auto t0 = std::chrono::steady_clock::now();
  world w = make_world(std::move(sc));
  std::unique_ptr<linetree_set> trees = make_linetrees(o, w);
  const frame_params fp = make_frame_params(o, trees.get(), &reproj);
  const camera cam = make_camera(view, width, height);
  if (int s = interrupt_signal()) return interrupted(bar, s);
  bar.show(2, phases, "rendering", -1);
  frame_result fr = render_frame_with_progress(pool, w, cam, fp, bar);
  double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  verify_result vr;
  if (o.verify) {
    if (int s = interrupt_signal()) return interrupted(bar, s);
    // Verifying traces every pixel as base does: the frame's own traced pixels say how long.
    const double left = fr.pixels.base ? fr.path_ms.base / double(fr.pixels.base) * double(width) * double(height) /
                                             double(threads) / 1000
                                       : -1;
    bar.show(3, phases, "verifying", left);
    vr = verify_frame(pool, w, cam, fr.img, o.eps);
  }
  check_finite(fr);
  if (int s = interrupt_signal()) return interrupted(bar, s);

  bar.show(phases - 1, phases, "writing", -1);
  output_files outs;  // removed again unless every write succeeds
  if (!o.pfm.empty()) write_pfm(fr.img, o.pfm), outs.wrote(o.pfm);
  if (!o.png.empty()) write_png(fr.img, o.png), outs.wrote(o.png);
  if (!o.reasons.empty()) write_png(fr.reasons, o.reasons), outs.wrote(o.reasons);
  if (!o.stats.empty()) {
    run_record r = make_run_record(o, width, height, threads);
    r.frames.push_back(make_frame_record(o.frame.value_or(0), fr, o.verify ? &vr : nullptr));
    r.total_ms = total_ms;
    r.peak_memory_bytes = peak_memory_bytes();
    write_stats_json(r, o.stats);
    outs.wrote(o.stats);
  }
  if (int s = interrupt_signal()) return interrupted(bar, s);
  outs.keep();
  bar.show(phases, phases, "done", -1);
  bar.finish();
  if (!o.quiet) {
    std::printf("%s: %dx%d, %zu primitives, %zu lights, mode %s, %d threads\n", printable_name(o.scene).c_str(), width,
                height, w.scene_prims, w.light_pos.size(), mode_name(o.mode), threads);
    std::printf("frame %.1f ms (total %.1f ms with BVH build); rays: eye %llu reflect %llu refract %llu shadow %llu\n",
                fr.ms, total_ms, (unsigned long long)fr.rays.eye, (unsigned long long)fr.rays.reflect,
                (unsigned long long)fr.rays.refract, (unsigned long long)fr.rays.shadow);
    std::printf("pixels: interp %llu (with per-pixel rays %llu) base %llu; memory %.1f MB\n",
                (unsigned long long)fr.pixels.interp, (unsigned long long)fr.pixels.deferred,
                (unsigned long long)fr.pixels.base, double(fr.memory_bytes) / 1e6);
    if (o.verify)
      std::printf("verify: max error %.4g, 99.9%% %.4g, %llu pixels over eps %g\n", vr.max_rel_err, vr.p999_rel_err,
                  (unsigned long long)vr.violations, double(o.eps));
    for (const std::string* f : {&o.png, &o.pfm, &o.reasons, &o.stats})
      if (!f->empty()) std::printf("wrote %s\n", printable_name(*f).c_str());
  }
  return 0;
}

}  // namespace epsray
