// Reprojection and span filling (issue 4): a pixel takes a reprojected cell only when its
// eye ray lies in the cell and nothing can hide the cell from the new eye, so occluders
// that move in front of reprojected cells between frames never leak into the image, and
// full mode stays within epsilon and independent of the thread count.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <random>

#include "reproject/face_raster.h"
#include "reproject/reproject.h"
#include "reproject/span_fill.h"
#include "sched/frame_render.h"
#include "sched/verify.h"
#include "test_util.h"

namespace epsray {
namespace {

world world_of(const std::string& text) { return make_world(parse_scene(text, "test.nff", "")); }

// A lit back wall and, well in front of it, a small red sphere on a post: as the camera
// slides sideways the sphere sweeps across wall cells reprojected from earlier frames
// (the paper's figure 9).
const char* sweep_scene = R"(
v
from 0 1 6
at 0 1 0
up 0 1 0
angle 40
hither 0.01
resolution 32 24
l 1 3 4
l -3 2 5 0.3 0.3 0.4
f 0.8 0.8 0.75 0.8 0 0 0 1
p 4
-6 -2 -1
6 -2 -1
6 4 -1
-6 4 -1
f 0.9 0.1 0.1 0.7 0.2 20 0 1
s 0 1 3 0.35
)";

camera_view slid(const camera_view& v, float dx) {
  camera_view out = v;
  out.from.x += dx, out.at.x += dx;
  return out;
}

struct walk_result {
  std::vector<image> frames;
  std::uint64_t fast = 0;
  std::uint64_t span = 0;  // of fast: span-filled in screen space
  int ahead_frames = 0;  // frames that prepared the next one's reprojection (--pipeline)
  size_t max_linetree_bytes = 0;
};

walk_result walk_full(const world& w, const std::vector<camera_view>& views, int width, int height, int threads,
                      float eps, bool verify, size_t memory_budget = 0, std::unique_ptr<face_raster> raster = nullptr,
                      bool pipeline = false, int span_segment = -1, tile_order order = tile_order::costly_first) {
  linetree_set trees(w.prim_bounds, memory_budget);
  reprojection_state reproj;
  reproj.raster = std::move(raster);
  workers pool(threads);
  frame_params p;
  p.mode = render_mode::full;
  p.interp.eps = eps;
  p.trees = &trees;
  p.reproj = &reproj;
  p.order = order;
  p.interp.plain_frames = false;  // the reprojection is what these walks test
  if (span_segment >= 0) p.interp.span_segment = span_segment;
  walk_result out;
  for (size_t k = 0; k < views.size(); ++k) {
    const camera cam = make_camera(views[k], width, height);
    p.camera_moving = k > 0 && !same_camera(cam, make_camera(views[k - 1], width, height));
    const camera next = k + 1 < views.size() ? make_camera(views[k + 1], width, height) : camera{};
    p.next_camera = pipeline && k + 1 < views.size() ? &next : nullptr;
    frame_result fr = render_frame(pool, w, cam, p);
    if (p.next_camera) {
      EXPECT_GT(fr.ahead_ms, 0) << "frame " << k;
    }
    out.ahead_frames += fr.ahead_ms > 0;
    if (verify) {
      verify_result vr = verify_frame(pool, w, cam, fr.img, eps);
      EXPECT_EQ(vr.violations, 0u) << "frame " << k << ", max error " << vr.max_rel_err;
    }
    if (k > 0) out.fast += fr.pixels.fast, out.span += fr.pixels.span;
    out.max_linetree_bytes = std::max(out.max_linetree_bytes, trees.bytes());
    // The running count of bytes published and freed equals a walk over every tree, also
    // after evictions and with threads racing to publish.
    EXPECT_EQ(trees.bytes(), trees.measured_bytes()) << "frame " << k;
    out.frames.push_back(std::move(fr.img));
  }
  return out;
}

TEST(Reprojection, OccluderSweepingAcrossReprojectedCellsNeverLeaks) {
  world w = world_of(sweep_scene);
  std::vector<camera_view> views;
  for (int k = 0; k < 8; ++k) views.push_back(slid(w.sc.view, 0.12f * float(k)));
  walk_result r = walk_full(w, views, 160, 120, 2, 0.05f, true);
  EXPECT_GT(r.fast, 160u * 120u) << "later frames should mostly reuse last frame's cells";
}

TEST(Reprojection, ObjectPassedByTheCameraIsNotReprojectedBehindIt) {
  // The camera flies towards the wall and past a matte sphere (whose cells are valid): the
  // lines through the new eye that meet the sphere meet it behind the eye, and the pixels
  // looking ahead, at the wall, must not take it. (Before the check, 507 pixels did.)
  std::string text = sweep_scene;
  const std::string shiny = "f 0.9 0.1 0.1 0.7 0.2 20 0 1", matte = "f 0.9 0.1 0.1 0.9 0 0 0 1";
  text.replace(text.find(shiny), shiny.size(), matte);
  world w = world_of(text);
  std::vector<camera_view> views;
  for (float z : {6.0f, 5.0f, 4.4f, 2.5f, 2.3f}) {
    camera_view v = w.sc.view;
    v.from.z = z, v.at.z = z - 6;
    views.push_back(v);
  }
  walk_result r = walk_full(w, views, 160, 120, 2, 0.05f, true);
  EXPECT_GT(r.fast, 160u * 120u);
}

// One interp frame of `scene` from the eye (from, at), 240x180 unless given, with no floor on cell size:
// its interpolated pixels, and its pixels over eps.
struct floorless_frame {
  std::uint64_t interp = 0, over = 0;
  double max_err = 0;
};
floorless_frame render_floorless(const std::string& scene, glm::vec3 from, glm::vec3 at, float angle, float eps,
                                 float min_prim_pixels, int width = 240, int height = 180) {
  world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + scene));
  camera_view v = w.sc.view;
  v.from = from, v.at = at, v.up = {0, 1, 0}, v.angle = angle;
  const camera cam = make_camera(v, width, height);
  linetree_set trees(w.prim_bounds, 0);
  workers pool(2);
  frame_params p;
  p.mode = render_mode::interp;
  p.interp.eps = eps;
  p.interp.min_cell_pixels = 0, p.interp.min_prim_pixels = min_prim_pixels;
  p.trees = &trees;
  const frame_result fr = render_frame(pool, w, cam, p);
  const verify_result vr = verify_frame(pool, w, cam, fr.img, eps);
  return {fr.pixels.interp, vr.violations, vr.max_rel_err};
}

