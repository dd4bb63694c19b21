#include "reproject_frame.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

namespace epsray {

namespace {

// for_each(n, f) on the pool's workers, or in this thread without a pool.
template <class F>
void each(workers* pool, std::size_t n, F&& f) {
  if (pool)
    tbb::parallel_for(std::size_t(0), n, f);
  else
    for (std::size_t i = 0; i < n; ++i) f(i);
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

void reproject_cells(workers* pool, const world& w, const camera& cam, const std::vector<cell_ref>& cells,
                     std::size_t first, face_raster* raster, std::vector<cell_trust>& trusted, std::int32_t* owner,
                     const mirror_view* mirror) {
  trusted.resize(cells.size());
  // Every band of rows scans the whole cell list, so bands are few: about four per thread,
  // not the frame's tiles (one-row tiles at 16 threads made 480 scans of 5,000 cells). A
  // pixel's owner is the first trusted cell covering it, however the rows are banded.
  const int band_rows = pool ? std::max(8, cam.height / (4 * pool->threads())) : cam.height;
  const std::vector<tile> bands = make_tiles(cam.height, band_rows);
  const bool draw = raster && first == 0;
  std::vector<pixel_rect> rects(draw ? 0 : cells.size());
  // OSMesa: the cells' triangles made in chunks, in parallel, then drawn in this thread
  // (the context's), last chunk first so that the first listed cell is drawn last.
  constexpr std::size_t chunk = 256;
  std::vector<std::vector<float>> xy(draw ? (cells.size() + chunk - 1) / chunk : 0);
  std::vector<std::vector<std::uint32_t>> rgba(xy.size());
  auto work = [&] {
    each(pool, cells.size() - first, [&](std::size_t k) {
      const std::size_t i = first + k;
      trusted[i] = mirror ? trust_from_mirror(w, cells[i], *mirror) : trust_from(w, cells[i], cam.origin);
      if (trusted[i].ok && !draw) rects[i] = raster_rect(cam, cell_screen_box(cam, cells[i].lt->fp, *cells[i].node));
    });
    if (draw)
      each(pool, xy.size(), [&](std::size_t c) {
        cell_triangles(cam, cells, trusted, c * chunk, std::min(cells.size(), (c + 1) * chunk), xy[c], rgba[c]);
      });
    else
      each(pool, bands.size(), [&](std::size_t i) {
        splat_rows(cam, cells, trusted, rects, bands[i].y0, bands[i].y1, owner, first);
      });
  };
  if (pool)
    pool->run(work);
  else
    work();
  if (draw) {
    std::vector<float> all_xy;
    std::vector<std::uint32_t> all_rgba;
    for (std::size_t c = xy.size(); c-- > 0;) {
      all_xy.insert(all_xy.end(), xy[c].begin(), xy[c].end());
      all_rgba.insert(all_rgba.end(), rgba[c].begin(), rgba[c].end());
    }
    raster->draw(cam, all_xy, all_rgba, owner);
  }
}

void start_ahead(reprojection_ahead& a, const world& w, const camera& next, const std::vector<cell_ref>& cells,
                 face_raster* raster) {
  a.cam = next;
  a.cells = cells;
  a.ready = false;
  a.owner.resize(std::size_t(next.width) * std::size_t(next.height));
  a.job = std::async(std::launch::async, [&a, &w, raster] {
    const auto t0 = std::chrono::steady_clock::now();
    reproject_cells(nullptr, w, a.cam, a.cells, 0, raster, a.trusted, a.owner.data());
    a.ms = ms_since(t0);
  });
}

double finish_ahead(reprojection_ahead& a) {
  if (!a.job.valid()) return 0;
  const auto t0 = std::chrono::steady_clock::now();
  a.job.get();  // rethrows what the thread threw
  a.ready = true;
  return ms_since(t0);
}

}  // namespace epsray
