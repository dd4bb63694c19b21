// engine/predicate/shaft: the shaft of two boxes must never miss a box that some segment
// from A to B meets (sampled segments and an exact hull oracle), must cull boxes clearly
// off the hull, and the BVH walk must visit exactly the primitives a brute-force test keeps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>
#include <vector>

#include "accel/world.h"
#include "predicate/shaft.h"

namespace epsray {
namespace {

using rng = std::mt19937;

float uniform(rng& g, float lo, float hi) { return std::uniform_real_distribution<float>(lo, hi)(g); }

// A size between lo and hi, spread over the decades.
float log_uniform(rng& g, float lo, float hi) { return std::exp(uniform(g, std::log(lo), std::log(hi))); }

enum class box_shape { solid, flat, thin, point };

bounds random_box(rng& g, box_shape kind, float spread, vec3 offset, float max_size = 5) {
  vec3 c = offset + vec3(uniform(g, -spread, spread), uniform(g, -spread, spread), uniform(g, -spread, spread));
  vec3 e(log_uniform(g, 0.01f, max_size), log_uniform(g, 0.01f, max_size), log_uniform(g, 0.01f, max_size));
  int axis = int(g() % 3);
  if (kind == box_shape::flat) e[axis] = 0;
  if (kind == box_shape::thin) e = vec3(0), e[axis] = log_uniform(g, 0.01f, 5);
  if (kind == box_shape::point) e = vec3(0);
  return bounds{c - e * 0.5f, c + e * 0.5f};
}

box_shape random_shape(rng& g) {
  switch (g() % 6) {
    case 0: return box_shape::flat;
    case 1: return box_shape::thin;
    case 2: return box_shape::point;
    default: return box_shape::solid;
  }
}

// A point of b, never outside it despite rounding.
vec3 random_point(rng& g, const bounds& b) {
  vec3 p;
  for (int i = 0; i < 3; ++i) p[i] = std::clamp(b.lo[i] + uniform(g, 0, 1) * (b.hi[i] - b.lo[i]), b.lo[i], b.hi[i]);
  return p;
}

vec3 corner(const bounds& b, int k) { return vec3(k & 1 ? b.hi.x : b.lo.x, k & 2 ? b.hi.y : b.lo.y, k & 4 ? b.hi.z : b.lo.z); }

// Exact enough (double) slab test of the segment p -> q against box x, ends included.
bool segment_meets_box(vec3 p, vec3 q, const bounds& x) {
  double t0 = 0, t1 = 1;
  for (int i = 0; i < 3; ++i) {
    double o = p[i], d = double(q[i]) - double(p[i]);
    if (d == 0) {
      if (o < x.lo[i] || o > x.hi[i]) return false;
      continue;
    }
    double a = (x.lo[i] - o) / d, b = (x.hi[i] - o) / d;
    if (a > b) std::swap(a, b);
    t0 = std::max(t0, a), t1 = std::min(t1, b);
  }
  return t0 <= t1;
}

// Exact oracle: does the convex hull of A and B meet x grown by `margin` on every side?
// The hull is {l a + (1 - l) b}; per axis its slice at l spans
// [l A.lo + (1 - l) B.lo, l A.hi + (1 - l) B.hi], so the question is whether some l in
// [0, 1] makes all three slices meet x: an intersection of intervals in l.
bool hull_meets_box(const bounds& a, const bounds& b, const bounds& x, double margin) {
  double l0 = 0, l1 = 1;
  auto at_most = [&](double c, double r) {  // c * l <= r
    if (c > 0) l1 = std::min(l1, r / c);
    else if (c < 0) l0 = std::max(l0, r / c);
    else if (r < 0) l0 = 2;
  };
  for (int i = 0; i < 3; ++i) {
    double xlo = double(x.lo[i]) - margin, xhi = double(x.hi[i]) + margin;
    at_most(double(a.lo[i]) - double(b.lo[i]), xhi - double(b.lo[i]));    // lower end <= xhi
    at_most(double(b.hi[i]) - double(a.hi[i]), double(b.hi[i]) - xlo);    // upper end >= xlo
  }
  return l0 <= l1;
}

float largest_coordinate(const bounds& a, const bounds& b) {
  float m = 0;
  for (int i = 0; i < 3; ++i)
    m = std::max({m, std::fabs(a.lo[i]), std::fabs(a.hi[i]), std::fabs(b.lo[i]), std::fabs(b.hi[i])});
  return m;
}

// A test box near the hull: around a point of a segment from A to B, often with one corner
// exactly there (touching), sometimes pushed a little off.
bounds box_near_hull(rng& g, const bounds& a, const bounds& b) {
  vec3 p = random_point(g, a), q = random_point(g, b);
  if (g() % 3 == 0) p = corner(a, int(g() % 8)), q = corner(b, int(g() % 8));
  float t = uniform(g, 0, 1);
  vec3 m = p + (q - p) * t;
  float size = log_uniform(g, 0.001f, 3);
  vec3 e(size * uniform(g, 0, 1), size * uniform(g, 0, 1), size * uniform(g, 0, 1));
  if (g() % 4 == 0) e[int(g() % 3)] = 0;  // flat test boxes too
  vec3 lo = m, hi = m + e;
  switch (g() % 4) {
    case 0: break;  // corner at m
    case 1: lo = m - e, hi = m; break;
    case 2: lo = m - e * 0.5f, hi = m + e * 0.5f; break;
    default: {
      vec3 shift(uniform(g, -1, 1), uniform(g, -1, 1), uniform(g, -1, 1));
      lo += shift * size * 0.5f, hi += shift * size * 0.5f;
    }
  }
  return bounds{lo, hi};
}

struct pair_case {
  bounds a, b;
};

pair_case random_pair(rng& g) {
  // Mostly near the origin; sometimes far from it, where the relative slack matters.
  vec3 offset(0);
  if (g() % 5 == 0) offset = vec3(uniform(g, -2000, 2000), uniform(g, -2000, 2000), uniform(g, -2000, 2000));
  float spread = log_uniform(g, 0.5f, 30);
  return {random_box(g, random_shape(g), spread, offset), random_box(g, random_shape(g), spread, offset)};
}

TEST(shaft, planes_hold_both_boxes) {
  rng g(1);
  for (int trial = 0; trial < 20000; ++trial) {
    pair_case c = random_pair(g);
    shaft s = make_shaft(c.a, c.b);
    ASSERT_LE(s.planes, shaft_max_planes);
    for (int k = 0; k < 8; ++k) {
      for (vec3 p : {corner(c.a, k), corner(c.b, k)}) {
        ASSERT_TRUE(shaft_may_overlap(s, bounds{p, p})) << "trial " << trial << " corner " << k;
        for (int j = 0; j < s.planes; ++j)
          ASSERT_LE(double(s.nx[j]) * p.x + double(s.ny[j]) * p.y + double(s.nz[j]) * p.z, double(s.d[j]));
      }
    }
    ASSERT_TRUE(shaft_may_overlap(s, c.a));
    ASSERT_TRUE(shaft_may_overlap(s, c.b));
  }
}

// (a) Sampled segments from A to B: any test box a segment meets must be kept.
TEST(shaft, never_misses_a_sampled_segment) {
  rng g(2);
  long hits = 0, culled = 0, tested = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    pair_case c = random_pair(g);
    shaft s = make_shaft(c.a, c.b);
    std::vector<std::pair<vec3, vec3>> segs;
    for (int i = 0; i < 64; ++i) segs.push_back({corner(c.a, i & 7), corner(c.b, i >> 3)});
    for (int i = 0; i < 400; ++i) segs.push_back({random_point(g, c.a), random_point(g, c.b)});
    for (int k = 0; k < 40; ++k) {
      bounds x = box_near_hull(g, c.a, c.b);
      bool kept = shaft_may_overlap(s, x);
      ++tested, culled += !kept;
      for (const auto& [p, q] : segs) {
        if (!segment_meets_box(p, q, x)) continue;
        ++hits;
        ASSERT_TRUE(kept) << "trial " << trial << " box " << k << ": segment (" << p.x << "," << p.y << ","
                          << p.z << ") -> (" << q.x << "," << q.y << "," << q.z << ") meets a culled box";
        break;
      }
    }
  }
  // The sampling has teeth: many boxes are met, and many near ones are culled.
  EXPECT_GT(hits, tested / 4);
  EXPECT_GT(culled, tested / 20);
}

// The same, against the exact hull: no false negatives, and (the shaft being the hull, not
// just the union box) no box more than a small slack away from the hull is kept.
TEST(shaft, equals_the_hull_up_to_the_slack) {
  rng g(3);
  long met = 0, kept_off = 0, culled = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    pair_case c = random_pair(g);
    shaft s = make_shaft(c.a, c.b);
    double slack = 1e-4 * double(largest_coordinate(c.a, c.b)) + 1e-6;
    for (int k = 0; k < 20; ++k) {
      bounds x = k % 2 ? box_near_hull(g, c.a, c.b)
                       : random_box(g, random_shape(g), 1.5f * (std::fabs(c.a.lo.x - c.b.hi.x) + 1), c.a.centre());
      bool kept = shaft_may_overlap(s, x);
      if (hull_meets_box(c.a, c.b, x, 0)) {
        ++met;
        ASSERT_TRUE(kept) << "trial " << trial << " box " << k;
      } else if (!hull_meets_box(c.a, c.b, x, slack)) {
        kept_off += kept, culled += !kept;
        EXPECT_FALSE(kept) << "trial " << trial << " box " << k << " is off the hull";
      }
    }
  }
  EXPECT_GT(met, 50000);
  EXPECT_GT(culled, 50000);
  EXPECT_EQ(kept_off, 0);
}

