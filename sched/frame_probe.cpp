#include "frame_probe.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "shade/shade_rows.h"

namespace epsray {

int probe_step(const camera& cam) {
  return std::max(8, int(std::sqrt(double(cam.width) * double(cam.height) / probe_pixels)));
}

frame_probe probe_frame(workers& pool, const interp_frame& f) {
  const camera& cam = *f.cam;
  const int step = probe_step(cam);
  std::vector<frame_probe> rows;
  for (int y = step / 2; y < cam.height; y += step) rows.emplace_back();
  pool.run([&] {
    tbb::parallel_for(size_t(0), rows.size(), [&](size_t j) {
      frame_probe& row = rows[j];
      trace_state st, within;
      st.lights = within.lights = f.lights;
      interp_scratch scratch;
      const int y = step / 2 + int(j) * step;
      for (int x = step / 2; x < cam.width; x += step, ++row.pixels) {
        const std::uint64_t before = st.counts.total() - st.build_rays;
        const pixel_result r = shade_pixel_interp(f, x, y, st, scratch);
        const std::uint64_t own = st.counts.total() - st.build_rays - before;
        row.own_rays += own;
        const int prim = tallied_prim(*f.w, r);
        if (prim < 0) continue;
        gate_entry e{prim, {}};
        gate_count(e.t, r, own, true);
        row.tallies.push_back(e);
      }
      for (int x = step / 2; x < cam.width; x += step) shade_pixel_within(*f.w, cam, x, y, f.p.eps, within);
      row.bounded = within.counts.shadow_bounded + within.counts.secondary_bounded;
      row.cast = within.counts.shadow + within.counts.reflect + within.counts.refract;
      row.rays = st.counts, row.build_ticks = st.build_ticks;
      row.rays += within.counts;
    });
  });
  frame_probe out;
  for (frame_probe& row : rows) {
    out.tallies.insert(out.tallies.end(), row.tallies.begin(), row.tallies.end());
    out.rays += row.rays, out.own_rays += row.own_rays, out.pixels += row.pixels;
    out.build_ticks += row.build_ticks, out.bounded += row.bounded, out.cast += row.cast;
  }
  return out;
}

}  // namespace epsray