TEST(Bound, TinyCellsNearAConeApexStayWithinEps) {
  // Seen from the alcove, the sculpture's cone near its apex: with no floor on cell size
  // (--min-cell-pixels 0) cells there became small enough to prove, while the float cone
  // hit made the reference itself jump by up to 2.5% between neighbouring rays (sweep seed
  // 2064: 2 pixels of this frame over eps 0.01; 40 runs of 468 in all).
  const floorless_frame f = render_floorless("/scenes/artroom.nff", {0.426788218f, 0.647942792f, -15.194861f},
                                             {-0.861576672f, 0.410898111f, -9.99471447f}, 27.2948f, 0.01f, 1024);
  EXPECT_GT(f.interp, 20000u);
  EXPECT_EQ(f.over, 0u) << "max error " << f.max_err;
}

TEST(Bound, TinyCellsOnAShineFiftyThousandHighlightStayWithinEps) {
  // The reference's highlight max(0, N.H)^50000 steps by 2e-4 (of 0.13) per ulp of its
  // float N.H, between neighbouring rays: tiny cells (no floors) proved the smooth
  // function within 1e-4 and a pixel went 1.45 eps over at eps 0.001 (sweep seed 2068).
  // The bound now carries that noise (evaluator::noise).
  const floorless_frame f = render_floorless("/scenes/stress/shiny.nff", {7.18066206f, 8.77660168f, 16.062616f},
                                             {-1.11639902f, 0.738130433f, 0.29212029f}, 98.3385f, 0.001f, 0);
  EXPECT_GT(f.interp, 1000u);
  EXPECT_EQ(f.over, 0u) << "max error " << f.max_err;
}

TEST(Bound, TinyCellsAtABoxEdgeStayWithinEps) {
  // The shapes scene's box seen from above and behind: a cell of a few lines along the
  // edge of its top face had a corner that float rounding shaded as the side face (sweep
  // seed 2075: one pixel 2x over eps 0.005). Faces are now decided in double, and the
  // predicate keeps a face's points a rounding margin off its edges.
  const floorless_frame f = render_floorless("/scenes/tests/shapes.nff", {-6.33065461f, 7.9277077f, -8.14043901f},
                                             {1.98108166f, 0.0489893774f, 1.96181808f}, 25.5237f, 0.005f, 1024,
                                             320, 240);
  EXPECT_GT(f.interp, 20000u);
  EXPECT_EQ(f.over, 0u) << "max error " << f.max_err;
}

TEST(FrameStats, BuildingTimeIsPartOfTheInterpAndBasePathsAndOnlyWhereCellsAreBuilt) {
  world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/tests/shapes.nff"));
  linetree_set trees(w.prim_bounds, 0);
  workers pool(2);
  frame_params p;
  p.mode = render_mode::interp;
  p.interp.eps = 0.05f;
  p.trees = &trees;
  const camera cam = make_camera(w.sc.view, 96, 72);
  const frame_result cold = render_frame(pool, w, cam, p);  // builds the cells
  EXPECT_GT(cold.path_ms.build, 0);
  EXPECT_LE(cold.path_ms.build, cold.path_ms.interp + cold.path_ms.base);
  const frame_result warm = render_frame(pool, w, cam, p);  // the same eye: every cell is built
  EXPECT_EQ(warm.path_ms.build, 0);
  frame_params b;
  EXPECT_EQ(render_frame(pool, w, cam, b).path_ms.build, 0) << "the base tracer builds nothing";
}