// (b) Boxes clearly off the hull are culled, including ones inside the union box that only
// the planes can cull.
TEST(shaft, culls_boxes_beside_the_hull) {
  // Two small boxes on a line along x: a box beside the line is outside the union box.
  bounds a{vec3(0), vec3(1)}, b{vec3(10, 0, 0), vec3(11, 1, 1)};
  shaft s = make_shaft(a, b);
  EXPECT_FALSE(shaft_may_overlap(s, bounds{vec3(5, 2, 0), vec3(6, 3, 1)}));
  EXPECT_FALSE(shaft_may_overlap(s, bounds{vec3(5, 0, 1.01f), vec3(6, 1, 2)}));
  EXPECT_TRUE(shaft_may_overlap(s, bounds{vec3(5, 0.9f, 0.9f), vec3(6, 3, 3)}));

  // A cube and a point light: the hull narrows towards the point; a box in the corner of
  // the union box, off the cone, is culled by a plane alone.
  bounds cube{vec3(0), vec3(1)}, light{vec3(10, 0.5f, 0.5f), vec3(10, 0.5f, 0.5f)};
  shaft c = make_shaft(cube, light);
  EXPECT_EQ(c.planes, 4);
  bounds corner_box{vec3(8, 0.9f, 0.9f), vec3(9, 1, 1)};
  EXPECT_TRUE(shaft_may_overlap(make_shaft(bounds{vec3(0), vec3(10, 1, 1)}, bounds{}), corner_box));
  EXPECT_FALSE(shaft_may_overlap(c, corner_box));
  EXPECT_TRUE(shaft_may_overlap(c, bounds{vec3(9.5f, 0.5f, 0.5f), vec3(9.6f, 0.6f, 0.6f)}));

  // Two boxes on a diagonal: a box in the empty corner of the union box is culled.
  bounds d0{vec3(0), vec3(1)}, d1{vec3(10, 10, 0), vec3(11, 11, 1)};
  shaft d = make_shaft(d0, d1);
  EXPECT_EQ(d.planes, 2);
  EXPECT_FALSE(shaft_may_overlap(d, bounds{vec3(8, 0, 0), vec3(9, 1, 1)}));
  EXPECT_FALSE(shaft_may_overlap(d, bounds{vec3(0, 8, 0), vec3(1, 9, 1)}));
  EXPECT_TRUE(shaft_may_overlap(d, bounds{vec3(5, 5, 0.5f), vec3(5.1f, 5.1f, 0.6f)}));
  // Just off the band's edge (the line y = x - 1 through (1, 0) and (11, 10)) by 1e-3.
  EXPECT_FALSE(shaft_may_overlap(d, bounds{vec3(6.002f, 4.999f, 0), vec3(7, 5, 1)}));
  EXPECT_TRUE(shaft_may_overlap(d, bounds{vec3(5.999f, 4.999f, 0), vec3(7, 5, 1)}));
}

