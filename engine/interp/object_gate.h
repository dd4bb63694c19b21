// Whether an object's linetrees pay (section 3 of docs/walkthroughs.md): a count-based
// choice per object, made after each frame for the next ones. A pixel served by a cell
// saves the rays the reference would cast for it (its cell's corner tree, tree_rays) less
// the rays it still casts (deferred lights and secondary rays) and what its path costs
// (a lookup, an interpolation, a span); a traced pixel that looked up a tree lost the
// lookup; a moving camera's builds cost 16 corner lines each. An object whose cells lost
// more than half a ray a pixel is traced, with no linetree, for the next frames, and tried again
// after 8, 16, 32 and then every 64 frames. Everything counted is an integer that does not
// depend on the threads (a build is counted by the call that published it, which exactly
// one call does), so images do not depend on threads or timing.
#pragma once
#include <cstdint>
#include <vector>

namespace epsray {

struct pixel_result;  // interp/interp_shade.h

// One object's counts over part of a frame.
struct gate_tally {
  std::uint64_t fast = 0, span = 0, interp = 0;  // pixels served from its cells, by path
  std::uint64_t saved = 0;   // the tree_rays of those pixels' cells
  std::uint64_t own = 0;     // the rays those pixels cast themselves
  std::uint64_t traced = 0;  // pixels that looked up its linetree and were traced
  std::uint64_t traced_rays = 0;
  std::uint64_t builds = 0;  // cells published for it
  gate_tally& operator+=(const gate_tally& o);
};

struct gate_entry {
  int prim = -1;
  gate_tally t;
};

// The weights of the gate's cost model, in rays: what each path costs beyond the rays it
// casts, from the measured per-path costs (docs/walkthroughs.md, section 3: an interpolated
// pixel's lookup and interpolation cost about 0.23 of a traced pixel of 3-4 rays, a fast
// pixel with nothing deferred 0.13, a span-filled one 0.05). Heavier weights turned off
// objects that paid: the art-room walk took 1.055 of the time with 1.5, 0.2, 1.5.
struct gate_weights {
  double fast = 0.6, span = 0.1, interp = 0.8, failed_lookup = 0.5;
  double corner_share = 0.5;  // of a build's 16 corner lines, those traced (the rest are shared)
};

// The gain of an object's cells over a frame, in rays (negative: they cost more than they saved).
double gate_gain(const gate_tally& t, bool moving, const gate_weights& wt = {});

// What one pixel adds to the tally of the object it looked up: `own`, the rays it cast
// itself (builds excluded). `reprojecting` (full mode): an interpolated pixel is counted
// as the fast one it becomes once its cell is reprojected, or a cold frame (all
// interpolated) would judge every object by a path it leaves after one frame.
void gate_count(gate_tally& g, const pixel_result& r, std::uint64_t own, bool reprojecting);

// An object is turned off when its gain is below -gate_margin rays per pixel it covered.
constexpr double gate_margin = 0.5;

// Whole frames: when the cells of the objects still on saved (gate_gain summed) under
// plain_gain of the rays a base frame would cast (the frame's own rays plus those saved),
// the next frames are plain: every pixel traced with no owner buffer, reprojection or
// lookup, 8, then 16, 32 and 64 frames, then a frame with cells again. Full mode's
// machinery costs every pixel (its traced pixels cost 6-10% more than base ones), which the
// cells' savings must pay. Measured (share of a base frame's rays saved, full against
// base): teapot-s6, rings-s3 and mount-s4 walks -0.02-0.06, 0.8-0.9x; gears-s2 0.14-0.17,
// 0.92-0.98x; the art room at 400x300 0.23-0.29, about 1.0x; balls-s3 0.38-0.50, 1.1x; the
// art room at 800x600 0.35-0.59, 1.34x (docs/walkthroughs.md, section 3).
constexpr double plain_gain = 0.2;
constexpr double allowance_share = 0.1;

class object_gate {
 public:
  void resize(std::size_t prims);
  bool enabled() const { return !off_until_.empty(); }
  // Is prim traced, with no linetree, in the coming frame? `box_pixels`: what its box covers
  // on this frame's screen (cell_screen.h). An object that has come 4 times larger on
  // screen than when it was turned off (a teleport, a close-up) is tried again at once: a
  // decision made for one view says little about a view its cells would serve far more of.
  bool off(int prim, float box_pixels) const {
    const std::size_t i = std::size_t(prim);
    return frame_ < off_until_[i] && !(box_pixels > 4 * off_pixels_[i]);
  }
  // After a frame: its tallies (any order; entries of one prim are summed), whether the
  // camera moved (builds count only then: a resting camera keeps its cells), and each
  // object's box_pixels in that frame.
  // `frame_rays`: the rays the frame cast, for plain_gain (0: no plain frames).
  void update(const std::vector<gate_entry>& tallies, bool moving, const float* box_pixels,
              std::uint64_t frame_rays = 0);
  std::size_t objects_off() const;
  // Does the coming frame, one with cells, follow none (a walk's first frame, the first
  // after plain frames)? Then the gate has no counts of this view, and a probe of a sparse
  // grid of its pixels (sched/frame_probe.h) tells whether its cells would pay before they
  // are built for every pixel.
  bool probe_due() const { return enabled() && !counted_; }
  // The probe's tallies and the rays its pixels cast (builds excluded): when the gains of
  // the objects it would keep on come under plain_gain, as update() judges a frame, the
  // coming frame and the next are plain (true), with the waits update() would give. Those
  // frames trace under the allowance when it bounded at least allowance_share of the rays
  // it could cast on the probe's pixels (`bounded`, `cast`, as plain_done takes them).
  bool probe(const std::vector<gate_entry>& tallies, std::uint64_t rays, std::uint64_t bounded,
             std::uint64_t cast);
  // Is the coming frame plain (plain_gain)? plain_done() after rendering it so.
  bool plain() const { return plain_left_ > 0; }
  // Does a plain frame trace under the pixels' allowance (shade_within), or exactly? The
  // allowance's checks cost every light and secondary ray; they pay where they bound many
  // (mount-s4's glass: 19% of the rays it might cast, 1.07x base), not where they bound few
  // (gears-s2 2%, teapot-s6 4%: slower than exact). So after a plain frame that bounded
  // under allowance_share, the next 8 plain frames are exact, then it is tried again.
  bool plain_allowance() const { return allowance_wait_ == 0; }
  // After a plain frame: the rays its allowance bounded and those it cast (shadow and
  // secondary; 0 and 0 for an exact one).
  void plain_done(std::uint64_t bounded, std::uint64_t cast);

 private:
  std::uint32_t frame_ = 0;
  std::vector<std::uint32_t> off_until_;  // the frame from which the object has linetrees again
  std::vector<std::uint8_t> strikes_;     // times turned off: the next retry waits longer
  std::vector<float> off_pixels_;         // box_pixels when turned off
  std::uint32_t plain_left_ = 0;          // plain frames still to come
  std::uint8_t plain_strikes_ = 0;        // times frames went plain in a row of low gains
  std::uint32_t allowance_wait_ = 0;      // exact plain frames before the allowance is tried again
  bool counted_ = false;                  // the last frame had cells and update() counted them
  // Sums the tallies per object into sum_; the gain of those kept on, and (apply) turns
  // off those that lost.
  double judge(const std::vector<gate_entry>& tallies, bool moving, const float* box_pixels, bool apply);
  void go_plain();
  std::vector<gate_tally> sum_;           // judge's scratch
  std::vector<int> touched_;
};

}  // namespace epsray
