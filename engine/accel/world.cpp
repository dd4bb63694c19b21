#include "accel/world.h"

#include "geom/shape_build.h"

namespace epsray {

world make_world(scene s) {
  world w;
  std::vector<bounds> boxes;
  boxes.reserve(s.prims.size());
  for (const primitive& p : s.prims) {
    boxes.push_back(primitive_bounds(s, p));
    w.box.grow(boxes.back());
  }
  w.tree = build_bvh(boxes);
  w.shapes.reserve(s.prims.size());
  for (int src : w.tree.order) {
    w.shapes.push_back(make_shape(s, s.prims[size_t(src)], w.polys));
    w.info.push_back({s.prims[size_t(src)].material, src, s.prims[size_t(src)].kind == prim_kind::patch});
    w.prim_bounds.push_back(boxes[size_t(src)]);
  }
  w.shape_of.resize(s.prims.size());
  for (size_t i = 0; i < w.info.size(); ++i) w.shape_of[size_t(w.info[i].source)] = int(i);
  for (const light& l : s.lights) {
    w.light_pos.push_back(l.position);
    w.light_power.push_back(light_intensity(s, l));
  }
  w.ambient = scene_ambient(s);
  w.background = s.background;
  w.delta = 1e-4f * glm::length(w.box.extent());
  w.sc = std::move(s);
  return w;
}

}  // namespace epsray
