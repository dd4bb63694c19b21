#include "walk.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

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

std::string frame_file(const std::string& dir, int k, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.%s", k, ext);
  return (std::filesystem::path(dir) / name).string();
}

}  // namespace

int run_walk(const cli_options& o) {
  // Every input is checked before any work: the scene, the whole path, the outputs.
  scene sc = load_scene(o.scene);
  camera_path path = load_camera_path(o.path);
  check_out_dir(o.out_dir);
  check_writable(o.stats, "--stats");
  reject_unbuilt(o);
  reprojection_state reproj;  // full: the cells carried to the next frame
  open_reprojection(o, reproj);

  const int width = o.size ? o.size->first : sc.view.width;
  const int height = o.size ? o.size->second : sc.view.height;
  const int threads = o.threads ? o.threads : hardware_threads();
  workers pool(threads, o.pin);
  pool.warm_up();
  output_files outs;  // removed again if the walk fails before its stats are written
  if (!o.out_dir.empty()) {
    outs.made_folder(o.out_dir);
    std::filesystem::create_directories(o.out_dir);
  }

  auto t0 = std::chrono::steady_clock::now();
  world w = make_world(std::move(sc));
  std::unique_ptr<linetree_set> trees = make_linetrees(o, w);
  frame_params fp = make_frame_params(o, trees.get(), &reproj);

  run_record rec = make_run_record(o, width, height, threads);
  double io_ms = 0;  // file writing is not part of total_ms (contract)
  const int count = int(path.frames.size());
  progress_line bar(o.quiet);
  bar.show(0, count, "frames", -1);
  const auto frames_start = std::chrono::steady_clock::now();
  camera last;  // the previous frame's
  int stopped = 0;  // the signal that ended the walk early
  for (int k = 0; k < count && !(stopped = interrupt_signal()); ++k) {
    const camera cam = make_camera(path.frames[size_t(k)], width, height);
    fp.camera_moving = k > 0 && !same_camera(cam, last);
    // --pipeline: the next frame's reprojection is prepared while this one is shaded.
    const camera next = k + 1 < count ? make_camera(path.frames[size_t(k + 1)], width, height) : camera{};
    fp.next_camera = o.pipeline && o.mode == render_mode::full && k + 1 < count ? &next : nullptr;
    last = cam;
    frame_result fr = render_frame(pool, w, cam, fp);
    check_finite(fr.img);
    verify_result vr;
    if (o.verify && !interrupt_signal()) vr = verify_frame(pool, w, cam, fr.img, o.eps);
    // Interrupted meanwhile: the frame in hand is abandoned, the ones before it stay.
    if ((stopped = interrupt_signal())) break;
    rec.frames.push_back(make_frame_record(k, fr, o.verify ? &vr : nullptr));
    auto io0 = std::chrono::steady_clock::now();
    const std::string png = frame_file(o.out_dir, k, "png"), pfm = frame_file(o.out_dir, k, "pfm");
    if (o.png_flag) write_png(fr.img, png), outs.wrote(png);
    if (o.pfm_flag) write_pfm(fr.img, pfm), outs.wrote(pfm);
    io_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - io0).count();
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - frames_start).count();
    char what[64];
    std::snprintf(what, sizeof what, "frames, last %.0f ms", fr.ms);
    bar.show(k + 1, count, what, k + 1 < count ? spent / (k + 1) * (count - k - 1) : -1);
  }
  bar.finish();
  rec.total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() - io_ms;
  rec.peak_memory_bytes = peak_memory_bytes();
  rec.interrupted = stopped != 0;
  if (!o.stats.empty()) write_stats_json(rec, o.stats), outs.wrote(o.stats);
  outs.keep();
  const int done = int(rec.frames.size());
  if (stopped)
    std::fprintf(stderr, "epsray: interrupted by %s after %d of %d frames; those and their stats are kept\n",
                 signal_name(stopped), done, count);

  if (!o.quiet) {
    std::vector<double> ms;
    pixel_counts px;
    double max_err = 0;
    std::uint64_t over = 0, mem = 0, lt_mem = 0;
    for (const frame_record& r : rec.frames) {
      ms.push_back(r.ms), px += r.pixels, max_err = std::max(max_err, r.max_rel_err), over += r.violations;
      mem = std::max<std::uint64_t>(mem, r.memory_bytes), lt_mem = std::max<std::uint64_t>(lt_mem, r.linetree_bytes);
    }
    std::sort(ms.begin(), ms.end());
    const double all = std::max(1.0, double(px.fast + px.interp + px.base));  // 1: interrupted before a frame
    std::printf("%s: %d frames at %dx%d, mode %s, eps %g, %d threads\n", printable_name(o.scene).c_str(), done, width,
                height, mode_name(o.mode), double(o.eps), threads);
    std::printf("median frame %.1f ms, total %.1f ms; pixels fast %.1f%% interp %.1f%% base %.1f%% "
                "(with per-pixel rays %.1f%%); memory %.1f MB (linetrees %.1f MB)\n",
                ms.empty() ? 0.0 : ms[ms.size() / 2], rec.total_ms, 100 * double(px.fast) / all,
                100 * double(px.interp) / all, 100 * double(px.base) / all, 100 * double(px.deferred) / all,
                double(mem) / 1e6, double(lt_mem) / 1e6);
    if (o.verify)
      std::printf("verify: max error %.4g, %llu pixels over eps %g\n", max_err, (unsigned long long)over,
                  double(o.eps));
    if (!o.out_dir.empty() && (o.png_flag || o.pfm_flag))
      std::printf("wrote %s/frame_*\n", printable_name(o.out_dir).c_str());
    if (!o.stats.empty()) std::printf("wrote %s\n", printable_name(o.stats).c_str());
  }
  return stopped ? interrupted_exit_code(stopped) : 0;
}

}  // namespace epsray
