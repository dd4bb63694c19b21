#include "stats_json.h"

#include <fstream>
#include <nlohmann/json.hpp>

#include "common.h"

namespace epsray {

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
                                     {"shadow", f.rays.shadow}}},
                           {"path_ms", {{"fast", f.path_ms.fast}, {"interp", f.path_ms.interp}, {"base", f.path_ms.base}}},
                           {"reproject_ms", f.reproject_ms},
                           {"deferred_pixels", f.pixels.deferred},
                           {"span_pixels", f.pixels.span},
                           {"span_ms", f.path_ms.span},
                           {"deferred_ms", f.path_ms.deferred},
                           {"build_ms", f.path_ms.build},
                           {"memory_bytes", f.memory_bytes},
                           {"linetree_bytes", f.linetree_bytes}};
    fj["sched"] = {{"shade_ms", f.shade.wall_ms}, {"join_ms", f.shade.join_ms}, {"tail_ms", f.shade.tail_ms},
                   {"after_ms", f.after_ms}};
    if (f.ahead_ms > 0) fj["ahead_ms"] = f.ahead_ms, fj["ahead_wait_ms"] = f.ahead_wait_ms;
    if (f.verified)
      fj["verify"] = {{"max_rel_err", f.max_rel_err}, {"violations", f.violations}, {"p999_rel_err", f.p999_rel_err},
                     {"mean_rel_err", f.mean_rel_err}};
    j["frames"].push_back(fj);
  }
  j["total_ms"] = r.total_ms;
  j["peak_memory_bytes"] = r.peak_memory_bytes;
  write_text_file(path, j.dump(2) + "\n");
}

}  // namespace epsray
