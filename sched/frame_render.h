// One frame rendered over scanline tiles on the workers. Per-tile results are combined in
// tile order, so images and counts are the same for any thread count and schedule.
#pragma once
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "image/image.h"
#include "interp/interp_shade.h"
#include "baselines/pixel_reuse.h"
#include "interp/linetree.h"
#include "reproject/face_raster.h"
#include "reproject_frame.h"
#include "tile_queue.h"
#include "scene/camera.h"
#include "shade/ray_tree_store.h"
#include "shade/whitted.h"
#include "workers.h"

namespace epsray {

// base, interp and full are the contract's modes. The rest are the baselines the
// speed-against-accuracy suite compares them with (engine/baselines): the base tracer at
// reduced resolution upsampled, reuse of last frame's pixels without error control, and
// interpolation without the predicate in fixed-depth linetrees.
enum class render_mode { base, interp, full, upsample, reuse, lightfield };
const char* mode_name(render_mode m);
bool parse_mode(const std::string& s, render_mode& out);

struct pixel_counts {
  std::uint64_t fast = 0, interp = 0, base = 0;
  std::uint64_t deferred = 0;  // of fast and interp: cells that cast some rays per pixel
  std::uint64_t span = 0;      // of fast: filled in screen space along a span (span_fill.h)
  pixel_counts& operator+=(const pixel_counts& o) {
    fast += o.fast, interp += o.interp, base += o.base, deferred += o.deferred, span += o.span;
    return *this;
  }
};

// Thread time spent per path, summed over threads (the paper's Table 1 divides these by
// the pixels of each path).
struct path_times {
  double fast = 0, interp = 0, base = 0;  // ms
  double deferred = 0;  // of fast + interp: the pixels that cast per-pixel rays (pixel_counts::deferred)
  double span = 0;      // of fast: the runs filled in screen space (pixel_counts::span)
  double build = 0;     // of interp + base: building interpolants (paid by the pixel that first reaches a cell)
};

// What full mode carries from one frame to the next besides the linetrees: the cells that
// gave pixels their radiance. The reuse baseline carries last frame's pixels instead.
// Full: the mirror cells of the frame's planar reflector (engine/reproject/mirror.h),
// in linetrees of their own, and the cells last frame's reflections used.
struct mirror_state {
  int reflector = -1;
  std::unique_ptr<linetree_set> trees;
  std::vector<cell_ref> cells;
};

struct reprojection_state {
  std::vector<cell_ref> cells;
  mirror_state mirror;
  reuse_state pixels;
  // `--reproject osmesa`: the OSMesa context that draws the cells' regions (opened by the
  // caller, which reports a failure to load OSMesa; null: the exact per-pixel method).
  std::unique_ptr<face_raster> raster;
  // `--pipeline`: the next frame's reprojection, prepared while this one is shaded. Last,
  // so that it is destroyed first: its thread may be using the raster.
  reprojection_ahead ahead;
};

struct frame_params {
  render_mode mode = render_mode::base;
  interp_params interp;            // eps and the cost model, for interp and full
  linetree_set* trees = nullptr;   // kept between frames by the caller; needed by interp/full
                                   // (its memory budget is enforced after each frame)
  reprojection_state* reproj = nullptr;  // kept between frames by the caller; needed by full
  int tile_rows = 0;               // 0: default_tile_rows
  tile_order order = tile_order::costly_first;  // how tiles are handed to threads (tile_queue.h)
  // Full, pipelined: the next frame's eye, whose reprojection is prepared on a thread of
  // its own from the last frame's cells while this frame is shaded (null: none).
  const camera* next_camera = nullptr;
  bool camera_moving = false;      // the camera differs from the last frame's (interp_params::
                                   // moving_failed_split_pixels applies)
  // The camera rests now but moves after this frame (a walk's first frame): the cells refused
  // at an edge are split no further than a moving camera's are. Its other floors stay a
  // resting camera's: the cells it refines serve the frames that follow (the art-room walk
  // took 1.12 of the time with all three floors moving in its first frame, 1.008 with this
  // one; mount-s4's and teapot-s6's orbits 0.90 and 0.96, perf/pair.py).
  bool moves_on = false;
  bool keep_ray_trees = false;     // base: fill frame_result::trees, one per pixel, raster order
  bool reasons = false;            // fill frame_result::reasons (the error-coded image)
  // Base, interp and full: each pixel traced again by base mode's code, timed and added to
  // frame_result::base_code_ms under the path that served it, so that a path's cost can be
  // set against what tracing the same pixels costs (a traced pixel lies where the scene is
  // dear, so the average base pixel is the wrong yardstick). Slow; the image is unchanged.
  bool base_cost = false;
  // Rows shaded so far, added tile by tile as each finishes (null: not counted): a
  // progress display reads it from another thread. Nothing the frame computes reads it.
  std::atomic<int>* rows_done = nullptr;
  // The baselines' one knob each.
  int upsample = 2;    // upsample: trace every k-th pixel along each axis
  int reuse_age = 4;   // reuse: frames a pixel's radiance may be carried before it is traced again
  int lf_depth = 4;    // lightfield: halvings of every axis of each linetree
};

struct frame_result {
  image img;
  image reasons;  // with frame_params::reasons: the paper's colours per pixel
  pixel_counts pixels;
  ray_counts rays;
  double ms = 0;
  double reproject_ms = 0;  // full: wall time of trusting and splatting last frame's cells
  // Full, pipelined: wall time of preparing the next frame on its own thread, and how long
  // this frame then waited for it (the part that did not overlap the shading).
  double ahead_ms = 0, ahead_wait_ms = 0;
  std::uint64_t reprojected_cells = 0, trusted_cells = 0;
  // Interp and full: objects the gate will trace with no linetree in the next frame
  // (engine/interp/object_gate.h).
  std::uint64_t objects_off = 0;
  bool plain = false;  // full: traced plainly, no cells (object_gate.h, plain_gain)
  // Every pixel of img is finite: checked by each tile after shading it, in parallel (a
  // serial scan of the image after the frame cost 0.4 ms a frame at 800x600).
  bool finite = true;
  // Full: the pixels of the probe that decided whether this frame keeps its cells, and its
  // wall time (frame_probe.h); 0 when none ran.
  std::uint64_t probe_pixels = 0;
  double probe_ms = 0;
  // Full: the reflector's deferred reflections by source (engine/reproject/mirror.h): a
  // reprojected mirror cell, a mirror cell looked up after a BVH walk, traced.
  std::uint64_t mirror_filled = 0, mirror_looked_up = 0, mirror_traced = 0;
  std::uint64_t mirror_cells = 0, mirror_trusted = 0;
  path_times path_ms;
  // With frame_params::base_cost: base mode's code on the pixels of each path (build: 0).
  path_times base_code_ms;
  // Where the wall time went: the tile phase (with its threads' waits) and what follows it
  // (full: merging the cells used, eviction).
  phase_times shade;
  double after_ms = 0;
  std::uint64_t memory_bytes = 0;  // image, ray trees, linetrees
  std::uint64_t linetree_bytes = 0;  // linetrees, their interpolants, the shared samples and ray trees
  ray_tree_store trees;
};

frame_result render_frame(workers& pool, const world& w, const camera& cam, const frame_params& p);

}  // namespace epsray
