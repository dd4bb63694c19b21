// Span filling in screen space (section 6). Along a scan line, the pixels one cell owns
// form a single run (reproject.h), and there the cell's interpolant is a smooth function of
// the pixel's x: each of the line's four coordinates is a ratio of two linear functions of
// x with one common denominator. So a segment of the run is filled by interpolating
// linearly, in screen space, between the interpolant's values at the segment's two end
// pixels, as the paper does. The paper ignored the error this adds; here it is bounded
// (span_error: the interpolant's first and second differences times the ratios'
// derivatives), and each span-filled pixel must pass the same test as any other with the
// cell's proven error plus this one, so the guarantee covers span-filled pixels too.
//
// Only plain cells are span-filled: untextured, leaving nothing to per-pixel rays, with no
// candidate occluder to test. Their pixels need no ray at all; the others keep fill_pixel.
#pragma once
#include <cstdint>

#include "reproject/reproject.h"

namespace epsray {

// The interpolant's largest first and mixed second differences over its 16 corners, per
// channel: bounds of |dQ/dt_i| and |d2Q/dt_i dt_j| over the whole cell (Q is multilinear,
// so each derivative is a convex combination of such differences; d2Q/dt_i^2 = 0).
struct corner_differences {
  glm::vec3 d1[4];
  glm::vec3 d2[4][4];
};
corner_differences corner_differences_of(const glm::vec3 v[16]);

// On row y between pixels xa < xb, both of whose lines lie in cell c: |L''(x)| <= m2 per
// channel, where L(x) is the interpolant at pixel x's exact line, and `rounding` bounds how
// far the float lines the pixels' own eye rays give (the ones their end values and the
// reference use) may move L. So a pixel x of the segment is within
// (x - xa)(xb - x) / 2 * m2 + 2 * rounding of the straight line between the end values,
// besides the cell's own error. Infinite when the segment is not one the bound covers.
struct span_bound {
  glm::vec3 m2{0};
  glm::vec3 rounding{0};
};
span_bound span_error(const camera& cam, const cell_ref& c, const corner_differences& d, int y, int xa, int xb);

// Whether a trusted cell's pixels may be span-filled.
bool span_fillable(const cell_ref& c, const cell_trust& t);

// Pixels x0..x1 (inclusive) of row y, all owned by the plain cell c, in segments of at most
// `segment` pixels: L[x - x0] and ok[x - x0] (1: passed the bound; 0: the pixel takes the
// per-pixel path, fill_pixel and then the interpolate path). Returns the pixels passed.
int fill_span(const camera& cam, const cell_ref& c, int y, int x0, int x1, int segment, float eps, glm::vec3* L,
              std::uint8_t* ok);

}  // namespace epsray