TEST(Reprojection, FullModeImagesIgnoreThreadCount) {
  world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/tests/shapes.nff"));
  std::vector<camera_view> views;
  for (int k = 0; k < 4; ++k) views.push_back(slid(w.sc.view, 0.05f * float(k)));
  walk_result a = walk_full(w, views, 96, 72, 1, 0.05f, false);
  for (int threads : {2, 8}) {  // 8: more workers than this machine's cores, racing builds
    walk_result b = walk_full(w, views, 96, 72, threads, 0.05f, false);
    ASSERT_EQ(a.frames.size(), b.frames.size());
    for (size_t k = 0; k < a.frames.size(); ++k)
      EXPECT_TRUE(test::same_pixels(a.frames[k], b.frames[k])) << threads << " threads, frame " << k;
    EXPECT_EQ(a.fast, b.fast) << threads << " threads";
    EXPECT_EQ(a.span, b.span) << threads << " threads";
  }
  // Nor on the order the tiles are handed out in (tile_queue.h): top to bottom.
  walk_result scan = walk_full(w, views, 96, 72, 8, 0.05f, false, 0, nullptr, false, -1, tile_order::scan);
  for (size_t k = 0; k < a.frames.size(); ++k)
    EXPECT_TRUE(test::same_pixels(a.frames[k], scan.frames[k])) << "scan order, frame " << k;
  EXPECT_EQ(a.fast, scan.fast);
  EXPECT_EQ(a.span, scan.span);
  EXPECT_GT(a.fast, 0u);
}

TEST(MemoryBudget, EvictionKeepsTheBoundTheBudgetAndThreadIndependence) {
  // The art room orbited at a small size: unbounded, its linetrees outgrow the budget;
  // bounded, least recently used cells are evicted between frames and rebuilt on demand.
  world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff"));
  std::vector<camera_view> views;
  for (int k = 0; k < 6; ++k) {
    camera_view v = w.sc.view;
    const float turn = 0.08f * float(k);
    const glm::vec3 d = v.at - v.from;
    v.at = v.from + glm::vec3(std::cos(turn) * d.x - std::sin(turn) * d.z, d.y, std::sin(turn) * d.x + std::cos(turn) * d.z);
    views.push_back(v);
  }
  const size_t budget = size_t(6) << 20;
  walk_result free_walk = walk_full(w, views, 200, 150, 2, 0.05f, false);
  ASSERT_GT(free_walk.max_linetree_bytes, budget) << "the walk must outgrow the budget for the test to mean much";
  walk_result one = walk_full(w, views, 200, 150, 1, 0.05f, true, budget);
  walk_result two = walk_full(w, views, 200, 150, 2, 0.05f, true, budget);
  // Over the budget only by the cells a frame used (kept so reprojection can use them).
  EXPECT_LT(one.max_linetree_bytes, free_walk.max_linetree_bytes);
  EXPECT_LT(one.max_linetree_bytes, 2 * budget);
  for (size_t k = 0; k < views.size(); ++k)
    EXPECT_EQ(std::memcmp(one.frames[k].pixels.data(), two.frames[k].pixels.data(),
                          one.frames[k].pixels.size() * sizeof(glm::vec3)),
              0)
        << "frame " << k;
  // Pipelined (--pipeline), the cells prepared for the next frame outlive the eviction
  // between frames although this frame may not have used them (ASan sees it if not).
  // A budget below one frame's cells evicts all else: also those, but for the marking.
  walk_result piped = walk_full(w, views, 200, 150, 2, 0.05f, true, budget / 16, nullptr, true);
  EXPECT_LT(piped.max_linetree_bytes, free_walk.max_linetree_bytes);
}

TEST(Reprojection, EpsZeroFullWalkIsTheBaseTracer) {
  world w = world_of(sweep_scene);
  std::vector<camera_view> views{w.sc.view, slid(w.sc.view, 0.1f)};
  walk_result r = walk_full(w, views, 48, 36, 2, 0.0f, false);
  workers pool(2);
  for (size_t k = 0; k < views.size(); ++k) {
    frame_result base = render_frame(pool, w, make_camera(views[k], 48, 36), frame_params{});
    EXPECT_EQ(std::memcmp(base.img.pixels.data(), r.frames[k].pixels.data(), base.img.pixels.size() * sizeof(glm::vec3)),
              0);
  }
  EXPECT_EQ(r.fast, 0u);
}

