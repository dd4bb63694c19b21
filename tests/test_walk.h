// A walk for the tests that drive render_frame directly: fresh linetrees and reprojection
// state, the camera of each frame from camera_at(k), each frame checked against the
// reference when asked (zero pixels over eps).
#pragma once
#include <gtest/gtest.h>

#include <functional>
#include <vector>

#include "sched/frame_render.h"
#include "sched/verify.h"

namespace epsray::test {

inline std::vector<frame_result> verified_walk(const world& w, frame_params p, int frames, int threads, bool verify,
                                               const std::function<camera(int)>& camera_at) {
  linetree_set trees(w.prim_bounds);
  reprojection_state reproj;
  workers pool(threads);
  p.trees = &trees, p.reproj = &reproj;
  std::vector<frame_result> out;
  camera last;
  for (int k = 0; k < frames; ++k) {
    const camera cam = camera_at(k);
    p.camera_moving = k > 0 && !same_camera(cam, last);
    last = cam;
    frame_result fr = render_frame(pool, w, cam, p);
    if (verify) {
      const verify_result vr = verify_frame(pool, w, cam, fr.img, p.interp.eps);
      EXPECT_EQ(vr.violations, 0u) << "frame " << k << ", max error " << vr.max_rel_err;
    }
    out.push_back(std::move(fr));
  }
  return out;
}

}  // namespace epsray::test
