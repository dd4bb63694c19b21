// epsray walk: every camera of a path in order, keeping the linetrees between frames; under
// mpirun, over the ranks (walk_ranks.cpp, docs/mpi.md).
#pragma once
#include <memory>
#include <string>

#include "accel/world.h"
#include "args.h"
#include "outputs.h"
#include "scene/path_file.h"
#include "sched/frame_render.h"
#include "sched/verify.h"
#include "stats_json.h"

namespace epsray {

int run_walk(const cli_options& o);

// --- what the walk in one process and the walk over ranks share ------------------------

// Every input, checked before any work: the scene, the whole path, the outputs, OSMesa.
struct walk_inputs {
  scene sc;
  camera_path path;
  int width = 0, height = 0, threads = 0;
  std::unique_ptr<reprojection_state> reproj;  // fresh, with OSMesa open where asked
};
walk_inputs check_walk_inputs(const cli_options& o);

// The frames of a walk, rendered in order with what they carry from one to the next: the
// linetrees, and in full mode the cells to reproject. A frame starts afresh (linetrees as
// make_linetrees makes them, no cells, OSMesa opened again) when it is the first of a
// segment or a keyframe (--keyframe), so that a rank starting at a keyframe renders it
// exactly as one process walking the whole path does.
class walk_frames {
 public:
  // first_state: the fresh state check_walk_inputs opened, used by the first frame.
  walk_frames(const cli_options& o, const world& w, workers& pool, const walk_inputs& in,
              std::unique_ptr<reprojection_state> first_state);
  struct rendered {
    frame_result fr;
    verify_result vr;
  };
  // Frame k of the segment first..last (first <= k <= last).
  rendered render(int k, int first, int last);
  // Whether frame k starts afresh in a segment that starts at `first`.
  bool cold(int k, int first) const { return k == first || (o_.keyframe > 0 && k % o_.keyframe == 0); }

 private:
  void start_afresh();
  const cli_options& o_;
  const world& w_;
  workers& pool_;
  const camera_path& path_;
  int width_, height_;
  std::unique_ptr<reprojection_state> reproj_, fresh_;
  std::unique_ptr<linetree_set> trees_;
  frame_params fp_;
};

// DIR/frame_0007.png and .pfm as the flags ask, each written whole and recorded in outs;
// returns the milliseconds spent writing.
double write_frame_files(const cli_options& o, int k, const image& img, output_files& outs);
// The one summary on stdout (not --quiet): over `ranks` ranks when more than one.
void print_walk_summary(const cli_options& o, const run_record& rec, int ranks);

}  // namespace epsray