// A cell of the wall seen past the sphere: trusted outright from an eye with a clear view;
// from an eye whose view of the cell's hit points the sphere may cross, trusted with the
// sphere as a candidate its pixels test.
TEST(Reprojection, CellIsTrustedWithTheOccludersItsPixelsMustTest) {
  world w = world_of(sweep_scene);
  linetree_set trees(w.prim_bounds);
  workers pool(1);
  frame_params p;
  p.mode = render_mode::interp;
  p.interp.eps = 0.05f;
  p.trees = &trees;
  p.reproj = nullptr;
  // Find the wall cell holding the line through a wall point left of the sphere, from a
  // first camera: render the frame to build cells, then look the line up.
  const camera cam = make_camera(w.sc.view, 160, 120);
  render_frame(pool, w, cam, p);
  const glm::vec3 target{-2.5f, 1.0f, -1.0f};
  int wall = -1;
  for (size_t i = 0; i < w.scene_prims; ++i)
    if (w.shapes[i].kind != shape_kind::sphere) wall = int(i);
  ASSERT_GE(wall, 0);
  const glm::vec3 d = glm::normalize(target - cam.origin);
  linetree& lt = trees.tree_for(wall, d);
  float x4[4];
  line_coords(lt.fp, cam.origin, d, x4);
  lt_node* n = &lt.root;
  while (lt_node* kids = n->kids.load()) n = child_at(*n, kids, x4);
  const interpolant* ip = n->interp.load();
  ASSERT_NE(ip, nullptr);
  ASSERT_EQ(ip->reason, cell_reason::valid);
  cell_ref c{&lt, n, ip, wall};
  const cell_trust clear = trust_from(w, c, cam.origin);
  EXPECT_TRUE(clear.ok);
  EXPECT_EQ(clear.count, 0);
  // An eye on the line from the cell's points through the sphere's centre: the sphere is the
  // one candidate (the walks below check that its pixels are refused where it hides them).
  const glm::vec3 mid = ip->hit_box.centre(), sphere{0, 1, 3};
  const glm::vec3 behind_sphere = sphere + glm::normalize(sphere - mid) * 2.0f;
  const cell_trust hidden = trust_from(w, c, behind_sphere);
  ASSERT_TRUE(hidden.ok);
  ASSERT_EQ(hidden.count, 1);
  int sphere_id = -1;
  for (size_t i = 0; i < w.scene_prims; ++i)
    if (w.shapes[i].kind == shape_kind::sphere) sphere_id = int(i);
  EXPECT_EQ(hidden.candidates[0], sphere_id);
}

// Splatting finds, per row, the run of pixels whose lines lie in each cell by solving the
// per-pixel test's inequalities (linear along a row); ownership must match testing every
// pixel of every cell's rectangle, but for pixels where float rounding decides (a few).
// A scene's cells (the art room's unless given) after a first frame, seen from the next eye
// (stepped forward and turned a little, so cells land on new pixels): each cell's trust and
// pixel rectangle.
struct next_eye {
  world w;
  linetree_set trees{w.prim_bounds};
  reprojection_state reproj;
  camera cam;
  std::vector<cell_trust> trusted;
  std::vector<pixel_rect> rects;
  next_eye(int width, int height)
      : next_eye(make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff")), width, height) {}
  next_eye(world scene, int width, int height) : w(std::move(scene)) {
    workers pool(2);
    frame_params p;
    p.mode = render_mode::full, p.interp.eps = 0.05f, p.trees = &trees, p.reproj = &reproj;
    p.interp.plain_frames = false;  // the reprojection is what these test
    render_frame(pool, w, make_camera(w.sc.view, width, height), p);
    camera_view v = w.sc.view;
    v.from += 0.05f * glm::normalize(v.at - v.from), v.at.x += 0.2f;
    cam = make_camera(v, width, height);
    const std::vector<cell_ref>& cells = reproj.cells;
    trusted.resize(cells.size()), rects.resize(cells.size());
    for (size_t i = 0; i < cells.size(); ++i) {
      trusted[i] = trust_from(w, cells[i], cam.origin);
      if (trusted[i].ok) rects[i] = raster_rect(cam, cell_screen_box(cam, cells[i].lt->fp, *cells[i].node));
    }
  }
};

// Calls f(x, y, x4, eye ray) for each pixel of cell i's rectangle whose eye line lies in the cell.
template <class F>
void for_each_line_in_cell(const next_eye& e, size_t i, F&& f) {
  const pixel_rect& r = e.rects[i];
  for (int y = r.y0; y < r.y1; ++y)
    for (int x = r.x0; x < r.x1; ++x) {
      float x4[4];
      if (!eye_line_in_cell(e.cam, e.reproj.cells[i], x, y, x4)) continue;
      f(x, y, x4, eye_ray(e.w, e.cam, eye_direction(e.cam, float(x), float(y))));
    }
}

// A box face's cell reaching past the face (cell_trust::face_check) owns only the pixels
// whose lines meet the face; a pixel whose line lies in such a cell but meets the face's
// plane off the face belongs to whatever lies behind, and fill_pixel refuses it.
TEST(Reprojection, BoxFaceCellsOwnOnlyPixelsOnTheirFace) {
  const int width = 200, height = 150;
  next_eye e(width, height);
  const world& w = e.w;
  const camera& cam = e.cam;
  const std::vector<cell_ref>& cells = e.reproj.cells;
  int checked_cells = 0, owned = 0, off_face = 0;
  trace_state st;
  for (size_t i = 0; i < cells.size(); ++i) {
    const cell_trust& t = e.trusted[i];
    if (!t.ok || !t.face_check) continue;
    ++checked_cells;
    const int box = scene_prim_of(w, cells[i].prim);
    ASSERT_NE(box, cells[i].prim);
    for_each_line_in_cell(e, i, [&](int x, int y, float* x4, const ray& ray_) {
      float tb;
      const bool on = hit_shape(w.shapes[size_t(box)], w.polys, ray_, INFINITY, tb) &&
                      face_prim_of(w, box, ray_) == cells[i].prim;
      glm::vec3 L;
      if (eye_line_owned(cam, cells[i], t, x, y, x4)) {
        ++owned;
      } else if (!on) {
        ++off_face;
        EXPECT_FALSE(fill_pixel(w, cam, cells[i], t, x, y, 0.05f, st, L)) << "pixel " << x << "," << y;
      }
    });
  }
  EXPECT_GT(checked_cells, 5);
  EXPECT_GT(owned, 100);
  EXPECT_GT(off_face, 100) << "lines in the cells that miss the face";
}

// The sweep scene with a disk between the wall and the sphere.
const std::string disk_scene = std::string(sweep_scene) + "f 0.3 0.5 0.9 0.8 0 0 0 1\ndisk 0 1 0  0 0.3 1  1.5\n";

// fill_pixel meets a trusted cell's flat object (polygon or disk) by its plane alone: a valid
// cell's lines are proven to meet it inside its outline. Every pixel whose line lies in such
// a cell must then meet the object by the full test, outline included, at the same t.
// Returns the pixels checked on polygons and on disks.
std::pair<size_t, size_t> flat_cells_meet_their_object(const next_eye& e) {
  const world& w = e.w;
  const std::vector<cell_ref>& cells = e.reproj.cells;
  size_t polygon_pixels = 0, disk_pixels = 0;
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!e.trusted[i].ok) continue;
    const shape& s = w.shapes[size_t(scene_prim_of(w, cells[i].prim))];
    if (s.kind != shape_kind::polygon && s.kind != shape_kind::disk) continue;
    for_each_line_in_cell(e, i, [&](int x, int y, float*, const ray& ray_) {
      float t = 0;
      const bool hit = hit_shape(s, w.polys, ray_, INFINITY, t);
      EXPECT_TRUE(hit) << "cell " << i << ", pixel " << x << "," << y;
      if (!hit) return;
      float plane_t = -1;
      EXPECT_TRUE(s.kind == shape_kind::polygon ? hit_polygon_plane(s.poly, ray_, INFINITY, plane_t)
                                                : hit_disk_plane(s.disk, ray_, INFINITY, plane_t));
      EXPECT_EQ(t, plane_t);
      (s.kind == shape_kind::polygon ? polygon_pixels : disk_pixels) += 1;
    });
  }
  return {polygon_pixels, disk_pixels};
}

