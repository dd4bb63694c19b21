#include "frame_render.h"

#include <oneapi/tbb/parallel_for.h>

#include <chrono>
#include <stdexcept>
#include <vector>

#include "shade/shade_rows.h"
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

frame_result render_frame(workers& pool, const world& w, const camera& cam, const frame_params& p) {
  if (p.mode != render_mode::base)
    throw std::logic_error(std::string("mode '") + mode_name(p.mode) + "' is not implemented yet");
  auto t0 = std::chrono::steady_clock::now();
  frame_result out;
  out.img = image(cam.width, cam.height);
  int rows = p.tile_rows > 0 ? p.tile_rows : default_tile_rows(cam.height, pool.threads());
  std::vector<tile> tiles = make_tiles(cam.height, rows);
  std::vector<ray_counts> counts(tiles.size());
  std::vector<ray_tree_store> trees(p.keep_ray_trees ? tiles.size() : 0);
  pool.run([&] {
    tbb::parallel_for(size_t(0), tiles.size(), [&](size_t i) {
      trace_state st;
      shade_rows_base(w, cam, tiles[i].y0, tiles[i].y1, out.img, st, p.keep_ray_trees ? &trees[i] : nullptr);
      counts[i] = st.counts;
    });
  });
  for (const ray_counts& c : counts) out.rays += c;
  for (const ray_tree_store& t : trees) out.trees.append(t);
  out.pixels.base = std::uint64_t(cam.width) * std::uint64_t(cam.height);
  out.memory_bytes = out.img.pixels.capacity() * sizeof(glm::vec3) + out.trees.bytes();
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace epsray
