// engine/predicate/reflect_shaft: the primitives listed for a flat mirror's cell must hold
// every primitive its reflected rays can meet, so that the list gives the BVH walk's hit
// (closest_listed_hit). Lines sampled in random cells (their 16 corners included) are
// traced to the mirror and reflected as shade_hit reflects them; the BVH's answer is the
// oracle, and the radiance each ray carries must lie in the cell's range. Mirrors: the
// art room's floor, and generated scenes with a mirror on each axis, facing either way (a
// floor, a ceiling, walls), as a polygon, a disk and a box's face.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>

#include "accel/world.h"
#include "interp/line_space.h"
#include "predicate/reflect_shaft.h"
#include "scene/nff.h"
#include "shade/surface.h"
#include "shade/whitted.h"
#include "test_util.h"

namespace epsray {
namespace {

using test::uniform;

struct tally {
  int cells = 0, listed = 0, rays = 0, hits = 0;
  int narrower = 0;  // listed cells whose rays' range is narrower than any depth-2 ray's
};

// `cells` random cells of facepair `index` of primitive `prim`, each 1/2 to 1/64 of the
// root along every axis, and 48 lines in each.
void check_mirror(const world& w, int prim, int index, std::mt19937& g, int cells, tally& n) {
  const facepair fp = make_facepair(w.prim_bounds[size_t(prim)], index);
  ASSERT_EQ(fp.flat, fp.axis) << "not the mirror's own facepair";
  constexpr float inf = std::numeric_limits<float>::infinity();
  for (int c = 0; c < cells; ++c) {
    float lo[4], hi[4];
    const float frac = std::ldexp(1.0f, -1 - int(g() % 6));
    for (int i = 0; i < 4; ++i) {
      const float width = (fp.hi[i] - fp.lo[i]) * frac;
      lo[i] = uniform(g, fp.lo[i], fp.hi[i] - width), hi[i] = lo[i] + width;
    }
    ++n.cells;
    reflect_candidates list;
    if (!list_reflect_candidates(w, prim, fp, lo, hi, list)) continue;
    ++n.listed;
    for (int k = 1; k < list.count; ++k) EXPECT_LE(list.near[k - 1], list.near[k]);
    n.narrower += glm::any(glm::lessThan(list.rad_hi - list.rad_lo, w.rad.hi[2] - w.rad.lo[2]));
    for (int s = 0; s < 48; ++s) {
      float x[4];
      for (int i = 0; i < 4; ++i) x[i] = s < 16 ? ((s >> i & 1) ? hi[i] : lo[i]) : uniform(g, lo[i], hi[i]);
      const glm::vec3 o = front_point(fp, x[0], x[1]);
      const ray r = make_ray(o, glm::normalize(back_point(fp, x[2], x[3]) - o));
      float t;
      if (!hit_shape(w.shapes[size_t(prim)], w.polys, r, inf, t)) continue;
      const surface sf = surface_at(w, prim, r, t);
      const glm::vec3 nf = glm::dot(sf.ng, r.d) < 0 ? sf.ns : -sf.ns;
      const ray rr = make_ray(sf.p + w.delta * nf, reflect_dir(r.d, nf));
      ++n.rays;
      hit walked, listed;
      const bool by_bvh = closest_hit(w, rr, inf, walked);
      const bool by_list = closest_listed_hit(w, rr, list, listed);
      ASSERT_EQ(by_bvh, by_list) << "cell " << c << " line " << s;
      // What the ray carries, traced as shade_hit traces a reflected ray, lies in the range.
      trace_state st;
      const glm::vec3 L = radiance(w, rr, 2, st);
      EXPECT_TRUE(glm::all(glm::lessThanEqual(list.rad_lo, L)) && glm::all(glm::lessThanEqual(L, list.rad_hi)))
          << "cell " << c << " line " << s << ": " << L.x << " outside " << list.rad_lo.x << ".." << list.rad_hi.x;
      if (!by_bvh) continue;
      ++n.hits;
      EXPECT_TRUE(std::find(list.prims, list.prims + list.count, walked.prim) != list.prims + list.count)
          << "prim " << walked.prim << " is not listed";
      EXPECT_EQ(walked.prim, listed.prim);
      EXPECT_EQ(walked.t, listed.t);
    }
  }
}

TEST(ReflectShaft, ArtRoomFloorRaysMeetOnlyListedPrimitives) {
  const world w = make_world(load_scene(std::string(EPSRAY_SOURCE_DIR) + "/scenes/artroom.nff"));
  int floor = -1;
  for (size_t i = 0; i < w.scene_prims; ++i) {
    const material& m = w.sc.materials[size_t(w.info[i].material)];
    if (w.shapes[i].kind == shape_kind::polygon && flat_axis(w.prim_bounds[i]) == 1 && m.ks > 0) floor = int(i);
  }
  ASSERT_GE(floor, 0);
  std::mt19937 g(5);
  tally n;
  check_mirror(w, floor, 3, g, 300, n);  // facepair 3: lines running down (-y) onto the floor
  // Most cells are listed, and the checks are not vacuous.
  EXPECT_GT(n.listed, n.cells / 2);
  EXPECT_GT(n.hits, 2000);
  EXPECT_GT(n.narrower, n.listed / 4);
}

// A mirror in the plane axis = at, seen from the side `sign` (+1: the mirror faces +axis),
// amid spheres, boxes and cylinders on that side, and one opaque box standing on it.
std::string mirror_scene(std::mt19937& g, int axis, int sign, bool disk) {
  std::ostringstream s;
  s << "v\nfrom 0 0 6\nat 0 0 0\nup 0 1 0\nangle 40\nresolution 8 8\n";
  s << "l 1 2 3\nl -2 1 -1\n";
  auto point = [&](float along, float a, float b) {
    glm::vec3 p;
    p[axis] = along, p[(axis + 1) % 3] = a, p[(axis + 2) % 3] = b;
    return p;
  };
  auto put = [&](glm::vec3 p) { s << ' ' << p.x << ' ' << p.y << ' ' << p.z; };
  const float at = -2.0f * float(sign);
  s << "f 0.9 0.9 0.9 0.6 0.3 20 0 1\n";
  if (disk) {
    s << "disk";
    put(point(at, 0.3f, -0.2f));
    put(point(float(sign), 0, 0));
    s << " 3.5\n";
  } else {
    s << "p 4\n";
    for (glm::vec2 q : {glm::vec2(-4, -4), glm::vec2(4, -4), glm::vec2(4, 4), glm::vec2(-4, 4)}) {
      put(point(at, q.x, q.y));
      s << '\n';
    }
  }
  s << "f 0.7 0.5 0.3 0.8 0.2 10 0 1\nbox";
  put(point(at, -3.5f, 2.5f));
  put(point(at + 1.2f * float(sign), -2.6f, 3.4f));
  s << '\n';
  for (int k = 0; k < 14; ++k) {
    const glm::vec3 c = point(at + float(sign) * uniform(g, 0.3f, 4.0f), uniform(g, -4, 4), uniform(g, -4, 4));
    switch (k % 3) {
      case 0: s << "s"; put(c); s << ' ' << uniform(g, 0.1f, 0.7f) << '\n'; break;
      case 1: {
        const glm::vec3 e = glm::vec3(uniform(g, 0.1f, 0.8f), uniform(g, 0.1f, 0.8f), uniform(g, 0.1f, 0.8f));
        s << "box"; put(c - e); put(c + e); s << '\n';
        break;
      }
      default: {
        const glm::vec3 e = test::unit_vec(g) * uniform(g, 0.3f, 1.2f);
        s << "cc"; put(c - e); s << ' ' << uniform(g, 0.05f, 0.4f); put(c + e); s << ' ' << uniform(g, 0.05f, 0.4f) << '\n';
      }
    }
  }
  return s.str();
}

TEST(ReflectShaft, GeneratedMirrorsOnEveryAxisAndSide) {
  std::mt19937 g(11);
  tally n;
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {1, -1}) {
      for (bool disk : {false, true}) {
        const world w = test::world_from_text(mirror_scene(g, axis, sign, disk));
        // The mirror is the scene's first primitive; lines reach it running against `sign`.
        const int mirror = w.shape_of[0];
        ASSERT_EQ(flat_axis(w.prim_bounds[size_t(mirror)]), axis);
        check_mirror(w, mirror, 2 * axis + (sign > 0 ? 1 : 0), g, 60, n);
        // The box standing on the mirror: its face towards the open side (a rectangle of
        // its own, larger than the face, whose reflected rays may meet the box's neighbours).
        const int face = w.face_prims[6 * size_t(w.shape_of[1]) + 2 * size_t(axis) + (sign > 0 ? 0 : 1)];
        if (face >= 0) check_mirror(w, face, 2 * axis + (sign > 0 ? 1 : 0), g, 30, n);
      }
    }
  }
  EXPECT_GT(n.listed, n.cells / 3);
  EXPECT_GT(n.hits, 5000);
  EXPECT_GT(n.narrower, 0);
}