TEST(Reprojection, FlatCellsLinesMeetTheirObjectInsideItsOutline) {
  const int width = 200, height = 150;
  next_eye art(width, height);
  EXPECT_GT(flat_cells_meet_their_object(art).first, size_t(width * height / 4)) << "the floor and walls";
  next_eye disk(world_of(disk_scene), width, height);
  const auto [polygon_pixels, disk_pixels] = flat_cells_meet_their_object(disk);
  EXPECT_GT(disk_pixels, size_t(width * height / 20));
  EXPECT_GT(polygon_pixels, size_t(width * height / 20));
}

TEST(Reprojection, RowRunsOwnThePixelsThePerPixelTestWould) {
  const int width = 200, height = 150;
  next_eye e(width, height);
  const camera& cam = e.cam;
  const std::vector<cell_ref>& cells = e.reproj.cells;
  const std::vector<cell_trust>& trusted = e.trusted;
  const std::vector<pixel_rect>& rects = e.rects;
  ASSERT_GT(cells.size(), 100u);
  std::vector<std::int32_t> rows(size_t(width) * height), brute(size_t(width) * height, -1);
  splat_rows(cam, cells, trusted, rects, 0, height, rows.data());
  for (size_t i = 0; i < cells.size(); ++i) {
    if (!trusted[i].ok) continue;
    for (int y = rects[i].y0; y < rects[i].y1; ++y)
      for (int x = rects[i].x0; x < rects[i].x1; ++x) {
        float x4[4];
        std::int32_t& o = brute[size_t(y) * width + size_t(x)];
        if (o < 0 && eye_line_owned(cam, cells[i], trusted[i], x, y, x4)) o = std::int32_t(i);
      }
  }
  size_t owned = 0, differ = 0;
  for (size_t k = 0; k < rows.size(); ++k) owned += brute[k] >= 0, differ += rows[k] != brute[k];
  EXPECT_GT(owned, rows.size() / 2) << "most pixels are reprojected";
  EXPECT_LE(differ, rows.size() / 1000) << differ << " of " << owned << " owned pixels differ";
}

// --- span filling in screen space (span_fill.h) ------------------------------------------

// Q is multilinear, so its derivatives over the cell are bounded by the corners' first and
// mixed second differences; checked against the exact derivatives at random points.
TEST(SpanFill, CornerDifferencesBoundTheInterpolantsDerivatives) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0, 1);
  for (int trial = 0; trial < 50; ++trial) {
    glm::vec3 v[16];
    for (glm::vec3& c : v) c = {u(rng), 2 * u(rng), u(rng) * u(rng)};
    const corner_differences d = corner_differences_of(v);
    for (int s = 0; s < 20; ++s) {
      float t[4];
      for (float& x : t) x = u(rng);
      auto at = [&](int i, float ti, int j, float tj) {
        float q[4] = {t[0], t[1], t[2], t[3]};
        q[i] = ti;
        if (j >= 0) q[j] = tj;
        return quadrilinear(v, q);
      };
      for (int i = 0; i < 4; ++i) {
        const glm::vec3 d1 = glm::abs(at(i, 1, -1, 0) - at(i, 0, -1, 0));  // dQ/dt_i, exactly
        EXPECT_TRUE(glm::all(glm::lessThanEqual(d1, d.d1[i] + 1e-5f))) << "axis " << i;
        for (int j = 0; j < 4; ++j) {
          if (j == i) continue;
          const glm::vec3 d2 = glm::abs(at(i, 1, j, 1) - at(i, 1, j, 0) - at(i, 0, j, 1) + at(i, 0, j, 0));
          EXPECT_TRUE(glm::all(glm::lessThanEqual(d2, d.d2[i][j] + 1e-5f))) << "axes " << i << j;
        }
      }
    }
  }
}

