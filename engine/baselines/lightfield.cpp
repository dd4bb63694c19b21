#include "baselines/lightfield.h"

#include <limits>

namespace epsray {

pixel_result shade_pixel_lightfield(const interp_frame& f, int depth, int x, int y, trace_state& st,
                                    interp_scratch& scratch) {
  const world& w = *f.w;
  const camera& cam = *f.cam;
  pixel_result out;
  ray r = make_ray(cam.origin, eye_direction(cam, float(x), float(y)));
  ++st.counts.eye;
  hit h;
  if (!closest_hit(w, r, std::numeric_limits<float>::infinity(), h)) {
    out.L = w.background;
    return out;
  }
  linetree& lt = f.trees->get(h.prim, facepair_of(r.d));
  float x4[4];
  line_coords(lt.fp, r.o, r.d, x4);
  if (!same_first_hit(w.shapes[size_t(h.prim)], lt.fp, cam.origin) || !holds(lt.root, x4)) {
    out.L = shade_hit(w, r, h, 1, st);
    return out;
  }
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
    ip = publish(*node, build_interpolant(w, h.prim, lt.fp, *node, false, f.trees->samples(), st, scratch, false),
                 f.trees->node_bytes());
  mark_used(*node, f.trees->frame());
  if (ip->reason == cell_reason::valid && interpolate_line(w, h.prim, *node, *ip, x4, f.p.eps, out.L)) {
    out.path = pixel_path::interp, out.reason = pixel_reason::interpolated;
    return out;
  }
  out.reason = pixel_reason(int(ip->reason));
  out.L = shade_hit(w, r, h, 1, st);
  return out;
}

}  // namespace epsray
