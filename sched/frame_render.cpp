#include "frame_render.h"

#include <oneapi/tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>
#include <vector>

#include "shade/shade_rows.h"
#include "cycle_clock.h"
#include "tiles.h"

namespace epsray {

const char* mode_name(render_mode m) {
  switch (m) {
    case render_mode::base: return "base";
    case render_mode::interp: return "interp";
    case render_mode::full: return "full";
  }
  return "?";
}

bool parse_mode(const std::string& s, render_mode& out) {
  if (s == "base") return out = render_mode::base, true;
  if (s == "interp") return out = render_mode::interp, true;
  if (s == "full") return out = render_mode::full, true;
  return false;
}

namespace {

struct tile_totals {
  ray_counts rays;
  pixel_counts pixels;
  std::uint64_t ticks_interp = 0, ticks_base = 0;
};

void shade_tile_interp(const interp_frame& f, const tile& t, image& out, image* reasons, tile_totals& tot) {
  trace_state st;
  interp_scratch scratch;
  for (int y = t.y0; y < t.y1; ++y) {
    std::uint64_t c0 = cycle_now();
    for (int x = 0; x < f.cam->width; ++x) {
      pixel_result r = shade_pixel_interp(f, x, y, st, scratch);
      out.at(x, y) = r.L;
      if (reasons) reasons->at(x, y) = reason_colour(r.reason);
      const bool interp = r.path == pixel_path::interp;
      (interp ? tot.pixels.interp : tot.pixels.base) += 1;
      const std::uint64_t c1 = cycle_now();
      (interp ? tot.ticks_interp : tot.ticks_base) += c1 - c0;
      c0 = c1;
    }
  }
  tot.rays = st.counts;
}

}  // namespace

frame_result render_frame(workers& pool, const world& w, const camera& cam, const frame_params& p) {
  if (p.mode == render_mode::full) throw std::logic_error("mode 'full' is not implemented yet (reprojection comes with walkthroughs)");
  if (p.mode == render_mode::interp && !p.trees) throw std::logic_error("interp mode needs a linetree set");
  const double tick_ms = ticks_per_ms();
  auto t0 = std::chrono::steady_clock::now();
  frame_result out;
  out.img = image(cam.width, cam.height);
  if (p.reasons) out.reasons = image(cam.width, cam.height);
  int rows = p.tile_rows > 0 ? p.tile_rows : default_tile_rows(cam.height, pool.threads());
  std::vector<tile> tiles = make_tiles(cam.height, rows);
  std::vector<tile_totals> totals(tiles.size());
  std::vector<ray_tree_store> trees(p.keep_ray_trees ? tiles.size() : 0);
  interp_frame f{&w, p.trees, &cam, p.interp};
  pool.run([&] {
    tbb::parallel_for(size_t(0), tiles.size(), [&](size_t i) {
      if (p.mode == render_mode::base) {
        const std::uint64_t c0 = cycle_now();
        trace_state st;
        shade_rows_base(w, cam, tiles[i].y0, tiles[i].y1, out.img, st, p.keep_ray_trees ? &trees[i] : nullptr);
        totals[i].rays = st.counts;
        totals[i].pixels.base = std::uint64_t(tiles[i].y1 - tiles[i].y0) * std::uint64_t(cam.width);
        if (p.reasons)
          for (int y = tiles[i].y0; y < tiles[i].y1; ++y)
            for (int x = 0; x < cam.width; ++x) out.reasons.at(x, y) = reason_colour(pixel_reason::traced);
        totals[i].ticks_base = cycle_now() - c0;
      } else {
        shade_tile_interp(f, tiles[i], out.img, p.reasons ? &out.reasons : nullptr, totals[i]);
      }
    });
  });
  for (const tile_totals& t : totals) {
    out.rays += t.rays, out.pixels += t.pixels;
    out.path_ms.interp += double(t.ticks_interp) / tick_ms, out.path_ms.base += double(t.ticks_base) / tick_ms;
  }
  for (const ray_tree_store& t : trees) out.trees.append(t);
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  // After the clock: measuring linetree memory walks every node.
  out.memory_bytes = out.img.pixels.capacity() * sizeof(glm::vec3) + out.trees.bytes() +
                     (p.trees ? p.trees->bytes() : 0);
  return out;
}

}  // namespace epsray