// Linear interpolation between a segment's end pixels stays within span_error's bound of
// the interpolant at every pixel's own line, on every run of a plain cell the art room's
// next eye reprojects, for short and long segments. The second-order term is needed: some
// pixels deviate by more than the rounding term alone allows.
TEST(SpanFill, ScreenSpaceInterpolationStaysWithinItsBound) {
  const int width = 200, height = 150;
  next_eye e(width, height);
  const camera& cam = e.cam;
  const std::vector<cell_ref>& cells = e.reproj.cells;
  std::vector<std::int32_t> owner(size_t(width) * height);
  splat_rows(cam, cells, e.trusted, e.rects, 0, height, owner.data());
  auto value = [&](const cell_ref& c, int x, int y, glm::vec3& L) {
    float x4[4], t[4];
    if (!eye_line_in_cell(cam, c, x, y, x4)) return false;
    cell_fractions(*c.node, x4, t);
    L = quadrilinear(c.ip->rad, t);
    return true;
  };
  size_t segments = 0, pixels = 0, second_order = 0;
  double worst = 0;  // largest deviation over its bound
  for (int segment : {4, 16, 64}) {
    for (int y = 0; y < height; ++y) {
      const std::int32_t* row = owner.data() + size_t(y) * width;
      for (int x0 = 0; x0 < width;) {
        int x1 = x0;
        while (x1 + 1 < width && row[x1 + 1] == row[x0]) ++x1;
        const std::int32_t own = row[x0];
        if (own >= 0 && span_fillable(cells[size_t(own)], e.trusted[size_t(own)])) {
          const cell_ref& c = cells[size_t(own)];
          const corner_differences d = corner_differences_of(c.ip->rad);
          for (int xa = x0; xa + 1 < x1; xa += segment) {
            const int xb = std::min(xa + segment, x1);
            glm::vec3 La, Lb, L;
            if (!value(c, xa, y, La) || !value(c, xb, y, Lb)) continue;
            const span_bound b = span_error(cam, c, d, y, xa, xb);
            ++segments;
            for (int x = xa + 1; x < xb; ++x) {
              if (!value(c, x, y, L)) continue;
              const float f = float(x - xa) / float(xb - xa);
              const glm::vec3 dev = glm::abs(La + f * (Lb - La) - L);
              const glm::vec3 bound = 0.5f * float(x - xa) * float(xb - x) * b.m2 + 2.0f * b.rounding;
              for (int ch = 0; ch < 3; ++ch) {
                // Float rounding of the lerp itself (within's own margin covers it).
                const float slack = 2e-6f * std::fabs(L[ch]) + 1e-9f;
                EXPECT_LE(dev[ch], bound[ch] + slack) << "row " << y << ", pixels " << xa << ".." << xb << ", x " << x;
                if (bound[ch] > 0) worst = std::max(worst, double(dev[ch]) / double(bound[ch]));
                second_order += dev[ch] > 2.0f * b.rounding[ch] + slack;
              }
              ++pixels;
            }
          }
        }
        x0 = x1 + 1;
      }
    }
  }
  EXPECT_GT(segments, 1000u);
  EXPECT_GT(pixels, 5000u);
  std::printf("span pixels checked %zu, deviation over bound at most %.3f, %zu needing the second-order term\n",
              pixels, worst, second_order);
  EXPECT_GT(second_order, 0u) << "no pixel needed the second-order term";
  RecordProperty("worst_deviation_over_bound", std::to_string(worst));
}

// Full mode with span filling: zero pixels over epsilon along a walk, most plain pixels
// span-filled, and the same images for 1 and 2 threads (spans follow the owner buffer's
// runs, which do not depend on tiles). Per-pixel evaluation (--span 0) stays within too.
TEST(SpanFill, FullWalkStaysWithinEpsAndIgnoresThreadCount) {
  world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff"));
  std::vector<camera_view> views;
  for (int k = 0; k < 4; ++k) {
    camera_view v = w.sc.view;
    v.from += 0.04f * float(k) * glm::normalize(v.at - v.from), v.at.x += 0.05f * float(k);
    views.push_back(v);
  }
  const walk_result a = walk_full(w, views, 160, 120, 1, 0.05f, true);
  const walk_result b = walk_full(w, views, 160, 120, 2, 0.05f, false);
  for (size_t k = 0; k < a.frames.size(); ++k) EXPECT_TRUE(test::same_pixels(a.frames[k], b.frames[k])) << "frame " << k;
  EXPECT_EQ(a.span, b.span);
  EXPECT_GT(a.span, 2000u) << a.span << " of " << a.fast << " fast pixels span-filled";
  const walk_result none = walk_full(w, views, 160, 120, 2, 0.05f, true, 0, nullptr, false, 0);
  EXPECT_EQ(none.span, 0u);
  EXPECT_EQ(none.fast, a.fast) << "spans fill the pixels per-pixel evaluation would";
}

