#include "walk.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <unistd.h>

#include "accel/world.h"
#include "common.h"
#include "image/image_io.h"
#include "scene/nff.h"
#include "scene/path_file.h"
#include "sched/verify.h"
#include "stats_json.h"

namespace epsray {

namespace {

// One line redrawn in place on a terminal; nothing when stderr is a file or a pipe.
void progress(int done, int total, double last_ms) {
  constexpr int width = 30;
  int filled = total ? done * width / total : width;
  std::fprintf(stderr, "\r[%.*s%*s] %d/%d frames, last %.0f ms", filled, "##############################",
               width - filled, "", done, total, last_ms);
  if (done == total) std::fputc('\n', stderr);
  std::fflush(stderr);
}

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
  const bool bar = !o.quiet && ::isatty(STDERR_FILENO);
  if (!o.out_dir.empty()) std::filesystem::create_directories(o.out_dir);

  auto t0 = std::chrono::steady_clock::now();
  world w = make_world(std::move(sc));
  std::unique_ptr<linetree_set> trees = make_linetrees(o, w);
  frame_params fp = make_frame_params(o, trees.get(), &reproj);

  run_record rec;
  rec.scene = o.scene, rec.mode = mode_name(o.mode), rec.width = width, rec.height = height, rec.threads = threads;
  rec.eps = o.eps;
  double io_ms = 0;  // file writing is not part of total_ms (contract)
  const int count = int(path.frames.size());
  camera last;  // the previous frame's
  for (int k = 0; k < count; ++k) {
    const camera cam = make_camera(path.frames[size_t(k)], width, height);
    fp.camera_moving = k > 0 && !same_camera(cam, last);
    // --pipeline: the next frame's reprojection is prepared while this one is shaded.
    const camera next = k + 1 < count ? make_camera(path.frames[size_t(k + 1)], width, height) : camera{};
    fp.next_camera = o.pipeline && o.mode == render_mode::full && k + 1 < count ? &next : nullptr;
    last = cam;
    frame_result fr = render_frame(pool, w, cam, fp);
    check_finite(fr.img);
    frame_record r{k, fr.ms, fr.pixels, fr.rays, fr.memory_bytes, fr.linetree_bytes, fr.path_ms, fr.reproject_ms,
                   fr.ahead_ms, fr.ahead_wait_ms, fr.shade, fr.after_ms};
    if (o.verify) {
      verify_result vr = verify_frame(pool, w, cam, fr.img, o.eps);
      r.verified = true, r.max_rel_err = vr.max_rel_err, r.p999_rel_err = vr.p999_rel_err, r.mean_rel_err = vr.mean_rel_err;
      r.violations = vr.violations;
    }
    rec.frames.push_back(r);
    auto io0 = std::chrono::steady_clock::now();
    if (o.png_flag) write_png(fr.img, frame_file(o.out_dir, k, "png"));
    if (o.pfm_flag) write_pfm(fr.img, frame_file(o.out_dir, k, "pfm"));
    io_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - io0).count();
    if (bar) progress(k + 1, count, fr.ms);
  }
  rec.total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() - io_ms;
  rec.peak_memory_bytes = peak_memory_bytes();
  if (!o.stats.empty()) write_stats_json(rec, o.stats);

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
    const double all = double(px.fast + px.interp + px.base);
    std::printf("%s: %d frames at %dx%d, mode %s, eps %g, %d threads\n", o.scene.c_str(), count, width, height,
                mode_name(o.mode), double(o.eps), threads);
    std::printf("median frame %.1f ms, total %.1f ms; pixels fast %.1f%% interp %.1f%% base %.1f%% "
                "(with per-pixel rays %.1f%%); memory %.1f MB (linetrees %.1f MB)\n",
                ms.empty() ? 0.0 : ms[ms.size() / 2], rec.total_ms, 100 * double(px.fast) / all,
                100 * double(px.interp) / all, 100 * double(px.base) / all, 100 * double(px.deferred) / all,
                double(mem) / 1e6, double(lt_mem) / 1e6);
    if (o.verify)
      std::printf("verify: max error %.4g, %llu pixels over eps %g\n", max_err, (unsigned long long)over,
                  double(o.eps));
    if (!o.out_dir.empty() && (o.png_flag || o.pfm_flag)) std::printf("wrote %s/frame_*\n", o.out_dir.c_str());
    if (!o.stats.empty()) std::printf("wrote %s\n", o.stats.c_str());
  }
  return 0;
}

}  // namespace epsray
