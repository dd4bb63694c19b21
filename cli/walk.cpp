#include "walk.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "common.h"
#include "image/image_io.h"
#include "interrupt.h"
#include "progress.h"
#include "ranks.h"
#include "scene/input_error.h"
#include "scene/nff.h"

namespace epsray {

namespace {

std::string frame_file(const std::string& dir, int k, const char* ext) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%04d.%s", k, ext);
  return (std::filesystem::path(dir) / name).string();
}

int run_walk_alone(const cli_options& o) {
  walk_inputs in = check_walk_inputs(o);
  const int count = int(in.path.frames.size());
  workers pool(in.threads, o.pin);
  pool.warm_up();
  output_files outs;  // removed again if the walk fails before its stats are written
  if (!o.out_dir.empty()) {
    outs.made_folder(o.out_dir);
    std::filesystem::create_directories(o.out_dir);
  }

  auto t0 = std::chrono::steady_clock::now();
  world w = make_world(std::move(in.sc));
  walk_frames frames(o, w, pool, in, std::move(in.reproj));

  run_record rec = make_run_record(o, in.width, in.height, in.threads);
  double io_ms = 0;  // file writing is not part of total_ms (contract)
  progress_line bar(o.quiet);
  bar.show(0, count, "frames", -1);
  const auto frames_start = std::chrono::steady_clock::now();
  int stopped = 0;  // the signal that ended the walk early
  for (int k = 0; k < count && !(stopped = interrupt_signal()); ++k) {
    walk_frames::rendered r = frames.render(k, 0, count - 1);
    // Interrupted meanwhile: the frame in hand is abandoned, the ones before it stay.
    if ((stopped = interrupt_signal())) break;
    rec.frames.push_back(make_frame_record(k, r.fr, o.verify ? &r.vr : nullptr));
    io_ms += write_frame_files(o, k, r.fr.img, outs);
    const double spent = std::chrono::duration<double>(std::chrono::steady_clock::now() - frames_start).count();
    char what[64];
    std::snprintf(what, sizeof what, "frames, last %.0f ms", r.fr.ms);
    bar.show(k + 1, count, what, k + 1 < count ? spent / (k + 1) * (count - k - 1) : -1);
  }
  bar.finish();
  rec.total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count() - io_ms;
  rec.peak_memory_bytes = peak_memory_bytes();
  rec.interrupted = stopped != 0;
  if (!o.stats.empty()) write_stats_json(rec, o.stats), outs.wrote(o.stats);
  outs.keep();
  if (stopped)
    std::fprintf(stderr, "epsray: interrupted by %s after %d of %d frames; those and their stats are kept\n",
                 signal_name(stopped), int(rec.frames.size()), count);
  print_walk_summary(o, rec, 1);
  return stopped ? interrupted_exit_code(stopped) : 0;
}

}  // namespace

int run_walk_ranks(const cli_options& o);  // walk_ranks.cpp

int run_walk(const cli_options& o) { return ranks().mpi ? run_walk_ranks(o) : run_walk_alone(o); }

walk_inputs check_walk_inputs(const cli_options& o) {
  walk_inputs in;
  in.sc = load_scene(o.scene);
  in.path = load_camera_path(o.path);
  check_out_dir(o.out_dir);
  check_writable(o.stats, "--stats");
  reject_unbuilt(o);
  in.reproj = std::make_unique<reprojection_state>();  // OSMesa: one that cannot load it fails here
  open_reprojection(o, *in.reproj);
  in.width = o.size ? o.size->first : in.sc.view.width;
  in.height = o.size ? o.size->second : in.sc.view.height;
  in.threads = o.threads ? o.threads : hardware_threads();
  return in;
}

walk_frames::walk_frames(const cli_options& o, const world& w, workers& pool, const walk_inputs& in,
                         std::unique_ptr<reprojection_state> first_state)
    : o_(o), w_(w), pool_(pool), path_(in.path), width_(in.width), height_(in.height), fresh_(std::move(first_state)) {}

void walk_frames::start_afresh() {
  // The cells first (a pipelined preparation may be using the raster and the linetrees).
  reproj_.reset();
  trees_.reset();
  if (fresh_) {
    reproj_ = std::move(fresh_);
  } else {
    reproj_ = std::make_unique<reprojection_state>();
    open_reprojection(o_, *reproj_);
  }
  trees_ = make_linetrees(o_, w_);
  fp_ = make_frame_params(o_, trees_.get(), reproj_.get());
}

walk_frames::rendered walk_frames::render(int k, int first, int last) {
  if (cold(k, first)) start_afresh();
  const auto cam_of = [&](int i) { return make_camera(path_.frames[size_t(i)], width_, height_); };
  const camera cam = cam_of(k);
  // Moving: the camera differs from the path's frame before, whichever rank rendered it.
  fp_.camera_moving = k > 0 && !same_camera(cam, cam_of(k - 1));
  // The path moves on after this frame (frame_params::moves_on), whichever rank renders the next.
  fp_.moves_on = k + 1 < int(path_.frames.size()) && !same_camera(cam, cam_of(k + 1));
  // --pipeline: the next frame's reprojection is prepared while this one is shaded, unless
  // the next one starts afresh or belongs to another segment.
  const bool ahead = o_.pipeline && o_.mode == render_mode::full && k + 1 <= last && !cold(k + 1, first);
  const camera next = ahead ? cam_of(k + 1) : camera{};
  fp_.next_camera = ahead ? &next : nullptr;
  rendered r;
  r.fr = render_frame(pool_, w_, cam, fp_);
  fp_.next_camera = nullptr;
  check_finite(r.fr);
  if (o_.verify && !interrupt_signal()) r.vr = verify_frame(pool_, w_, cam, r.fr.img, o_.eps);
  return r;
}

double write_frame_files(const cli_options& o, int k, const image& img, output_files& outs) {
  auto io0 = std::chrono::steady_clock::now();
  const std::string png = frame_file(o.out_dir, k, "png"), pfm = frame_file(o.out_dir, k, "pfm");
  if (o.png_flag) write_png(img, png), outs.wrote(png);
  if (o.pfm_flag) write_pfm(img, pfm), outs.wrote(pfm);
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - io0).count();
}

void print_walk_summary(const cli_options& o, const run_record& rec, int ranks) {
  if (o.quiet) return;
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
  char over_ranks[48] = "";
  if (ranks > 1) std::snprintf(over_ranks, sizeof over_ranks, " on each of %d ranks", ranks);
  std::printf("%s: %d frames at %dx%d, mode %s, eps %g, %d threads%s\n", printable_name(o.scene).c_str(),
              int(rec.frames.size()), rec.width, rec.height, mode_name(o.mode), double(o.eps), rec.threads,
              over_ranks);
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

}  // namespace epsray