// While the camera moves, cells are not split below moving_min_cell_pixels, cells refused
// for an edge not below moving_failed_split_pixels, and cells under moving_defer_pixels may
// defer: fewer cells are built and more pixels are traced; a resting camera splits them as
// before. Both stay within epsilon, and with the moving floors set to the resting ones a
// moving frame is the resting frame.
TEST(Reprojection, AMovingCameraBuildsFewerEdgeCellsThanARestingOne) {
  world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff"));
  camera_view moved = w.sc.view;
  moved.from += 0.05f * glm::normalize(moved.at - moved.from), moved.at.x += 0.1f;
  const int width = 320, height = 240;
  struct run {
    std::uint64_t traced = 0;
    size_t bytes = 0;
  };
  auto second_frame = [&](bool moving, bool same_floors = false) {
    linetree_set trees(w.prim_bounds);
    reprojection_state reproj;
    workers pool(2);
    frame_params p;
    p.mode = render_mode::full, p.interp.eps = 0.05f, p.trees = &trees, p.reproj = &reproj;
    p.interp.plain_frames = false;  // the reprojection is what these test
    if (same_floors) {
      p.interp.moving_min_cell_pixels = p.interp.min_cell_pixels;
      p.interp.moving_failed_split_pixels = p.interp.failed_split_pixels;
      p.interp.moving_defer_pixels = p.interp.defer_pixels;
    }
    render_frame(pool, w, make_camera(w.sc.view, width, height), p);
    p.camera_moving = moving;
    const camera cam = make_camera(moved, width, height);
    const frame_result fr = render_frame(pool, w, cam, p);
    const verify_result vr = verify_frame(pool, w, cam, fr.img, 0.05f);
    EXPECT_EQ(vr.violations, 0u) << (moving ? "moving" : "resting") << ", max error " << vr.max_rel_err;
    return run{fr.pixels.base, trees.bytes()};
  };
  const run resting = second_frame(false), moving = second_frame(true);
  EXPECT_GT(moving.traced, resting.traced);
  EXPECT_LT(moving.bytes, resting.bytes);
  const run same = second_frame(true, true);
  EXPECT_EQ(same.traced, resting.traced);
  EXPECT_EQ(same.bytes, resting.bytes);
}

// --- reprojection through OSMesa (--reproject osmesa) -------------------------------------

bool inside_convex(const float* xy, int n, float px, float py, float slack) {
  // Counter-clockwise: inside is left of every edge (within `slack` pixels).
  for (int i = 0; i < n; ++i) {
    const float ax = xy[2 * i], ay = xy[2 * i + 1];
    const float bx = xy[2 * ((i + 1) % n)], by = xy[2 * ((i + 1) % n) + 1];
    const float ex = bx - ax, ey = by - ay, len = std::sqrt(ex * ex + ey * ey);
    if (len > 0 && (ex * (py - ay) - ey * (px - ax)) / len < -slack) return false;
  }
  return true;
}

// The regions drawn for a cell must hold every pixel centre whose eye line lies in the
// cell, also when a face crosses the eye's plane (the eye between a floor's planes) or
// lies behind the eye; checked on the art room's cells from several eyes, without OSMesa.
TEST(FaceRaster, RegionsHoldEveryPixelWhoseLineLiesInTheCell) {
  world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff"));
  linetree_set trees(w.prim_bounds);
  reprojection_state reproj;
  workers pool(2);
  frame_params p;
  p.mode = render_mode::full, p.interp.eps = 0.05f, p.trees = &trees, p.reproj = &reproj;
  p.interp.plain_frames = false;
  const int width = 160, height = 120;
  render_frame(pool, w, make_camera(w.sc.view, width, height), p);
  ASSERT_GT(reproj.cells.size(), 100u);
  std::vector<camera_view> eyes;
  for (int k = 0; k < 4; ++k) {
    camera_view v = w.sc.view;
    const glm::vec3 d = v.at - v.from;
    const float turn = 0.6f * float(k);  // up to 1.8 rad: cells to the side and behind
    v.at = v.from + glm::vec3(std::cos(turn) * d.x - std::sin(turn) * d.z, d.y - 0.3f * float(k),
                              std::sin(turn) * d.x + std::cos(turn) * d.z);
    eyes.push_back(v);
  }
  size_t inside = 0, missed = 0;
  for (const camera_view& v : eyes) {
    const camera cam = make_camera(v, width, height);
    for (const cell_ref& c : reproj.cells) {
      std::vector<int> counts;
      std::vector<float> xy;
      cell_regions(cam, c.lt->fp, *c.node, counts, xy);
      for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
          float x4[4];
          if (!eye_line_in_cell(cam, c, x, y, x4)) continue;
          // Pixel (x, y)'s centre in window coordinates (y up from the bottom).
          const float px = float(x) + 0.5f, py = float(height - 1 - y) + 0.5f;
          bool in = false;
          size_t at = 0;
          for (int n : counts) {
            in = in || inside_convex(xy.data() + 2 * at, n, px, py, 1e-3f);
            at += size_t(n);
          }
          ++(in ? inside : missed);
        }
    }
  }
  EXPECT_GT(inside, 10000u);
  EXPECT_EQ(missed, 0u) << "of " << inside + missed << " pixels in a cell";
}