TEST(shaft, degenerate_pairs) {
  // A flat patch and a point light.
  bounds patch{vec3(0, 0, 0), vec3(1, 1, 0)}, light{vec3(0.5f, 0.5f, 4), vec3(0.5f, 0.5f, 4)};
  shaft s = make_shaft(patch, light);
  EXPECT_TRUE(shaft_may_overlap(s, bounds{vec3(0.4f, 0.4f, 2), vec3(0.6f, 0.6f, 2.1f)}));
  EXPECT_FALSE(shaft_may_overlap(s, bounds{vec3(0.9f, 0.9f, 3), vec3(1, 1, 3.5f)}));
  // The same box twice, and a box with a point inside it: just the (slightly grown) box.
  shaft same = make_shaft(patch, patch);
  EXPECT_EQ(same.planes, 0);
  EXPECT_TRUE(shaft_may_overlap(same, bounds{vec3(1, 1, 0), vec3(2, 2, 2)}));
  EXPECT_FALSE(shaft_may_overlap(same, bounds{vec3(0, 0, 0.01f), vec3(2, 2, 2)}));
  bounds cube{vec3(0), vec3(2)}, inside{vec3(1), vec3(1)};
  EXPECT_EQ(make_shaft(cube, inside).planes, 0);
  // Two points: a segment.
  bounds p{vec3(0), vec3(0)}, q{vec3(4, 4, 0), vec3(4, 4, 0)};
  shaft seg = make_shaft(p, q);
  EXPECT_TRUE(shaft_may_overlap(seg, bounds{vec3(2, 2, 0), vec3(2, 2, 0)}));
  EXPECT_FALSE(shaft_may_overlap(seg, bounds{vec3(3, 0, 0), vec3(4, 1, 0)}));
  // An empty box contributes nothing; two empty boxes cull everything finite.
  shaft one = make_shaft(bounds{}, cube);
  EXPECT_EQ(one.planes, 0);
  EXPECT_TRUE(shaft_may_overlap(one, bounds{vec3(1), vec3(3)}));
  EXPECT_FALSE(shaft_may_overlap(make_shaft(bounds{}, bounds{}), cube));
  // A NaN box is never culled.
  float nan = std::nanf("");
  EXPECT_TRUE(shaft_may_overlap(s, bounds{vec3(nan), vec3(nan)}));
}

