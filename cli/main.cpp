// epsray: the command line of ../shared/spec/contract.md.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>

#include "accel/world.h"
#include "args.h"
#include "common.h"
#include "walk.h"
#include "viewer/view.h"
#include "image/image_io.h"
#include "scene/input_error.h"
#include "scene/nff.h"
#include "scene/path_file.h"
#include "sched/topology.h"
#include "sched/verify.h"
#include "stats_json.h"

using namespace epsray;

namespace {

int run_info() {
  std::cout << "epsray 0.1\nhardware threads: " << hardware_threads() << "\n"
            << "topology (hwloc): " << discover_topology().summary() << "\n";
  return 0;
}

int run_render(const cli_options& o) {
  scene sc = load_scene(o.scene);
  camera_view view = sc.view;
  if (!o.path.empty()) {
    camera_path path = load_camera_path(o.path);
    int k = o.frame.value_or(0);
    if (k >= int(path.frames.size()))
      throw usage_error("epsray: bad --frame " + std::to_string(k) + ": " + o.path + " has " +
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
  auto t0 = std::chrono::steady_clock::now();
  world w = make_world(std::move(sc));
  std::unique_ptr<linetree_set> trees = make_linetrees(o, w);
  const frame_params fp = make_frame_params(o, trees.get(), &reproj);
  const camera cam = make_camera(view, width, height);
  frame_result fr = render_frame(pool, w, cam, fp);
  double total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  verify_result vr;
  if (o.verify) vr = verify_frame(pool, w, cam, fr.img, o.eps);

  check_finite(fr.img);

  if (!o.pfm.empty()) write_pfm(fr.img, o.pfm);
  if (!o.png.empty()) write_png(fr.img, o.png);
  if (!o.reasons.empty()) write_png(fr.reasons, o.reasons);
  if (!o.stats.empty()) {
    run_record r;
    r.scene = o.scene, r.mode = mode_name(o.mode), r.width = width, r.height = height, r.threads = threads;
    r.eps = o.eps;
    frame_record fr_rec{o.frame.value_or(0), fr.ms, fr.pixels, fr.rays, fr.memory_bytes, fr.linetree_bytes, fr.path_ms, fr.reproject_ms,
                        fr.ahead_ms, fr.ahead_wait_ms, fr.shade, fr.after_ms};
    fr_rec.verified = o.verify;
    fr_rec.max_rel_err = vr.max_rel_err, fr_rec.p999_rel_err = vr.p999_rel_err, fr_rec.mean_rel_err = vr.mean_rel_err, fr_rec.violations = vr.violations;
    r.frames.push_back(fr_rec);
    r.total_ms = total_ms;
    r.peak_memory_bytes = peak_memory_bytes();
    write_stats_json(r, o.stats);
  }
  if (!o.quiet) {
    std::printf("%s: %dx%d, %zu primitives, %zu lights, mode %s, %d threads\n", o.scene.c_str(), width, height,
                w.scene_prims, w.light_pos.size(), mode_name(o.mode), threads);
    std::printf("frame %.1f ms (total %.1f ms with BVH build); rays: eye %llu reflect %llu refract %llu shadow %llu\n",
                fr.ms, total_ms, (unsigned long long)fr.rays.eye, (unsigned long long)fr.rays.reflect,
                (unsigned long long)fr.rays.refract, (unsigned long long)fr.rays.shadow);
    std::printf("pixels: interp %llu (with per-pixel rays %llu) base %llu; memory %.1f MB\n",
                (unsigned long long)fr.pixels.interp, (unsigned long long)fr.pixels.deferred,
                (unsigned long long)fr.pixels.base, double(fr.memory_bytes) / 1e6);
    if (o.verify)
      std::printf("verify: max error %.4g, 99.9%% %.4g, %llu pixels over eps %g\n", vr.max_rel_err, vr.p999_rel_err,
                  (unsigned long long)vr.violations, double(o.eps));
    if (!o.png.empty()) std::printf("wrote %s\n", o.png.c_str());
    if (!o.pfm.empty()) std::printf("wrote %s\n", o.pfm.c_str());
    if (!o.stats.empty()) std::printf("wrote %s\n", o.stats.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty() && (args[0] == "--help" || args[0] == "-h" || args[0] == "help")) {
    std::cout << usage_text();
    return 0;
  }
  try {
    cli_options o = parse_args(args);
    if (o.command == "info") return run_info();
    if (o.command == "walk") return run_walk(o);
    if (o.command == "view") return run_view(o);
    return run_render(o);
  } catch (const input_error& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const usage_error& e) {
    std::cerr << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "epsray: " << e.what() << "\n";
    return 1;
  }
}