// Drawn by OSMesa, ownership is the exact method's (first listed trusted cell holding the
// pixel's line) but for pixels whose centres lie within rounding of a region's edge.
TEST(FaceRaster, OwnsThePixelsTheExactMethodOwns) {
  std::string why;
  std::unique_ptr<face_raster> raster = face_raster::open(why);
  if (!raster) GTEST_SKIP() << why;
  const int width = 200, height = 150;
  next_eye e(width, height);
  const camera& cam = e.cam;
  const std::vector<cell_ref>& cells = e.reproj.cells;
  const std::vector<cell_trust>& trusted = e.trusted;
  std::vector<std::int32_t> exact(size_t(width) * height), drawn(size_t(width) * height);
  splat_rows(cam, cells, trusted, e.rects, 0, height, exact.data());
  EXPECT_GT(raster->owners(cam, cells, trusted, drawn.data()), cells.size() / 2);
  size_t owned = 0, differ = 0, wrong = 0;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const size_t k = size_t(y) * width + size_t(x);
      owned += exact[k] >= 0, differ += exact[k] != drawn[k];
      float x4[4];
      if (drawn[k] >= 0) {
        ASSERT_LT(size_t(drawn[k]), cells.size());
        EXPECT_TRUE(trusted[size_t(drawn[k])].ok);
        wrong += !eye_line_in_cell(cam, cells[size_t(drawn[k])], x, y, x4);  // fill_pixel sends these on
      }
    }
  EXPECT_GT(owned, exact.size() / 2);
  // Rounding at regions' edges. A long thin cell (the predicate proves the room's cross
  // beams in cells 3 m long) draws a sliver about a pixel high, whose row
  // rounds as a whole: 31 of the 34 wrong pixels here. fill_pixel sends them on.
  EXPECT_LE(differ, exact.size() / 500) << differ << " of " << owned << " owned pixels differ";
  EXPECT_LE(wrong, exact.size() / 500) << wrong << " drawn pixels lie outside their cell";
  // A second frame through the same context, at another size.
  camera small = cam;
  small.width = 100, small.height = 75, small.step *= 2;
  std::vector<std::int32_t> again(100 * 75);
  raster->owners(small, cells, trusted, again.data());
  EXPECT_GT(std::count_if(again.begin(), again.end(), [](std::int32_t o) { return o >= 0; }), 100 * 75 / 2);
}

TEST(FaceRaster, OsmesaWalkStaysWithinEpsAndIgnoresThreadCount) {
  std::string why;
  if (!face_raster::open(why)) GTEST_SKIP() << why;
  world w = world_of(sweep_scene);
  std::vector<camera_view> views;
  for (int k = 0; k < 6; ++k) views.push_back(slid(w.sc.view, 0.12f * float(k)));
  walk_result a = walk_full(w, views, 160, 120, 1, 0.05f, true, 0, face_raster::open(why));
  EXPECT_GT(a.fast, 160u * 120u);
  for (int threads : {2, 8}) {
    walk_result b = walk_full(w, views, 160, 120, threads, 0.05f, false, 0, face_raster::open(why));
    for (size_t k = 0; k < a.frames.size(); ++k)
      EXPECT_TRUE(test::same_pixels(a.frames[k], b.frames[k])) << threads << " threads, frame " << k;
    EXPECT_EQ(a.fast, b.fast);
  }
}

// --pipeline: each next frame's reprojection prepared on a thread of its own from the
// cells of the frame before, while this one is shaded. Ownership depends on the lists and
// the eyes only: the same images for any thread count and the bound kept; with a memory
// budget (MemoryBudget) the prepared cells survive the eviction between frames.
TEST(Reprojection, PipelinedWalkStaysWithinEpsAndIgnoresThreadCount) {
  world w = world_of(sweep_scene);
  std::vector<camera_view> views;
  for (int k = 0; k < 6; ++k) views.push_back(slid(w.sc.view, 0.12f * float(k)));
  std::string why;
  for (bool osmesa : {false, true}) {
    if (osmesa && !face_raster::open(why)) continue;  // the exact method is checked regardless
    auto raster = [&] { return osmesa ? face_raster::open(why) : nullptr; };
    walk_result a = walk_full(w, views, 160, 120, 1, 0.05f, true, 0, raster(), true);
    EXPECT_EQ(a.ahead_frames, int(views.size()) - 1);
    const walk_result plain = walk_full(w, views, 160, 120, 1, 0.05f, false, 0, raster(), false);
    EXPECT_GE(a.fast, plain.fast * 99 / 100) << "prepared ahead, as many pixels reprojected";
    for (int threads : {2, 8}) {
      walk_result b = walk_full(w, views, 160, 120, threads, 0.05f, false, 0, raster(), true);
      for (size_t k = 0; k < a.frames.size(); ++k)
        EXPECT_TRUE(test::same_pixels(a.frames[k], b.frames[k])) << threads << " threads, frame " << k;
      EXPECT_EQ(a.fast, b.fast);
    }
  }
}

}  // namespace
}  // namespace epsray
