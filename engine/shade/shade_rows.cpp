#include "shade/shade_rows.h"

#include <limits>

namespace epsray {

void shade_rows_base(const world& w, const camera& cam, int y0, int y1, image& out, trace_state& st,
                     ray_tree_store* trees) {
  ray_tree scratch;  // reused for every pixel of the band
  ray_tree* saved = st.tree;
  if (trees) st.tree = &scratch;
  for (int y = y0; y < y1; ++y) {
    for (int x = 0; x < cam.width; ++x) {
      ray r = eye_ray(w, cam, eye_direction(cam, float(x), float(y)));
      out.at(x, y) = trace_eye(w, r, st);
      if (trees) trees->append(scratch);
    }
  }
  st.tree = saved;
}

vec3 shade_pixel_within(const world& w, const camera& cam, int x, int y, float eps, trace_state& st) {
  const ray r = eye_ray(w, cam, eye_direction(cam, float(x), float(y)));
  ++st.counts.eye;
  hit h;
  return closest_hit(w, r, std::numeric_limits<float>::infinity(), h) ? shade_within(w, r, h, eps, st) : w.background;
}

void shade_rows_within(const world& w, const camera& cam, int y0, int y1, float eps, image& out, trace_state& st) {
  for (int y = y0; y < y1; ++y)
    for (int x = 0; x < cam.width; ++x) out.at(x, y) = shade_pixel_within(w, cam, x, y, eps, st);
}

}  // namespace epsray
