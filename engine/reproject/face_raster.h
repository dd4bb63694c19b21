// Reprojection through OSMesa (the paper's section 6.1, `--reproject osmesa`): each trusted
// cell is drawn from the new eye, with its index as its colour, as the region of the screen
// whose eye lines cross both of its faces (the overlap of the two faces' projections), in
// reverse list order, so that the pixel keeps the first listed cell that covers it: the
// ownership rule of the exact method (splat_rows), decided by Mesa's rasterizer instead of
// per-pixel tests. Drawing the faces' overlap, not the faces one by one with conflict
// detection, leaves no false conflicts between sibling cells that share a face.
//
// Rasterization rounds at the regions' edges, so a pixel may be given a cell its line just
// misses: fill_pixel tests every pixel's own line again, and such a pixel takes the
// interpolate path. OSMesa is loaded at run time (dlopen) and its GL entry points are
// fetched through OSMesaGetProcAddress, so its gl* symbols never meet the viewer's GL in
// one executable (../shared/docs/dependencies.md).
#pragma once
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "reproject/reproject.h"

namespace epsray {

// One OSMesa context and its frame buffer. Not thread-safe: one frame at a time, from any
// one thread at a time.
class face_raster {
 public:
  // Null, with the reason in `why`, when OSMesa cannot be loaded or gives no context.
  static std::unique_ptr<face_raster> open(std::string& why);
  ~face_raster();
  face_raster(const face_raster&) = delete;
  face_raster& operator=(const face_raster&) = delete;

  // owner[y * width + x]: the first trusted cell (in list order) whose region covers pixel
  // (x, y), or -1; all in the calling thread. Returns the number of triangles drawn.
  std::size_t owners(const camera& cam, const std::vector<cell_ref>& cells, const std::vector<cell_trust>& trusted,
                     std::int32_t* owner);

  // The same from triangles made beforehand (cell_triangles, in parallel by the caller):
  // draws them in order, later ones over earlier ones.
  void draw(const camera& cam, const std::vector<float>& xy, const std::vector<std::uint32_t>& rgba,
            std::int32_t* owner);

  struct gl;  // the entry points, private to face_raster.cpp

 private:
  face_raster() = default;
  void* lib_ = nullptr;
  void* ctx_ = nullptr;
  std::unique_ptr<gl> gl_;
  std::vector<std::uint32_t> buffer_;  // RGBA8, bottom row first (OSMesa's default)
};

// Appends the triangles of the trusted cells among cells[first, last), last listed first
// (so that drawn in order the first listed ends on top): vertices in window coordinates
// (two floats each) and, per vertex, the cell's colour (its index + 1, RGBA8 in memory).
void cell_triangles(const camera& cam, const std::vector<cell_ref>& cells, const std::vector<cell_trust>& trusted,
                    std::size_t first, std::size_t last, std::vector<float>& xy, std::vector<std::uint32_t>& rgba);

// The screen regions of a cell (exposed for tests): convex polygons in window coordinates
// (x right from the left edge, y up from the bottom, pixel centres at half-integers) whose
// union holds the pixel centres whose eye lines cross both faces and lie in the view (and,
// for a cell that needs a face check, meet the face's rectangle in front of the eye).
// Appends each polygon's vertex count to `counts` and its vertices to `xy`.
void cell_regions(const camera& cam, const facepair& fp, const lt_node& n, std::vector<int>& counts,
                  std::vector<float>& xy,
                  const cell_trust* trust = nullptr);

}  // namespace epsray