// A soup of spheres, built the way the tracer builds its world.
world sphere_soup(rng& g, int n, float extent, float rmin, float rmax, bool clustered = false) {
  scene sc;
  sc.materials.push_back(material{});
  for (int i = 0; i < n; ++i) {
    primitive p;
    p.kind = prim_kind::sphere;
    p.material = 0;
    p.a = clustered && i % 3 == 0 ? vec3(extent * 0.5f)  // many coincident centres
                                  : vec3(uniform(g, 0, extent), uniform(g, 0, extent), uniform(g, 0, extent));
    p.r0 = uniform(g, rmin, rmax);
    sc.prims.push_back(p);
  }
  return make_world(std::move(sc));
}

std::set<int> brute_force(const world& w, const shaft& s) {
  std::set<int> ids;
  for (size_t i = 0; i < w.prim_bounds.size(); ++i)
    if (shaft_may_overlap(s, w.prim_bounds[i])) ids.insert(int(i));
  return ids;
}

// (c) The BVH walk visits exactly the primitives whose boxes the shaft keeps, each once.
TEST(shaft, traversal_equals_brute_force) {
  rng g(4);
  long total = 0;
  for (int soup = 0; soup < 8; ++soup) {
    int n = soup < 4 ? 2000 : soup < 7 ? 10000 : 1;
    world w = sphere_soup(g, n, 100, 0.05f, soup % 2 ? 3.0f : 0.8f, soup == 3);
    ASSERT_EQ(w.prim_bounds.size(), size_t(n));
    for (int q = 0; q < 150; ++q) {
      bounds a = random_box(g, random_shape(g), 50, vec3(50), 40);
      bounds b = random_box(g, q % 3 ? box_shape::point : random_shape(g), 50, vec3(50), 40);
      shaft s = make_shaft(a, b);
      std::vector<int> visited;
      bool stopped = for_each_in_shaft(w.tree, w.prim_bounds, s, [&](int id) {
        visited.push_back(id);
        return false;
      });
      EXPECT_FALSE(stopped);
      std::set<int> got(visited.begin(), visited.end());
      ASSERT_EQ(got.size(), visited.size()) << "a primitive was visited twice";
      ASSERT_EQ(got, brute_force(w, s)) << "soup " << soup << " query " << q;
      total += long(got.size());
    }
  }
  EXPECT_GT(total, 10000);  // the shafts do meet spheres
}

TEST(shaft, traversal_stops_early) {
  rng g(5);
  world w = sphere_soup(g, 3000, 100, 0.5f, 2);
  shaft s = make_shaft(bounds{vec3(0, 0, 0), vec3(100, 100, 0)}, bounds{vec3(50, 50, 100), vec3(50, 50, 100)});
  size_t all = brute_force(w, s).size();
  ASSERT_GT(all, 10u);
  int calls = 0;
  EXPECT_TRUE(for_each_in_shaft(w.tree, w.prim_bounds, s, [&](int) { return ++calls == 5; }));
  EXPECT_EQ(calls, 5);
  calls = 0;
  EXPECT_FALSE(for_each_in_shaft(world{}.tree, {}, s, [&](int) { return ++calls, true; }));
  EXPECT_EQ(calls, 0);
  // A shaft far from every sphere visits none.
  shaft far = make_shaft(bounds{vec3(500), vec3(501)}, bounds{vec3(600), vec3(600)});
  EXPECT_FALSE(for_each_in_shaft(w.tree, w.prim_bounds, far, [&](int) { return ++calls, false; }));
  EXPECT_EQ(calls, 0);
}

}  // namespace
}  // namespace epsray
