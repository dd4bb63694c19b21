#include "stats_json.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "common.h"
#include "sched/topology.h"
#include "version.h"

namespace epsray {

namespace {

// The CPU's model as /proc/cpuinfo names it (x86: "model name"; some ARM kernels:
// "Model" or "Hardware"), or "unknown".
std::string cpu_model() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    const size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::string key = line.substr(0, colon);
    key.erase(key.find_last_not_of(" \t") + 1);
    if (key != "model name" && key != "Model" && key != "Hardware") continue;
    const size_t start = line.find_first_not_of(" \t", colon + 1);
    if (start != std::string::npos) return line.substr(start);
  }
  return "unknown";
}

}  // namespace

frame_record make_frame_record(int index, const frame_result& fr, const verify_result* vr) {
  frame_record r{index, fr.ms, fr.pixels, fr.rays, fr.memory_bytes, fr.linetree_bytes, fr.path_ms, fr.reproject_ms,
                 fr.ahead_ms, fr.ahead_wait_ms, fr.shade, fr.after_ms};
  r.objects_off = fr.objects_off;
  r.base_code_ms = fr.base_code_ms;
  r.plain = fr.plain;
  r.probe_pixels = fr.probe_pixels, r.probe_ms = fr.probe_ms;
  r.mirror_filled = fr.mirror_filled, r.mirror_looked_up = fr.mirror_looked_up, r.mirror_traced = fr.mirror_traced;
  r.mirror_cells = fr.mirror_cells, r.mirror_trusted = fr.mirror_trusted;
  if (vr) {
    r.verified = true, r.max_rel_err = vr->max_rel_err, r.p999_rel_err = vr->p999_rel_err;
    r.mean_rel_err = vr->mean_rel_err, r.violations = vr->violations;
  }
  return r;
}

run_record make_run_record(const cli_options& o, int width, int height, int threads) {
  run_record r;
  r.scene = o.scene, r.mode = mode_name(o.mode), r.width = width, r.height = height, r.threads = threads;
  r.eps = o.eps;
  r.base_cost = o.base_cost;
  r.command = o.command_line;
  return r;
}

std::uint64_t peak_memory_bytes() {
  std::ifstream in("/proc/self/status");
  std::string key;
  while (in >> key) {
    if (key == "VmHWM:") {
      std::uint64_t kb = 0;
      in >> kb;
      return kb * 1024;
    }
    in.ignore(1 << 20, '\n');
  }
  return 0;
}

void write_stats_json(const run_record& r, const std::string& path) {
  nlohmann::json j;
  j["scene"] = r.scene;
  j["size"] = {r.width, r.height};
  j["mode"] = r.mode;
  j["eps"] = r.eps;
  j["threads"] = r.threads;
  j["frames"] = nlohmann::json::array();
  for (const frame_record& f : r.frames) {
    nlohmann::json fj = {{"index", f.index},
                           {"ms", f.ms},
                           {"pixels", {{"fast", f.pixels.fast}, {"interp", f.pixels.interp}, {"base", f.pixels.base}}},
                           {"rays", {{"eye", f.rays.eye}, {"reflect", f.rays.reflect}, {"refract", f.rays.refract},
                                     {"shadow", f.rays.shadow}, {"shadow_bounded", f.rays.shadow_bounded},
                                     {"shadow_asked", f.rays.shadow_asked},
                                     {"shadow_listed", f.rays.shadow_listed},
                                     {"reflect_listed", f.rays.reflect_listed},
                                     {"shadow_proven", f.rays.shadow_proven},
                                     {"secondary_bounded", f.rays.secondary_bounded}}},
                           {"path_ms", {{"fast", f.path_ms.fast}, {"interp", f.path_ms.interp}, {"base", f.path_ms.base}}},
                           {"reproject_ms", f.reproject_ms},
                           {"deferred_pixels", f.pixels.deferred},
                           {"span_pixels", f.pixels.span},
                           {"span_ms", f.path_ms.span},
                           {"deferred_ms", f.path_ms.deferred},
                           {"build_ms", f.path_ms.build},
                           {"objects_off", f.objects_off},
                           {"plain", f.plain},
                           {"memory_bytes", f.memory_bytes},
                           {"linetree_bytes", f.linetree_bytes}};
    fj["sched"] = {{"shade_ms", f.shade.wall_ms}, {"join_ms", f.shade.join_ms}, {"tail_ms", f.shade.tail_ms},
                   {"after_ms", f.after_ms}};
    if (r.base_cost)
      fj["base_code_ms"] = {{"fast", f.base_code_ms.fast}, {"interp", f.base_code_ms.interp},
                            {"base", f.base_code_ms.base}, {"deferred", f.base_code_ms.deferred},
                            {"span", f.base_code_ms.span}};
    if (r.ranks > 0) fj["rank"] = f.rank;
    if (f.probe_pixels > 0) fj["probe"] = {{"pixels", f.probe_pixels}, {"ms", f.probe_ms}};
    if (f.ahead_ms > 0) fj["ahead_ms"] = f.ahead_ms, fj["ahead_wait_ms"] = f.ahead_wait_ms;
    if (f.mirror_filled + f.mirror_looked_up + f.mirror_traced + f.mirror_cells > 0)
      fj["mirror"] = {{"filled", f.mirror_filled}, {"looked_up", f.mirror_looked_up}, {"traced", f.mirror_traced},
                      {"cells", f.mirror_cells}, {"trusted", f.mirror_trusted}};
    if (f.verified)
      fj["verify"] = {{"max_rel_err", f.max_rel_err}, {"violations", f.violations}, {"p999_rel_err", f.p999_rel_err},
                     {"mean_rel_err", f.mean_rel_err}};
    j["frames"].push_back(fj);
  }
  j["total_ms"] = r.total_ms;
  j["peak_memory_bytes"] = r.peak_memory_bytes;
  j["interrupted"] = r.interrupted;
  j["epsray_version"] = epsray_version();
  j["command"] = r.command;
  j["machine"] = {{"cpu", cpu_model()},
                  {"hardware_threads", hardware_threads()},
                  {"topology", discover_topology().summary()}};
  if (r.ranks > 0) {
    nlohmann::json segs = nlohmann::json::array();
    for (const auto& [first, last] : r.segments) segs.push_back({first, last});
    j["machine"]["mpi"] = {{"ranks", r.ranks}, {"segments", segs}, {"hosts", r.hosts}};
  }
  // Invalid UTF-8 (a file name's bytes) is replaced, not a reason to lose the run.
  write_text_file(path, j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
}

}  // namespace epsray
