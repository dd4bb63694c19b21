#include "frame_render.h"

#include <oneapi/tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <stdexcept>
#include <unordered_set>
#include <vector>

#include "baselines/lightfield.h"
#include "baselines/upsample.h"
#include "interp/cell_screen.h"
#include "reproject/reproject.h"
#include "reproject/span_fill.h"
#include "shade/shade_rows.h"
#include "cycle_clock.h"
#include "frame_probe.h"
#include "tiles.h"

namespace epsray {

const char* mode_name(render_mode m) {
  switch (m) {
    case render_mode::base: return "base";
    case render_mode::interp: return "interp";
    case render_mode::full: return "full";
    case render_mode::upsample: return "upsample";
    case render_mode::reuse: return "reuse";
    case render_mode::lightfield: return "lightfield";
  }
  return "?";
}

bool parse_mode(const std::string& s, render_mode& out) {
  if (s == "base") return out = render_mode::base, true;
  if (s == "interp") return out = render_mode::interp, true;
  if (s == "full") return out = render_mode::full, true;
  if (s == "upsample") return out = render_mode::upsample, true;
  if (s == "reuse") return out = render_mode::reuse, true;
  if (s == "lightfield") return out = render_mode::lightfield, true;
  return false;
}

namespace {

// A cache line of its own: shade_tile_interp counts into it pixel by pixel while the
// threads next door count into their tiles' totals.
struct alignas(64) tile_totals {
  ray_counts rays;
  pixel_counts pixels;
  std::uint64_t ticks_fast = 0, ticks_interp = 0, ticks_base = 0;
  std::uint64_t ticks_deferred = 0;  // within fast and interp
  std::uint64_t ticks_span = 0;      // within fast
  std::uint64_t ticks_build = 0;     // within interp and base
  // frame_params::base_cost: base mode's code on the same pixels, by the same paths.
  std::uint64_t base_fast = 0, base_interp = 0, base_base = 0, base_deferred = 0, base_span = 0;
  std::vector<cell_ref> cells;  // full: the cells this tile's pixels used, for the next frame
  std::vector<gate_entry> gate;  // full: per object, what its cells saved and cost (object_gate.h)
  std::vector<cell_ref> mirror_cells;  // full: the mirror cells this tile's pixels used
  std::uint64_t mirror_filled = 0, mirror_looked_up = 0, mirror_traced = 0;
};

// Last frame's cells seen from the new eye: which pixels each one owns.
struct reprojection_frame {
  const std::vector<cell_ref>* cells = nullptr;
  const std::int32_t* owner = nullptr;  // per pixel, -1: none
  const std::vector<cell_trust>* trust = nullptr;  // per cell
};

// Interp and full modes. Full: a pixel owned by one of last frame's cells is span-filled
// from it; otherwise, and when its bound fails, it takes the interpolate path. Runs of a
// plain cell's pixels are filled in screen space (span_fill.h), the rest pixel by pixel.
void shade_tile_interp(const interp_frame& f, const reprojection_frame* rp, const mirror_frame* mf, int lf_depth,
                       const tile& t, image& out, image* reasons, tile_totals& tot, bool base_cost) {
  trace_state st;
  st.lights = f.lights;
  interp_scratch scratch;
  mirror_use mirror;
  mirror.m = mf;
  mirror_use* mu = mf ? &mirror : nullptr;
  const camera& cam = *f.cam;
  const int segment = f.p.span_segment;
  std::vector<glm::vec3> span_L(rp && segment > 0 ? size_t(cam.width) : 0);
  std::vector<std::uint8_t> span_ok(span_L.size());
  // The object gate's counts, run by run of pixels of one object (neighbours mostly share it).
  const bool gating = rp && f.p.object_gate && f.trees->gate.enabled();
  gate_entry run;
  auto tally = [&](int prim) -> gate_tally& {
    if (run.prim != prim) {
      if (run.prim >= 0) tot.gate.push_back(run);
      run = gate_entry{prim, {}};
    }
    return run.t;
  };
  std::uint64_t rays_before = 0, builds_before = 0;
  auto gate_pixel = [&](const pixel_result& r) {
    const std::uint64_t own = st.counts.total() - st.build_rays - rays_before;
    const int prim = tallied_prim(*f.w, r);
    if (prim < 0) return;
    gate_tally& g = tally(prim);
    g.builds += st.builds - builds_before;
    gate_count(g, r, own, rp != nullptr);
  };
  auto count = [&](const pixel_result& r, std::uint64_t ticks) {
    if (rp && r.cell.node) note_cell(tot.cells, r.cell);
    const bool deferring = r.cell.ip && (r.cell.ip->deferred | r.cell.ip->deferred_rays);
    if (deferring) ++tot.pixels.deferred, tot.ticks_deferred += ticks;
    switch (r.path) {
      case pixel_path::fast: tot.pixels.fast += 1, tot.ticks_fast += ticks; break;
      case pixel_path::interp: tot.pixels.interp += 1, tot.ticks_interp += ticks; break;
      case pixel_path::base: tot.pixels.base += 1, tot.ticks_base += ticks; break;
    }
  };
  // One clock read per pixel (or per span): each pixel's time runs from the last read.
  std::uint64_t clock = cycle_now();
  auto lap = [&] {
    const std::uint64_t now = cycle_now(), ticks = now - clock;
    clock = now;
    return ticks;
  };
  // base_cost: the pixel traced by base mode's code, with a state of its own (no light
  // cache; its last blockers run on from pixel to pixel, as in a base tile), its colour
  // dropped; its time is left out of the path's.
  trace_state base_st;
  auto base_ticks = [&](int x, int y) {
    const std::uint64_t c0 = cycle_now();
    const vec3 L = trace_eye(*f.w, eye_ray(*f.w, cam, eye_direction(cam, float(x), float(y))), base_st);
    asm volatile("" : : "g"(&L) : "memory");  // kept: the trace is what is timed
    clock = cycle_now();
    return clock - c0;
  };
  auto shade_one = [&](int x, int y) {
    pixel_result r;
    if (gating) rays_before = st.counts.total() - st.build_rays, builds_before = st.builds;
    std::int32_t own = rp ? rp->owner[size_t(y) * size_t(cam.width) + size_t(x)] : -1;
    if (own >= 0 && f.off && f.off[size_t(scene_prim_of(*f.w, (*rp->cells)[size_t(own)].prim))]) own = -1;
    if (own >= 0 && fill_pixel(*f.w, cam, (*rp->cells)[size_t(own)], (*rp->trust)[size_t(own)], x, y, f.p.eps, st,
                               r.L, mu)) {
      r.path = pixel_path::fast, r.reason = pixel_reason::reprojected, r.cell = (*rp->cells)[size_t(own)];
    } else if (lf_depth >= 0) {
      r = shade_pixel_lightfield(f, lf_depth, x, y, st, scratch);
    } else {
      r = shade_pixel_interp(f, x, y, st, scratch, mu);
    }
    out.at(x, y) = r.L;
    if (reasons) reasons->at(x, y) = reason_colour(r.reason);
    if (gating) gate_pixel(r);
    count(r, lap());
    if (base_cost) {
      const std::uint64_t b = base_ticks(x, y);
      if (r.cell.ip && (r.cell.ip->deferred | r.cell.ip->deferred_rays)) tot.base_deferred += b;
      (r.path == pixel_path::fast ? tot.base_fast : r.path == pixel_path::interp ? tot.base_interp : tot.base_base) += b;
    }
  };
  for (int y = t.y0; y < t.y1; ++y) {
    const std::int32_t* owner = rp ? rp->owner + size_t(y) * size_t(cam.width) : nullptr;
    for (int x = 0; x < cam.width;) {
      const std::int32_t own = owner ? owner[x] : -1;
      int xe = x;
      if (own >= 0)
        while (xe + 1 < cam.width && owner[xe + 1] == own) ++xe;
      if (xe == x || span_L.empty() || !span_fillable((*rp->cells)[size_t(own)], (*rp->trust)[size_t(own)]) ||
          (f.off && f.off[size_t(scene_prim_of(*f.w, (*rp->cells)[size_t(own)].prim))])) {
        for (; x <= xe; ++x) shade_one(x, y);
        continue;
      }
      // A run of one plain cell's pixels: filled in screen space; a pixel the bound does
      // not pass takes the per-pixel path. The span's time includes the run's scan.
      const cell_ref& c = (*rp->cells)[size_t(own)];
      const int passed = fill_span(cam, c, y, x, xe, segment, f.p.eps, span_L.data(), span_ok.data());
      const glm::vec3 colour = reason_colour(pixel_reason::reprojected);
      for (int i = 0; i <= xe - x; ++i) {
        if (!span_ok[size_t(i)]) continue;
        out.at(x + i, y) = span_L[size_t(i)];
        if (reasons) reasons->at(x + i, y) = colour;
      }
      if (passed) {  // else the attempt's time goes to the pixels' own paths below
        const std::uint64_t ticks = lap();
        tot.pixels.span += std::uint64_t(passed);
        note_cell(tot.cells, c);
        tot.pixels.fast += std::uint64_t(passed), tot.ticks_fast += ticks, tot.ticks_span += ticks;
        if (base_cost) {
          std::uint64_t b = 0;
          for (int i = 0; i <= xe - x; ++i)
            if (span_ok[size_t(i)]) b += base_ticks(x + i, y);
          tot.base_fast += b, tot.base_span += b;
        }
        if (gating) {
          gate_tally& g = tally(scene_prim_of(*f.w, c.prim));
          g.span += std::uint64_t(passed), g.saved += std::uint64_t(passed) * c.ip->tree_rays;
        }
      }
      for (int i = 0; i <= xe - x; ++i)
        if (!span_ok[size_t(i)]) shade_one(x + i, y);
      x = xe + 1;
    }
  }
  if (run.prim >= 0) tot.gate.push_back(run);
  if (mu) {
    keep_first_uses(mirror.cells);
    tot.mirror_cells = std::move(mirror.cells);
    tot.mirror_filled = mirror.filled, tot.mirror_looked_up = mirror.looked_up, tot.mirror_traced = mirror.traced;
  }
  tot.rays = st.counts;
  tot.ticks_build = st.build_ticks;
}

}  // namespace

frame_result render_frame(workers& pool, const world& w, const camera& cam, const frame_params& p) {
  const bool interpolates = p.mode == render_mode::interp || p.mode == render_mode::full || p.mode == render_mode::lightfield;
  if (interpolates && !p.trees) throw std::logic_error("interp, full and lightfield modes need a linetree set");
  if ((p.mode == render_mode::full || p.mode == render_mode::reuse) && !p.reproj)
    throw std::logic_error("full and reuse modes need a reprojection state");
  const double tick_ms = ticks_per_ms();
  if (p.trees) p.trees->next_frame();
  auto t0 = std::chrono::steady_clock::now();
  frame_result out;
  out.img = image::unwritten(cam.width, cam.height);  // every tile writes all its pixels
  if (p.reasons) out.reasons = image::unwritten(cam.width, cam.height);
  int rows = p.tile_rows > 0 ? p.tile_rows : default_tile_rows(cam.height, pool.threads());
  std::vector<tile> tiles = make_tiles(cam.height, rows);
  std::vector<tile_totals> totals(tiles.size());
  std::vector<ray_tree_store> trees(p.keep_ray_trees ? tiles.size() : 0);
  interp_frame f{&w, p.trees, &cam, p.interp};
  light_cache* lights = (p.mode == render_mode::interp || p.mode == render_mode::full) && f.p.light_cache && p.trees
                            ? p.trees->lights(w)
                            : nullptr;
  if (lights && lights->in_use()) f.lights = lights;
  if (p.camera_moving) {
    f.p.min_cell_pixels = std::max(f.p.min_cell_pixels, f.p.moving_min_cell_pixels);
    f.p.failed_split_pixels = std::max(f.p.failed_split_pixels, f.p.moving_failed_split_pixels);
    f.p.defer_pixels = std::max(f.p.defer_pixels, f.p.moving_defer_pixels);
  } else if (p.moves_on) {
    f.p.failed_split_pixels = std::max(f.p.failed_split_pixels, f.p.moving_failed_split_pixels);
  }
  // Primitives too small on screen to be worth linetrees (interp and full): a function of
  // the camera alone, like every cost-model choice, so images do not depend on threads.
  // So are the objects the gate says do not pay (object_gate.h): decided from the last
  // frame's counts, so also a function of what the frames before computed, not of threads.
  std::vector<std::uint8_t> small, off;
  std::vector<float> box_px;  // gated: every primitive's box_pixels
  // Full mode only: interp mode is the paper's interpolate path for every object, which the
  // still-frame benchmark and the stress tests measure as such.
  const bool gated = p.mode == render_mode::full && f.p.object_gate && f.p.eps > 0 && p.trees->gate.enabled();
  // A plain frame (object_gate.h, plain_gain): traced as base mode traces it, or under the
  // pixels' allowance while that pays, with no cells; the next frame with cells starts with
  // none to reproject.
  bool plain = gated && f.p.plain_frames && p.trees->gate.plain();
  if (!plain && (p.mode == render_mode::interp || p.mode == render_mode::full) && (f.p.min_prim_pixels > 0 || gated)) {
    small.resize(w.prim_bounds.size());
    if (gated) off.resize(small.size()), box_px.resize(small.size());
    pool.run([&] {
      tbb::parallel_for(tbb::blocked_range<size_t>(0, small.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
        if (!gated) return small_primitives(w, cam, f.p.min_prim_pixels, r.begin(), r.end(), small.data());
        for (size_t i = r.begin(); i < r.end(); ++i) {
          box_px[i] = box_pixels(cam, w.prim_bounds[i]);
          off[i] = std::uint8_t(p.trees->gate.off(int(i), box_px[i]));
          small[i] = std::uint8_t(box_px[i] < f.p.min_prim_pixels) | off[i];
        }
      });
    });
    f.small = small.data();
    if (gated) f.off = off.data();
  }
  if (!gated) f.p.object_gate = false;
  // A frame with cells after none: a probe of its pixels first says whether they pay.
  if (gated && f.p.plain_frames && !plain && p.trees->gate.probe_due()) {
    const auto q0 = std::chrono::steady_clock::now();
    frame_probe probe = probe_frame(pool, f);
    plain = p.trees->gate.probe(probe.tallies, probe.own_rays, probe.bounded, probe.cast);
    out.rays += probe.rays;  // cast in this frame: counted with its own
    out.path_ms.build += double(probe.build_ticks) / tick_ms;
    out.probe_pixels = probe.pixels;
    out.probe_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - q0).count();
  }
  const bool plain_allowance = plain && p.trees->gate.plain_allowance();
  out.plain = plain;
  if (plain) {
    reprojection_state& rs = *p.reproj;
    if (rs.ahead.job.valid()) finish_ahead(rs.ahead);
    rs.ahead.ready = false, rs.ahead.cells.clear();
    rs.cells.clear(), rs.mirror.cells.clear();
  }
  // Full: last frame's cells from the new eye (each checked once, in parallel), then each
  // tile's pixels take the first containing trusted cell.
  std::vector<std::int32_t, no_init_allocator<std::int32_t>> owner;  // reproject_cells fills it
  std::vector<cell_trust> trusted;
  reprojection_frame rp;
  if (p.mode == render_mode::full && !plain) {
    const auto r0 = std::chrono::steady_clock::now();
    reprojection_state& rs = *p.reproj;
    owner.resize(size_t(cam.width) * size_t(cam.height));
    std::vector<cell_ref> last = std::move(rs.cells);  // the cells the last frame used
    if (f.off)  // objects the gate now traces: their cells own no pixels
      last.erase(std::remove_if(last.begin(), last.end(),
                                [&](const cell_ref& c) { return f.off[size_t(scene_prim_of(w, c.prim))] != 0; }),
                 last.end());
    reprojection_ahead& ahead = rs.ahead;
    const bool prepared = ahead.ready && same_camera(ahead.cam, cam) && ahead.owner.size() == owner.size();
    if (prepared) {
      // Prepared while the last frame was shaded, from the frame before it: now only the
      // cells the last frame used besides those, into the pixels still unowned.
      std::vector<cell_ref> cells = std::move(ahead.cells);
      std::unordered_set<const lt_node*> known;
      for (const cell_ref& c : cells) known.insert(c.node);
      const size_t first = cells.size();
      for (const cell_ref& c : last)
        if (!known.count(c.node)) cells.push_back(c);
      trusted = std::move(ahead.trusted);
      std::copy(ahead.owner.begin(), ahead.owner.end(), owner.begin());
      reproject_cells(&pool, w, cam, cells, first, nullptr, trusted, owner.data());
      rs.cells = std::move(cells);
    } else {
      reproject_cells(&pool, w, cam, last, 0, rs.raster.get(), trusted, owner.data());
    }
    ahead.ready = false;
    if (p.next_camera) start_ahead(ahead, w, *p.next_camera, last, rs.raster.get());  // copies the list
    if (!prepared) rs.cells = std::move(last);
    rp = reprojection_frame{&rs.cells, owner.data(), &trusted};
    out.reprojected_cells = rs.cells.size();
    out.trusted_cells =
        std::uint64_t(std::count_if(trusted.begin(), trusted.end(), [](const cell_trust& t) { return t.ok; }));
    out.reproject_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
  }
  // Full: the planar reflector's mirrored eye, and last frame's mirror cells seen from it.
  mirror_frame mf;
  std::vector<std::int32_t, no_init_allocator<std::int32_t>> mirror_owner;
  std::vector<cell_trust> mirror_trusted;
  std::vector<std::uint8_t> mirror_small;
  bool mirrored = false;
  if (p.mode == render_mode::full && f.p.mirror && f.p.eps > 0 && !plain) {
    const auto r0 = std::chrono::steady_clock::now();
    mirror_state& ms = p.reproj->mirror;
    mf.view = choose_mirror(w, cam);
    if (mf.view.reflector != ms.reflector) {  // another plane's cells serve nothing here
      ms.reflector = mf.view.reflector;
      ms.cells.clear();
      ms.trees = ms.reflector >= 0 ? std::make_unique<linetree_set>(w.prim_bounds, p.trees->memory_budget(),
                                                                    size_t(cam.width) * size_t(cam.height))
                                   : nullptr;
    }
    if (ms.reflector >= 0) {
      mirrored = true;
      ms.trees->next_frame();
      mirror_small.resize(w.prim_bounds.size());
      pool.run([&] {
        tbb::parallel_for(tbb::blocked_range<size_t>(0, mirror_small.size(), 1024),
                          [&](const tbb::blocked_range<size_t>& r) {
                            small_primitives(w, mf.view.cam, f.p.min_prim_pixels, r.begin(), r.end(),
                                             mirror_small.data());
                          });
      });
      mf.f = f;
      mf.f.trees = ms.trees.get(), mf.f.cam = &mf.view.cam, mf.f.small = mirror_small.data(), mf.f.off = nullptr;
      mf.f.p.eps = mirror_eps(f.p.eps, mf.view.ks), mf.f.p.build_depth = 2, mf.f.p.object_gate = false;
      mirror_owner.resize(size_t(cam.width) * size_t(cam.height));
      reproject_cells(&pool, w, mf.view.cam, ms.cells, 0, nullptr, mirror_trusted, mirror_owner.data(), &mf.view);
      mf.cells = &ms.cells, mf.owner = mirror_owner.data(), mf.trust = &mirror_trusted;
      out.mirror_cells = ms.cells.size();
      out.mirror_trusted = std::uint64_t(
          std::count_if(mirror_trusted.begin(), mirror_trusted.end(), [](const cell_trust& t) { return t.ok; }));
    }
    out.reproject_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
  }
  // Upsample: the reduced frame first, traced over its own tiles.
  image low;
  const camera low_cam = p.mode == render_mode::upsample ? reduced_camera(cam, std::max(1, p.upsample)) : camera{};
  if (p.mode == render_mode::upsample) {
    low = image::unwritten(low_cam.width, low_cam.height);
    const std::vector<tile> low_tiles = make_tiles(low_cam.height, rows);
    std::vector<tile_totals> low_totals(low_tiles.size());
    pool.run([&] {
      tbb::parallel_for(size_t(0), low_tiles.size(), [&](size_t i) {
        const std::uint64_t c0 = cycle_now();
        trace_state st;
        shade_rows_base(w, low_cam, low_tiles[i].y0, low_tiles[i].y1, low, st, nullptr);
        low_totals[i].rays = st.counts;
        low_totals[i].pixels.base = std::uint64_t(low_tiles[i].y1 - low_tiles[i].y0) * std::uint64_t(low_cam.width);
        low_totals[i].ticks_base = cycle_now() - c0;
      });
    });
    totals.insert(totals.end(), low_totals.begin(), low_totals.end());  // counted with the frame's
  }
  // Reuse: last frame's points splatted into this view, nearest first.
  std::vector<std::atomic<std::uint64_t>> nearest;
  reuse_state* reuse = p.mode == render_mode::reuse ? &p.reproj->pixels : nullptr;
  if (reuse) {
    const bool carried = reuse->last.width == cam.width && reuse->last.height == cam.height;
    reuse->next.resize(cam.width, cam.height);
    if (carried) {
      const auto r0 = std::chrono::steady_clock::now();
      nearest = std::vector<std::atomic<std::uint64_t>>(size_t(cam.width) * size_t(cam.height));
      const size_t n = nearest.size(), chunk = 4096;
      pool.run([&] {
        tbb::parallel_for(size_t(0), n, chunk, [&](size_t i) {
          for (size_t j = i; j < std::min(n, i + chunk); ++j) nearest[j].store(~std::uint64_t(0), std::memory_order_relaxed);
        });
        tbb::parallel_for(size_t(0), n, chunk, [&](size_t i) {
          splat_points(reuse->last, cam, p.reuse_age, i, std::min(n, i + chunk), nearest.data());
        });
      });
      out.reproject_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - r0).count();
    }
  }
  // The tiles, dearest first by last frame's costs (tile_queue.h). A plain frame's are base's.
  const render_mode tile_mode = plain ? render_mode::base : p.mode;
  image base_scratch = p.base_cost && plain_allowance ? image::unwritten(cam.width, cam.height) : image{};
  std::vector<std::uint64_t> tile_ticks(tiles.size());
  std::vector<std::uint8_t> tile_finite(tiles.size());
  out.shade = run_tiles(pool, pool.history().order(tiles.size(), p.order), [&](size_t i) {
    const std::uint64_t c0 = cycle_now();
    trace_state st;
    st.lights = f.lights;  // a plain frame's too; null in base mode
    switch (tile_mode) {
      case render_mode::base:
        if (plain_allowance)
          shade_rows_within(w, cam, tiles[i].y0, tiles[i].y1, f.p.eps, out.img, st);
        else
          shade_rows_base(w, cam, tiles[i].y0, tiles[i].y1, out.img, st,
                          p.keep_ray_trees && !plain ? &trees[i] : nullptr);
        totals[i].rays = st.counts;
        totals[i].pixels.base = std::uint64_t(tiles[i].y1 - tiles[i].y0) * std::uint64_t(cam.width);
        totals[i].ticks_base = cycle_now() - c0;
        if (p.base_cost) {  // a plain frame under the allowance is not base's code: timed again
          const std::uint64_t b0 = cycle_now();
          if (plain_allowance) {
            trace_state bs;
            shade_rows_base(w, cam, tiles[i].y0, tiles[i].y1, base_scratch, bs, nullptr);
          }
          totals[i].base_base = plain_allowance ? cycle_now() - b0 : totals[i].ticks_base;
        }
        break;
      case render_mode::upsample:  // the traced pixels are counted with the reduced frame's tiles
        upsample_rows(low, cam, std::max(1, p.upsample), tiles[i].y0, tiles[i].y1, out.img);
        totals[i].pixels.interp = std::uint64_t(tiles[i].y1 - tiles[i].y0) * std::uint64_t(cam.width);
        totals[i].ticks_interp = cycle_now() - c0;
        break;
      case render_mode::reuse: {
        const std::uint64_t reused = shade_rows_reuse(w, cam, reuse->last, nearest.empty() ? nullptr : nearest.data(),
                                                      tiles[i].y0, tiles[i].y1, out.img, reuse->next, st);
        totals[i].rays = st.counts;
        totals[i].pixels.fast = reused;
        totals[i].pixels.base = std::uint64_t(tiles[i].y1 - tiles[i].y0) * std::uint64_t(cam.width) - reused;
        totals[i].ticks_base = cycle_now() - c0;  // per pixel, not per path: one band of both
        break;
      }
      case render_mode::interp:
      case render_mode::full:
      case render_mode::lightfield:
        shade_tile_interp(f, p.mode == render_mode::full ? &rp : nullptr, mirrored ? &mf : nullptr,
                          p.mode == render_mode::lightfield ? p.lf_depth : -1, tiles[i], out.img,
                          p.reasons ? &out.reasons : nullptr, totals[i], p.base_cost);
        keep_first_uses(totals[i].cells);  // here, in parallel: the serial merge below then sees far fewer
        break;
    }
    if (p.reasons &&
        (tile_mode == render_mode::base || tile_mode == render_mode::upsample || tile_mode == render_mode::reuse))
      for (int y = tiles[i].y0; y < tiles[i].y1; ++y)
        for (int x = 0; x < cam.width; ++x) out.reasons.at(x, y) = reason_colour(pixel_reason::traced);
    tile_finite[i] = all_finite(out.img, tiles[i].y0, tiles[i].y1);  // while the rows are in this core's cache
    tile_ticks[i] = cycle_now() - c0;
    if (p.rows_done) p.rows_done->fetch_add(tiles[i].y1 - tiles[i].y0, std::memory_order_relaxed);
  });
  pool.history().ticks = std::move(tile_ticks);
  out.finite = std::find(tile_finite.begin(), tile_finite.end(), 0) == tile_finite.end();
  const auto a0 = std::chrono::steady_clock::now();
  if (reuse) std::swap(reuse->last, reuse->next);
  for (const tile_totals& t : totals) {
    out.rays += t.rays, out.pixels += t.pixels;
    out.path_ms.fast += double(t.ticks_fast) / tick_ms;
    out.path_ms.interp += double(t.ticks_interp) / tick_ms, out.path_ms.base += double(t.ticks_base) / tick_ms;
    out.path_ms.deferred += double(t.ticks_deferred) / tick_ms;
    out.path_ms.span += double(t.ticks_span) / tick_ms;
    out.path_ms.build += double(t.ticks_build) / tick_ms;
    out.base_code_ms.fast += double(t.base_fast) / tick_ms, out.base_code_ms.interp += double(t.base_interp) / tick_ms;
    out.base_code_ms.base += double(t.base_base) / tick_ms;
    out.base_code_ms.deferred += double(t.base_deferred) / tick_ms, out.base_code_ms.span += double(t.base_span) / tick_ms;
  }
  if (p.mode == render_mode::full && !plain) {
    reprojection_ahead& ahead = p.reproj->ahead;
    if (ahead.job.valid()) {
      out.ahead_wait_ms = finish_ahead(ahead);
      out.ahead_ms = ahead.ms;
      for (const cell_ref& c : ahead.cells) mark_used(*c.node, p.trees->frame());  // the next frame's: kept
    }
    std::vector<cell_ref> next;
    size_t used = 0;
    for (const tile_totals& t : totals) used += t.cells.size();
    next.reserve(used);
    for (const tile_totals& t : totals) next.insert(next.end(), t.cells.begin(), t.cells.end());
    keep_first_uses(next);
    for (const cell_ref& c : next) mark_used(*c.node, p.trees->frame());  // carried: never evicted now
    p.reproj->cells = std::move(next);
    if (mirrored) {
      mirror_state& ms = p.reproj->mirror;
      std::vector<cell_ref> mnext;
      for (const tile_totals& t : totals) {
        mnext.insert(mnext.end(), t.mirror_cells.begin(), t.mirror_cells.end());
        out.mirror_filled += t.mirror_filled, out.mirror_looked_up += t.mirror_looked_up;
        out.mirror_traced += t.mirror_traced;
      }
      keep_first_uses(mnext);
      for (const cell_ref& c : mnext) mark_used(*c.node, ms.trees->frame());
      ms.cells = std::move(mnext);
      ms.trees->evict();
    }
  }
  if (plain) {
    const ray_counts& r = out.rays;
    p.trees->gate.plain_done(plain_allowance ? r.shadow_bounded + r.secondary_bounded : 0,
                             plain_allowance ? r.shadow + r.reflect + r.refract : 0);
    out.objects_off = p.trees->gate.objects_off();
  } else if (gated) {
    std::vector<gate_entry> entries;
    for (const tile_totals& t : totals) entries.insert(entries.end(), t.gate.begin(), t.gate.end());
    p.trees->gate.update(entries, p.camera_moving, box_px.data(), f.p.plain_frames ? out.rays.total() : 0);
    out.objects_off = p.trees->gate.objects_off();
  }
  if (lights)
    lights->next_frame(f.lights != nullptr, out.rays.shadow_asked, out.rays.shadow_listed);
  if (p.trees) p.trees->evict();  // between frames: nothing else touches the trees now
  for (const ray_tree_store& t : trees) out.trees.append(t);
  const auto t1 = std::chrono::steady_clock::now();
  out.after_ms = std::chrono::duration<double, std::milli>(t1 - a0).count();
  out.ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  // After the clock: measuring linetree memory walks every node.
  out.linetree_bytes = p.trees ? p.trees->bytes() : 0;
  out.memory_bytes = out.img.pixels.capacity() * sizeof(glm::vec3) + out.trees.bytes() + out.linetree_bytes +
                     (p.trees ? p.trees->light_bytes() : 0);
  return out;
}

}  // namespace epsray
