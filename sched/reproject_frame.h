// Full mode's reprojection for one frame (engine/reproject): which of the carried cells are
// trusted from the new eye and which pixels each owns, on the workers or, pipelined, on a
// thread of its own while the frame before is shaded (`--pipeline`).
//
// Pipelining: frame k+1's eye is known while frame k is shaded (a walk's path), but the
// cells frame k will use are not. So frame k+1 is prepared from the cells frame k-1 used
// (known when frame k starts), on a std::thread of its own, while the workers shade frame
// k; when frame k+1 starts, only the cells frame k used besides those are reprojected on
// the critical path, into the pixels still unowned. Ownership is then "first among the
// prepared cells, in list order, then first among the new ones": a function of the lists
// and the eye, never of the threads.
#pragma once
#include <cstdint>
#include <future>
#include <memory>
#include <vector>

#include "reproject/face_raster.h"
#include "reproject/mirror.h"
#include "reproject/reproject.h"
#include "tiles.h"
#include "workers.h"

namespace epsray {

// Trust of cells[first, end) from cam, and their ownership of the pixels not owned yet
// (first == 0: of every pixel; owner is rewritten). With a raster and first == 0, OSMesa
// draws the ownership in the calling thread; otherwise the exact per-pixel method. With a
// pool the work runs on its workers, without one in the calling thread.
// With a mirror, cam is its mirrored eye and the cells are trusted by trust_from_mirror.
void reproject_cells(workers* pool, const world& w, const camera& cam, const std::vector<cell_ref>& cells,
                     std::size_t first, face_raster* raster, std::vector<cell_trust>& trusted, std::int32_t* owner,
                     const mirror_view* mirror = nullptr);

// A frame's reprojection prepared ahead of it (reprojection_state::ahead).
struct reprojection_ahead {
  std::future<void> job;        // running on its own thread; joined before the frame ends
  camera cam;                   // the eye it is for
  std::vector<cell_ref> cells;  // the cells it reprojected: the frame before last's
  std::vector<cell_trust> trusted;
  std::vector<std::int32_t> owner;
  double ms = 0;                // its wall time, off the critical path
  bool ready = false;           // joined, and for `cam`
};

// Starts preparing `next` from `cells` (copied) on a thread of its own.
void start_ahead(reprojection_ahead& a, const world& w, const camera& next, const std::vector<cell_ref>& cells,
                 face_raster* raster);

// Waits for the preparation; returns the milliseconds waited (the part not overlapped).
double finish_ahead(reprojection_ahead& a);

}  // namespace epsray
