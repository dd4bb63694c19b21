#include "baselines/lightfield.h"

#include <limits>

namespace epsray {

pixel_result shade_pixel_lightfield(const interp_frame& f, int depth, int x, int y, trace_state& st,
                                    interp_scratch& scratch) {
  const world& w = *f.w;
  pixel_result out;
  const pixel_line pl = find_pixel_line(f, x, y, st, out);
  if (!pl.lt) return out;
  linetree& lt = *pl.lt;
  const float* x4 = pl.x4;
  const ray& r = pl.r;
  const hit& h = pl.h;
  lt_node* node = &lt.root;
  for (;;) {
    if (lt_node* kids = node->kids.load(std::memory_order_acquire)) {
      node = child_at(*node, kids, x4);
    } else if (node->depth < depth) {
      node = child_at(*node, subdivide(*node, split_all, f.trees->node_bytes()), x4);
    } else {
      break;
    }
  }
  const interpolant* ip = node->interp.load(std::memory_order_acquire);
  if (!ip)
    ip = publish(*node, build_interpolant(w, pl.prim, lt.fp, *node, false, false, f.trees->samples(), st, scratch, false),
                 f.trees->node_bytes());
  mark_used(*node, f.trees->frame());
  if (ip->reason == cell_reason::valid && interpolate_line(w, pl.prim, *node, *ip, x4, f.p.eps, r, h.t, st, out.L)) {
    out.path = pixel_path::interp, out.reason = pixel_reason::interpolated;
    return out;
  }
  out.reason = pixel_reason(int(ip->reason));
  out.L = shade_hit(w, r, h, 1, st);
  return out;
}

}  // namespace epsray
