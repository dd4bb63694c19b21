// The interpolate path (section 8.3, path 2): a visibility ray finds the object, its
// linetree gives the cell, and the cell's interpolant gives the radiance when the proven
// bound meets epsilon for this pixel; otherwise the pixel is traced.
#pragma once
#include <array>
#include <cstdint>
#include <memory>

#include "image/image.h"
#include "interp/linetree.h"
#include "scene/camera.h"
#include "shade/whitted.h"

namespace epsray {

struct mirror_use;  // engine/reproject/mirror.h

struct interp_params {
  float eps = 0.05f;
  float min_cell_pixels = 16;  // no subdivision into children covering fewer pixels
  float failed_split_pixels = 0;  // ... nor, after a discontinuity or a miss, fewer than these
  float max_cell_pixels = 4096;  // larger cells are subdivided without building an interpolant
  float defer_pixels = 256;    // cells under these pixels may leave lights and secondary
                               // rays they cannot prove to per-pixel rays
  // The same three while the camera moves (frame_params::camera_moving): a moving eye needs
  // new cells along every edge each frame, and a cell it builds serves a few frames, so
  // there tracing a pixel or casting its shadow rays costs less than building and proving
  // small cells. A resting camera builds them once and keeps them (the art-room walk took
  // 0.935 of the time with these, perf/pair.py; a still camera's frames unchanged).
  float moving_min_cell_pixels = 32;
  float moving_failed_split_pixels = 128;
  float moving_defer_pixels = 1024;
  int max_depth = 16;          // halvings of any axis below the root (floats keep ~7 digits)
  // Primitives whose box covers fewer pixels on screen are traced, with no linetree: the
  // 16 corner lines and the bound of each cell cost more than a few dozen pixels save,
  // and an object that small is mostly silhouette (an SPD scene's thousand triangles).
  float min_prim_pixels = 1024;
  // Full: objects whose cells cost more than they save, by the counts of the last frame,
  // are traced for the next frames (object_gate.h); false: every object keeps its linetrees.
  bool object_gate = true;
  // Full, with the object gate: whole frames traced plainly while cells pay too little
  // (object_gate.h, plain_gain).
  bool plain_frames = true;
  bool four_way = true;        // halve only the axes the failure points at (section 8.6)
  // Full: runs of a plain cell's pixels are span-filled in screen space, in segments of at
  // most this many pixels (engine/reproject/span_fill.h); 0: every pixel evaluates its cell.
  int span_segment = 32;
  // The depth of the rays whose lines the trees hold: 1, eye lines; 2, a planar reflector's
  // reflected lines (engine/reproject/mirror.h), whose cells defer nothing.
  int build_depth = 1;
  // Full: a planar reflector's deferred reflections through the mirrored eye
  // (engine/reproject/mirror.h); false: traced per pixel. Off by default: on the art-room
  // walk it serves 64% of the floor's deferred reflections from reprojected cells with zero
  // pixels over epsilon, but took 1.014 of the time at 800x600 (perf/pair.py, one thread).
  bool mirror = false;
  // Interp and full: shadow rays tested against the light cache's lists of what may block
  // them (accel/light_cache.h), which give the BVH's answer; false: each walks the BVH.
  bool light_cache = true;
};

// How a pixel got its radiance, and why an interpolant was not used.
enum class pixel_path : std::uint8_t { fast, interp, base };
enum class pixel_reason : std::uint8_t {
  interpolated,     // success
  discontinuity,    // cell_reason values, in the same order
  missed,
  blocked,
  nonlinear,
  traced,           // base-traced for another reason: background, eye behind the face, ...
  reprojected,      // full mode: span-filled from a reprojected cell
};

// Per-thread scratch for building interpolants: reused, never reallocated per ray.
struct interp_scratch {
  std::array<ray_tree, 16> trees;
  // The last leaf found: neighbouring pixels mostly fall in the same cell, so the lookup
  // starts there when the line lies strictly inside it (the same leaf a descent from the
  // root would reach).
  const linetree* hint_tree = nullptr;
  lt_node* hint = nullptr;
};

struct interp_frame {
  const world* w = nullptr;
  linetree_set* trees = nullptr;
  const camera* cam = nullptr;
  interp_params p;
  // Per primitive, nonzero when its box covers under p.min_prim_pixels on screen
  // (small_primitives); null: none is.
  const std::uint8_t* small = nullptr;
  // Per primitive, nonzero when the object gate traces it this frame (also set in small);
  // full mode does not reproject its cells. Null: none.
  const std::uint8_t* off = nullptr;
  // Interp and full: the trees' light cache (accel/light_cache.h) for every shadow ray the
  // frame casts outside builds; null: the BVH walks them all.
  const light_cache* lights = nullptr;
};

// Marks the primitives whose boxes cover fewer than min_pixels pixels of the image from
// this camera (box_pixels), for interp_frame::small.
void small_primitives(const world& w, const camera& cam, float min_pixels, size_t first, size_t last,
                      std::uint8_t* small);

// A cell that gave pixels their radiance: what reprojection carries to the next frame.
struct cell_ref {
  const linetree* lt = nullptr;
  const lt_node* node = nullptr;
  const interpolant* ip = nullptr;
  int prim = -1;
};

struct pixel_result {
  glm::vec3 L{0};
  pixel_path path = pixel_path::base;
  pixel_reason reason = pixel_reason::traced;
  cell_ref cell;  // path interp or fast: the cell used
  // The primitive whose linetree the pixel looked up (the eye ray's hit), -1 when it
  // needed none: what the object gate charges a traced pixel's failed lookup to.
  int gate_prim = -1;
};

// The object the gate charges a pixel to (object_gate.h): its cell's object (a box for a
// face's cell), else the primitive it looked up; -1: none.
inline int tallied_prim(const world& w, const pixel_result& r) {
  return r.cell.ip ? scene_prim_of(w, r.cell.prim) : r.gate_prim;
}

pixel_result shade_pixel_interp(const interp_frame& f, int x, int y, trace_state& st, interp_scratch& scratch,
                                mirror_use* mu = nullptr);

// The leaf that line x4 of prim's tree lt ends in under the frame's cost model (f.cam's
// screen), building interpolants and splitting cells on the way; ip is its interpolant
// (never null). Marks the leaf used in this frame.
lt_node* find_cell(const interp_frame& f, linetree& lt, int prim, const float x4[4], trace_state& st,
                   interp_scratch& scratch, const interpolant*& ip);

// The first step of every pixel that may be interpolated: the visibility ray, and the line
// it lies on in its object's linetree. lt is null when the pixel needs no tree: `out`
// then holds its radiance (the background, or traced: eps 0, a line whose first hit is not
// the eye ray's, rounding at the root's edge).
struct pixel_line {
  ray r;
  hit h;
  int prim = -1;  // whose linetree lt is: h.prim, or the face rectangle of a box's face
  linetree* lt = nullptr;
  float x4[4] = {0, 0, 0, 0};
};
pixel_line find_pixel_line(const interp_frame& f, int x, int y, trace_state& st, pixel_result& out);

// Is the proven bound within epsilon for every line of the cell (textured cells: decided
// per line)?
bool cell_accurate(const interpolant& ip, float eps);
// The per-pixel test of whitted.md 6 for interpolated radiance La with proven error E (per
// channel): the relative error is within eps, with a margin for float rounding.
bool within(glm::vec3 La, glm::vec3 E, float eps);
// Is an eye ray's first hit on the shape the first hit of its line after the front plane
// (the one the interpolant holds)?
bool same_first_hit(const shape& s, const facepair& fp, glm::vec3 eye);
// The interpolated radiance of the line x4 of cell n, when the bound meets epsilon for it.
// r is the pixel's eye ray, t_hit where it meets prim: the deferred lights' shadow rays
// leave from there.
// With mu (full mode, pixel (px, py)): a deferred reflection off the frame's planar
// reflector comes from a mirror cell where one serves (engine/reproject/mirror.h).
bool interpolate_line(const world& w, int prim, const lt_node& n, const interpolant& ip, const float x4[4], float eps,
                      const ray& r, float t_hit, trace_state& st, glm::vec3& L, mirror_use* mu = nullptr,
                      int px = 0, int py = 0);

// The interpolant of cell n of prim's facepair fp: its 16 extremal lines traced against the
// object alone (through the shared sample cache), then the topology test and the error
// predicate. terminal: n will not be split, so stop at the first two differing corners.
// With `defer`, the root's lights whose visibility differs or cannot be proven are left
// to per-pixel shadow rays, and its reflected and transmitted subtrees to per-pixel rays.
// predicate false (the light-field baseline, engine/baselines): no topology test and no
// bound; only corners that miss the object still fail the cell.
std::unique_ptr<interpolant> build_interpolant(const world& w, int prim, const facepair& fp, const lt_node& n,
                                               bool terminal, bool defer, sample_cache& cache,
                                               trace_state& st, interp_scratch& scratch, bool predicate,
                                               int depth = 1);

// The paper's colours for the error-coded image.
glm::vec3 reason_colour(pixel_reason r);

}  // namespace epsray