// A cell of a primitive that is not an axis-aligned flat mirror, or of another facepair,
// gets no list: its rays walk the BVH.
TEST(ReflectShaft, OnlyAxisAlignedFlatMirrorsInTheirOwnFacepair) {
  const world w = test::world_from_text(
      "v\nfrom 0 0 6\nat 0 0 0\nup 0 1 0\nangle 40\nresolution 8 8\nl 1 2 3\n"
      "f 0.9 0.9 0.9 0.6 0.3 20 0 1\np 4\n-4 -2 -4\n4 -2 -4\n4 -2 4\n-4 -2 4\n"
      "s 0 0 0 1\np 3\n-1 -1 -1\n1 -1 -0.5\n0 1 -1.2\n");
  const int floor = w.shape_of[0], ball = w.shape_of[1], tilted = w.shape_of[2];
  reflect_candidates list;
  const facepair down = make_facepair(w.prim_bounds[size_t(floor)], 3);
  EXPECT_TRUE(list_reflect_candidates(w, floor, down, down.lo, down.hi, list));
  const facepair across = make_facepair(w.prim_bounds[size_t(floor)], 1);
  EXPECT_FALSE(list_reflect_candidates(w, floor, across, across.lo, across.hi, list));
  const facepair round = make_facepair(w.prim_bounds[size_t(ball)], 3);
  EXPECT_FALSE(list_reflect_candidates(w, ball, round, round.lo, round.hi, list));
  const facepair slanted = make_facepair(w.prim_bounds[size_t(tilted)], 5);
  EXPECT_FALSE(list_reflect_candidates(w, tilted, slanted, slanted.lo, slanted.hi, list));
}

}  // namespace
}  // namespace epsray
