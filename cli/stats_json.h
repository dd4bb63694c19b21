// The --stats file of the contract: one entry per frame, written whole or not at all.
#pragma once
#include <string>
#include <vector>

#include "args.h"
#include "sched/frame_render.h"
#include "sched/verify.h"

namespace epsray {

struct frame_record {
  int index = 0;
  double ms = 0;
  pixel_counts pixels;
  ray_counts rays;
  std::uint64_t memory_bytes = 0, linetree_bytes = 0;
  path_times path_ms;  // thread time per path
  double reproject_ms = 0;
  double ahead_ms = 0, ahead_wait_ms = 0;  // --pipeline (frame_result)
  phase_times shade;   // the tile phase and its threads' waits (frame_result)
  double after_ms = 0;
  std::uint64_t objects_off = 0;  // interp, full: traced by the object gate in the next frame
  bool plain = false;             // full: a plain frame (object_gate.h)
  std::uint64_t probe_pixels = 0;  // full: the probe before the frame (sched/frame_probe.h)
  double probe_ms = 0;
  // Full: the reflector's deferred reflections by source, and its mirror cells (frame_result).
  std::uint64_t mirror_filled = 0, mirror_looked_up = 0, mirror_traced = 0, mirror_cells = 0, mirror_trusted = 0;
  bool verified = false;
  double max_rel_err = 0, p999_rel_err = 0, mean_rel_err = 0;
  std::uint64_t violations = 0;
  int rank = 0;  // the rank that rendered it (a walk under mpirun)
  path_times base_code_ms{};  // with --base-cost (run_record::base_cost)
};

// Frame `index`'s record; with vr (--verify), its errors.
frame_record make_frame_record(int index, const frame_result& fr, const verify_result* vr);

struct run_record {
  std::string scene, mode;
  int width = 0, height = 0, threads = 0;
  float eps = 0;
  bool base_cost = false;  // --base-cost: frames carry base_code_ms
  std::vector<std::string> command;  // the provenance's argument list, "epsray" first
  std::vector<frame_record> frames;
  double total_ms = 0;
  std::uint64_t peak_memory_bytes = 0;
  bool interrupted = false;  // walk stopped by SIGINT or SIGTERM: frames holds those done
  // A walk under mpirun (ranks > 0): each rank's segment of the path [first, last] and its
  // host; each frame then says its rank.
  int ranks = 0;
  std::vector<std::pair<int, int>> segments;
  std::vector<std::string> hosts;
};

// A run's record before its frames: what the options and the image size say.
run_record make_run_record(const cli_options& o, int width, int height, int threads);

// The JSON, with the provenance: epsray_version, command, machine (cpu, hardware_threads,
// topology). Written whole or not at all; throws std::runtime_error when it cannot.
void write_stats_json(const run_record& r, const std::string& path);
std::uint64_t peak_memory_bytes();

}  // namespace epsray
