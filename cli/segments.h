// How `mpirun -np K epsray walk` splits a camera path over its K ranks (docs/mpi.md): into
// contiguous segments, so that frame-to-frame coherence survives inside each, balanced by
// an estimate of each frame's cost rather than by frame count. The estimate reads only the
// cameras, so every rank computes the same segments without talking to the others.
#pragma once
#include <vector>

#include "scene/scene.h"

namespace epsray {

// Frames first..last; empty (last < first) for a rank left without frames.
struct segment {
  int first = 0, last = -1;
  int frames() const { return last - first + 1; }
};

// A frame's cost in units of a warm frame whose camera did not move. A cold frame is the
// first of a segment, a teleport or a keyframe: it starts with no linetrees and no cells
// to reproject. A warm frame costs more the further the camera moved since the frame
// before: motion is the step over the path's median step plus the turn over its median
// turn (each term only where that median is not zero), capped at max_motion.
struct frame_cost_model {
  double cold = 3.0;         // measured: the art room's first frame against its next ones (docs/mpi.md)
  double per_motion = 0.2;   // added per unit of motion
  double max_motion = 5.0;
  // A teleport: a step over teleport_steps median steps, or a turn over teleport_degrees.
  double teleport_steps = 10.0;
  double teleport_degrees = 30.0;
};

// Per frame: what it costs when it starts a segment (cold), and otherwise. A teleport and
// a keyframe (with keyframe N > 0, every frame whose index is a multiple of N) cost the
// cold cost either way.
struct frame_costs {
  std::vector<double> cold, warm;
  std::vector<bool> teleport;
};
frame_costs estimate_frame_costs(const std::vector<camera_view>& frames, int keyframe,
                                 const frame_cost_model& m = {});

// The cost of frames first..last rendered as one segment.
double segment_cost(const frame_costs& c, int first, int last);

// `parts` contiguous segments covering every frame in order, minimising the largest
// segment cost; with keyframe N > 0 every segment starts at a multiple of N. Where moving
// a boundary onto a teleport keeps the largest cost, the teleport starts the segment.
// Fewer frames (or keyframe blocks) than parts: the last segments are empty.
std::vector<segment> split_path(const frame_costs& c, int parts, int keyframe);

}  // namespace epsray
